#include "rt_core/fe_rotor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "rt_core/timoshenko_element.hpp"

namespace ambdrop {
namespace {

constexpr double kNodeTolerance_m = 1e-9;
/// A section's subdivision node closer to a station than this share of its element gives way
/// to the station's node.
constexpr double kStationMergeFraction = 0.01;

// The yz plane's slope is dy/dz = -theta_x: its plane matrices map to (y, theta_x) through
// T = diag(1, -1, 1, -1).
const Eigen::Matrix4d& YzTransform() {
  static const Eigen::Matrix4d t = Eigen::Vector4d(1, -1, 1, -1).asDiagonal();
  return t;
}

void AddPlaneBlocks(const Eigen::Matrix4d& xz, const Eigen::Matrix4d& yz, int node,
                    Eigen::MatrixXd* global) {
  // Element DOF (w1, s1, w2, s2) → global index of node / node+1.
  const int xz_index[4] = {4 * node + 0, 4 * node + 3, 4 * node + 4, 4 * node + 7};
  const int yz_index[4] = {4 * node + 1, 4 * node + 2, 4 * node + 5, 4 * node + 6};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      (*global)(xz_index[i], xz_index[j]) += xz(i, j);
      (*global)(yz_index[i], yz_index[j]) += yz(i, j);
    }
  }
}

}  // namespace

int FeRotor::NodeAt(double z_m) const {
  for (int i = 0; i < static_cast<int>(node_positions_m.size()); ++i) {
    if (std::abs(node_positions_m[i] - z_m) <= kNodeTolerance_m) return i;
  }
  return -1;
}

std::vector<double> StationPositions(const ModelParams& p) {
  std::vector<double> z;
  for (const auto& b : p.bearings) z.push_back(b.position_m);
  for (const auto& a : p.ambs) z.push_back(a.position_m);
  for (const auto& t : p.tdbs) z.push_back(t.position_m);
  for (const auto& s : p.sensors) z.push_back(s.position_m);
  for (const auto& u : p.unbalances) z.push_back(u.position_m);
  for (const auto& d : p.rotor.discs) z.push_back(d.position_m);
  return z;
}

FeRotor AssembleFeRotor(const RotorParams& rotor, const std::vector<double>& stations) {
  if (rotor.sections.empty()) throw std::invalid_argument("flexible rotor without shaft sections");
  FeRotor fe;

  // Mesh: section boundaries, every station, and the sections' subdivisions except those
  // within a hundredth of their element of a station: the station's node takes their place.
  // Kept, a station a hair beside a subdivision node made an element of that hair's length
  // (a TDB moved 10 um off its node on a 30 mm element: stiffness ~1e9 times its
  // neighbours'), which changed the reduced model by a jump (the flexible truth rig's drop
  // residual 0.048 -> 0.082), not by the hair.
  double total = 0.0;
  for (const auto& s : rotor.sections) total += s.length_m;
  fe.length_m = total;
  std::vector<double> z{0.0};
  for (double zs : stations) {
    if (zs < -kNodeTolerance_m || zs > fe.length_m + kNodeTolerance_m) {
      throw std::invalid_argument("station at z = " + std::to_string(zs) +
                                  " m lies outside the shaft [0, " + std::to_string(fe.length_m) +
                                  "] m");
    }
    z.push_back(std::clamp(zs, 0.0, fe.length_m));
  }
  const std::size_t station_nodes = z.size();
  std::vector<double> section_end;
  double z0 = 0.0;
  for (const auto& s : rotor.sections) {
    const double h = s.length_m / s.elements;
    for (int k = 1; k <= s.elements; ++k) {
      const double zk = z0 + s.length_m * k / s.elements;
      bool taken = false;
      for (std::size_t i = 1; i < station_nodes && k < s.elements; ++i) {
        const double gap = std::abs(z[i] - zk);
        taken = taken || (gap > kNodeTolerance_m && gap < kStationMergeFraction * h);
      }
      if (!taken) z.push_back(zk);
    }
    z0 += s.length_m;
    section_end.push_back(z0);
  }
  std::sort(z.begin(), z.end());
  for (double zi : z) {
    if (fe.node_positions_m.empty() || zi - fe.node_positions_m.back() > kNodeTolerance_m) {
      fe.node_positions_m.push_back(zi);
    }
  }
  const int nodes = static_cast<int>(fe.node_positions_m.size());
  const int n = 4 * nodes;
  fe.mass = Eigen::MatrixXd::Zero(n, n);
  fe.stiffness = Eigen::MatrixXd::Zero(n, n);
  fe.gyroscopic = Eigen::MatrixXd::Zero(n, n);

  // Shaft elements.
  const Eigen::Matrix4d& t = YzTransform();
  double mass_moment_kg_m = 0.0;
  for (int e = 0; e + 1 < nodes; ++e) {
    const double za = fe.node_positions_m[e];
    const double L = fe.node_positions_m[e + 1] - za;
    const double mid = za + 0.5 * L;
    const auto section_index = static_cast<std::size_t>(
        std::lower_bound(section_end.begin(), section_end.end(), mid) - section_end.begin());
    const ShaftSection& s = rotor.sections[std::min(section_index, rotor.sections.size() - 1)];
    const PlaneElementMatrices el = ShaftPlaneElement(
        rotor.element_theory, L, s.outer_diameter_m, s.inner_diameter_m,
        s.material.youngs_modulus_Pa, s.material.shear_modulus_Pa, s.material.density_kg_m3);
    const Eigen::Matrix4d m = el.translational_mass + el.rotary_mass;
    AddPlaneBlocks(m, t * m * t, e, &fe.mass);
    AddPlaneBlocks(el.stiffness, t * el.stiffness * t, e, &fe.stiffness);
    // Gyroscopic coupling of the planes: in slope coordinates G[xz, yz] = +R_J and
    // G[yz, xz] = -R_J (spin axis (theta_y, -theta_x, 1)); then map yz through T.
    const int xz_index[4] = {4 * e + 0, 4 * e + 3, 4 * e + 4, 4 * e + 7};
    const int yz_index[4] = {4 * e + 1, 4 * e + 2, 4 * e + 5, 4 * e + 6};
    const Eigen::Matrix4d g_xz_yz = el.polar_rotary * t;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        fe.gyroscopic(xz_index[i], yz_index[j]) += g_xz_yz(i, j);
        fe.gyroscopic(yz_index[j], xz_index[i]) -= g_xz_yz(i, j);
      }
    }
    const double pi = std::numbers::pi;
    const double D = s.outer_diameter_m;
    const double d = s.inner_diameter_m;
    const double element_mass_kg = s.material.density_kg_m3 * pi / 4.0 * (D * D - d * d) * L;
    fe.mass_kg += element_mass_kg;
    mass_moment_kg_m += element_mass_kg * mid;
    fe.polar_inertia_kg_m2 +=
        s.material.density_kg_m3 * pi / 32.0 * (D * D * D * D - d * d * d * d) * L;
  }

  // Rigid discs: m on x, y; Id on the tilts; Ip couples the tilts (Id th_x'' + Ip W th_y' = M_x).
  for (const Disc& disc : rotor.discs) {
    const int node = fe.NodeAt(disc.position_m);
    const int b = 4 * node;
    fe.mass(b + 0, b + 0) += disc.mass_kg;
    fe.mass(b + 1, b + 1) += disc.mass_kg;
    fe.mass(b + 2, b + 2) += disc.transverse_inertia_kg_m2;
    fe.mass(b + 3, b + 3) += disc.transverse_inertia_kg_m2;
    fe.gyroscopic(b + 2, b + 3) += disc.polar_inertia_kg_m2;
    fe.gyroscopic(b + 3, b + 2) -= disc.polar_inertia_kg_m2;
    fe.mass_kg += disc.mass_kg;
    mass_moment_kg_m += disc.mass_kg * disc.position_m;
    fe.polar_inertia_kg_m2 += disc.polar_inertia_kg_m2;
  }
  fe.centre_of_mass_m = fe.mass_kg > 0.0 ? mass_moment_kg_m / fe.mass_kg : 0.5 * fe.length_m;
  return fe;
}

void LinearBearingMatrices(const FeRotor& fe, const std::vector<LinearBearingParams>& bearings,
                           Eigen::MatrixXd* stiffness, Eigen::MatrixXd* damping) {
  *stiffness = Eigen::MatrixXd::Zero(fe.dofs(), fe.dofs());
  *damping = Eigen::MatrixXd::Zero(fe.dofs(), fe.dofs());
  for (const auto& b : bearings) {
    const int node = fe.NodeAt(b.position_m);
    if (node < 0) throw std::invalid_argument("bearing '" + b.name + "' is not on a node");
    (*stiffness)(4 * node, 4 * node) += b.stiffness_x_N_per_m;
    (*stiffness)(4 * node + 1, 4 * node + 1) += b.stiffness_y_N_per_m;
    (*damping)(4 * node, 4 * node) += b.damping_x_N_s_per_m;
    (*damping)(4 * node + 1, 4 * node + 1) += b.damping_y_N_s_per_m;
  }
}

}  // namespace ambdrop
