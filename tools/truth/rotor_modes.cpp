#include "rotor_modes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

namespace ambdrop_truth {

namespace {

constexpr double kPi = std::numbers::pi;

struct Element {
  double z0_m = 0.0, length_m = 0.0;
  double area_m2 = 0.0, second_moment_m4 = 0.0;
};

struct Mesh {
  std::vector<double> nodes_m;
  std::vector<Element> elements;
};

/// The shaft's elements, split again at every station inside it.
Mesh MeshShaft(const FlexibleShaftRig& shaft, std::vector<double> stations_m) {
  Mesh mesh;
  double z = shaft.start_m;
  mesh.nodes_m.push_back(z);
  std::sort(stations_m.begin(), stations_m.end());
  for (const ShaftSegmentRig& s : shaft.segments) {
    const double ro = 0.5 * s.outer_diameter_m, ri = 0.5 * s.inner_diameter_m;
    const double area = kPi * (ro * ro - ri * ri);
    const double second = kPi / 4.0 * (std::pow(ro, 4) - std::pow(ri, 4));
    std::vector<double> cuts;
    for (int e = 1; e <= s.elements; ++e) cuts.push_back(z + s.length_m * e / s.elements);
    for (double st : stations_m) {
      if (st > z + 1e-9 && st < z + s.length_m - 1e-9) cuts.push_back(st);
    }
    std::sort(cuts.begin(), cuts.end());
    for (double c : cuts) {
      if (c - mesh.nodes_m.back() < 1e-9) continue;
      mesh.elements.push_back({mesh.nodes_m.back(), c - mesh.nodes_m.back(), area, second});
      mesh.nodes_m.push_back(c);
    }
    z += s.length_m;
  }
  for (double st : stations_m) {
    if (st < shaft.start_m - 1e-9 || st > z + 1e-9) {
      throw std::runtime_error("station " + std::to_string(st) + " m is off the shaft (" +
                               std::to_string(shaft.start_m) + " to " + std::to_string(z) + " m)");
    }
  }
  return mesh;
}

int NodeAt(const Mesh& mesh, double z_m) {
  for (std::size_t i = 0; i < mesh.nodes_m.size(); ++i) {
    if (std::abs(mesh.nodes_m[i] - z_m) < 1e-9) return static_cast<int>(i);
  }
  throw std::runtime_error("disc at " + std::to_string(z_m) + " m is not on the shaft");
}

struct Assembled {
  Eigen::MatrixXd mass, stiffness, gyroscopic;
};

/// Friswell et al. 2010 Eqs. (5.59), (5.61), (5.62) per plane; G = 2 x rotary inertia.
Assembled Assemble(const FlexibleShaftRig& shaft, const Mesh& mesh) {
  const int dofs = 2 * static_cast<int>(mesh.nodes_m.size());
  Assembled a{Eigen::MatrixXd::Zero(dofs, dofs), Eigen::MatrixXd::Zero(dofs, dofs),
              Eigen::MatrixXd::Zero(dofs, dofs)};
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const Element& el = mesh.elements[e];
    const double L = el.length_m;
    Eigen::Matrix4d k;
    k << 12, 6 * L, -12, 6 * L, 6 * L, 4 * L * L, -6 * L, 2 * L * L, -12, -6 * L, 12, -6 * L, 6 * L,
        2 * L * L, -6 * L, 4 * L * L;
    k *= shaft.youngs_modulus_Pa * el.second_moment_m4 / (L * L * L);
    Eigen::Matrix4d mt;
    mt << 156, 22 * L, 54, -13 * L, 22 * L, 4 * L * L, 13 * L, -3 * L * L, 54, 13 * L, 156, -22 * L,
        -13 * L, -3 * L * L, -22 * L, 4 * L * L;
    mt *= shaft.density_kg_m3 * el.area_m2 * L / 420.0;
    Eigen::Matrix4d mr;
    mr << 36, 3 * L, -36, 3 * L, 3 * L, 4 * L * L, -3 * L, -L * L, -36, -3 * L, 36, -3 * L, 3 * L,
        -L * L, -3 * L, 4 * L * L;
    mr *= shaft.density_kg_m3 * el.second_moment_m4 / (30.0 * L);
    const int o = 2 * static_cast<int>(e);
    a.stiffness.block<4, 4>(o, o) += k;
    a.mass.block<4, 4>(o, o) += mt + mr;
    a.gyroscopic.block<4, 4>(o, o) += 2.0 * mr;
  }
  for (const DiscRig& d : shaft.discs) {
    const int i = NodeAt(mesh, d.position_m);
    a.mass(2 * i, 2 * i) += d.mass_kg;
    a.mass(2 * i + 1, 2 * i + 1) += d.transverse_inertia_kg_m2;
    a.gyroscopic(2 * i + 1, 2 * i + 1) += d.polar_inertia_kg_m2;
  }
  return a;
}

/// Rigid-body vectors: translation (w = 1, w' = 0) and rotation about station zc (w = z - zc,
/// w' = 1).
Eigen::VectorXd Translation(const Mesh& mesh) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * static_cast<int>(mesh.nodes_m.size()));
  for (std::size_t i = 0; i < mesh.nodes_m.size(); ++i) r(2 * static_cast<int>(i)) = 1.0;
  return r;
}
Eigen::VectorXd Rotation(const Mesh& mesh, double zc) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * static_cast<int>(mesh.nodes_m.size()));
  for (std::size_t i = 0; i < mesh.nodes_m.size(); ++i) {
    r(2 * static_cast<int>(i)) = mesh.nodes_m[i] - zc;
    r(2 * static_cast<int>(i) + 1) = 1.0;
  }
  return r;
}

void CheckShaft(const FlexibleShaftRig& shaft) {
  if (shaft.segments.empty()) throw std::runtime_error("rotor.shaft: no segments");
  if (!(shaft.youngs_modulus_Pa > 0.0) || !(shaft.density_kg_m3 > 0.0)) {
    throw std::runtime_error("rotor.shaft: youngs_modulus_Pa and density_kg_m3 must be positive");
  }
  for (const ShaftSegmentRig& s : shaft.segments) {
    if (!(s.length_m > 0.0) || !(s.outer_diameter_m > s.inner_diameter_m) ||
        s.inner_diameter_m < 0.0 || s.elements < 1 || s.elements > 200) {
      throw std::runtime_error(
          "rotor.shaft.segments: expected length > 0, outer > inner >= 0 diameters, 1..200 "
          "elements");
    }
  }
}

}  // namespace

Eigen::RowVectorXd RotorModes::AtStation(double z_m) const {
  if (shapes.size() == 0) {  // rigid
    Eigen::RowVectorXd phi(2);
    phi << 1.0, z_m - centre_of_mass_m;
    return phi;
  }
  std::size_t e = 0;
  while (e + 2 < nodes_m.size() && z_m > nodes_m[e + 1]) ++e;
  const double L = nodes_m[e + 1] - nodes_m[e];
  const double s = std::clamp((z_m - nodes_m[e]) / L, 0.0, 1.0);
  const double n1 = 1 - 3 * s * s + 2 * s * s * s, n2 = L * (s - 2 * s * s + s * s * s);
  const double n3 = 3 * s * s - 2 * s * s * s, n4 = L * (-s * s + s * s * s);
  const int o = 2 * static_cast<int>(e);
  return n1 * shapes.row(o) + n2 * shapes.row(o + 1) + n3 * shapes.row(o + 2) +
         n4 * shapes.row(o + 3);
}

RotorModes RigidRotorModes(const RotorRig& rotor) {
  RotorModes m;
  m.n = 2;
  m.centre_of_mass_m = rotor.centre_of_mass_m;
  m.mass = Eigen::Vector2d(rotor.mass_kg, rotor.transverse_inertia_kg_m2);
  m.damping = Eigen::MatrixXd::Zero(2, 2);
  m.stiffness = Eigen::MatrixXd::Zero(2, 2);
  m.gyroscopic = Eigen::Vector2d(0.0, rotor.polar_inertia_kg_m2).asDiagonal();
  m.weight_share = Eigen::Vector2d(rotor.mass_kg, 0.0);
  m.gravity_acceleration = m.weight_share.cwiseQuotient(m.mass);
  return m;
}

RotorRig ShaftInertia(const FlexibleShaftRig& shaft) {
  CheckShaft(shaft);
  std::vector<double> discs;
  for (const DiscRig& d : shaft.discs) discs.push_back(d.position_m);
  const Mesh mesh = MeshShaft(shaft, discs);
  const Assembled a = Assemble(shaft, mesh);
  const Eigen::VectorXd t = Translation(mesh);
  RotorRig r;
  r.mass_kg = t.dot(a.mass * t);
  r.centre_of_mass_m = Rotation(mesh, 0.0).dot(a.mass * t) / r.mass_kg;
  const Eigen::VectorXd rot = Rotation(mesh, r.centre_of_mass_m);
  r.transverse_inertia_kg_m2 = rot.dot(a.mass * rot);
  r.polar_inertia_kg_m2 = rot.dot(a.gyroscopic * rot);
  return r;
}

RotorModes FlexibleRotorModes(const FlexibleShaftRig& shaft, std::vector<double> stations_m) {
  CheckShaft(shaft);
  for (const DiscRig& d : shaft.discs) stations_m.push_back(d.position_m);
  const Mesh mesh = MeshShaft(shaft, stations_m);
  const Assembled a = Assemble(shaft, mesh);
  const int dofs = static_cast<int>(a.mass.rows());
  const int n = 2 + shaft.bending_modes;
  if (shaft.bending_modes < 0 || n > dofs) {
    throw std::runtime_error("rotor.shaft.bending_modes: expected 0 to " +
                             std::to_string(dofs - 2));
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(a.stiffness, a.mass);
  if (solver.info() != Eigen::Success) throw std::runtime_error("rotor.shaft: eigensolver failed");
  RotorModes m;
  m.n = n;
  m.nodes_m = mesh.nodes_m;
  m.shapes = solver.eigenvectors().leftCols(n);  // M-normalised
  m.mass = Eigen::VectorXd::Ones(n);
  m.stiffness = Eigen::MatrixXd::Zero(n, n);
  m.damping = Eigen::MatrixXd::Zero(n, n);
  for (int i = 2; i < n; ++i) {
    const double w = std::sqrt(std::max(solver.eigenvalues()(i), 0.0));
    m.stiffness(i, i) = w * w;
    m.damping(i, i) = 2.0 * shaft.modal_damping_ratio * w;
    m.bending_rad_s.push_back(w);
  }
  m.gyroscopic = m.shapes.transpose() * a.gyroscopic * m.shapes;
  m.weight_share = m.shapes.transpose() * (a.mass * Translation(mesh));
  m.gravity_acceleration = m.weight_share.cwiseQuotient(m.mass);
  const RotorRig inertia = ShaftInertia(shaft);
  m.centre_of_mass_m = inertia.centre_of_mass_m;
  return m;
}

std::vector<double> FreeFreeBendingFrequencies(const FlexibleShaftRig& shaft,
                                               std::vector<double> stations_m) {
  CheckShaft(shaft);
  for (const DiscRig& d : shaft.discs) stations_m.push_back(d.position_m);
  const Mesh mesh = MeshShaft(shaft, stations_m);
  const Assembled a = Assemble(shaft, mesh);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(a.stiffness, a.mass,
                                                                         Eigen::EigenvaluesOnly);
  std::vector<double> out;
  for (int i = 2; i < solver.eigenvalues().size(); ++i) {
    out.push_back(std::sqrt(std::max(solver.eigenvalues()(i), 0.0)));
  }
  return out;
}

}  // namespace ambdrop_truth
