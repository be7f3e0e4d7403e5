#include "rt_core/modal_reduction.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambdrop {
namespace {

// Below this a free-free mode is a rigid-body mode: it gets no modal damping and zero stiffness.
constexpr double kRigidBodyFrequency_rad_s = 1.0;

}  // namespace

StationShape ReducedRotor::ShapeAt(double z) const {
  int nearest = 0;
  for (int i = 1; i < static_cast<int>(node_positions_m.size()); ++i) {
    if (std::abs(node_positions_m[i] - z) < std::abs(node_positions_m[nearest] - z)) nearest = i;
  }
  const double dz = z - node_positions_m[nearest];
  const int b = 4 * nearest;
  StationShape s(2, size);
  s.row(0) = basis.row(b + 0) + dz * basis.row(b + 3);
  s.row(1) = basis.row(b + 1) - dz * basis.row(b + 2);
  return s;
}

ReducedRotor ReduceFeRotor(const FeRotor& fe, const Eigen::MatrixXd& kb, const Eigen::MatrixXd& cb,
                           int modes, double zeta) {
  const int nodes = static_cast<int>(fe.node_positions_m.size());
  if (modes < 2 || modes > kMaxModes || modes > fe.dofs() || modes % 2 != 0) {
    throw std::invalid_argument(
        "rotor.modes = " + std::to_string(modes) + ": expected an even number from 2 to " +
        std::to_string(std::min(kMaxModes, fe.dofs())) +
        " (modes come in x/y pairs; the mesh has " + std::to_string(fe.dofs()) + " DOF)");
  }
  // The shaft and discs do not couple the two bending planes, so the free-free modes are those
  // of the xz plane (x, theta_y per node) and their copies in the yz plane (y, -theta_x). Keeping
  // the planes apart lets the step work on plane blocks.
  const int h = modes / 2;
  Eigen::MatrixXd m_plane(2 * nodes, 2 * nodes), k_plane(2 * nodes, 2 * nodes);
  const auto plane_dof = [](int i) { return 4 * (i / 2) + (i % 2 == 0 ? 0 : 3); };
  for (int i = 0; i < 2 * nodes; ++i) {
    for (int j = 0; j < 2 * nodes; ++j) {
      m_plane(i, j) = fe.mass(plane_dof(i), plane_dof(j));
      k_plane(i, j) = fe.stiffness(plane_dof(i), plane_dof(j));
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k_plane, m_plane);
  if (eig.info() != Eigen::Success) throw std::runtime_error("free-free eigen analysis failed");

  ReducedRotor r;
  r.size = modes;
  r.basis = Eigen::MatrixXd::Zero(fe.dofs(), modes);
  for (int k = 0; k < h; ++k) {
    for (int node = 0; node < nodes; ++node) {
      const double w = eig.eigenvectors()(2 * node, k);
      const double slope = eig.eigenvectors()(2 * node + 1, k);
      r.basis(4 * node + 0, k) = w;  // x-plane mode k
      r.basis(4 * node + 3, k) = slope;
      r.basis(4 * node + 1, h + k) = w;  // its yz copy
      r.basis(4 * node + 2, h + k) = -slope;
    }
  }
  r.node_positions_m = fe.node_positions_m;
  r.mass_kg = fe.mass_kg;
  r.polar_inertia_kg_m2 = fe.polar_inertia_kg_m2;
  r.length_m = fe.length_m;
  r.centre_of_mass_m = fe.centre_of_mass_m;
  r.free_frequencies_rad_s.resize(modes);
  ModalMatrix k_modal = ModalMatrix::Zero(modes, modes);
  ModalMatrix c_modal = ModalMatrix::Zero(modes, modes);
  for (int i = 0; i < modes; ++i) {
    const double w = std::sqrt(std::max(eig.eigenvalues()(i % h), 0.0));
    const bool rigid = w < kRigidBodyFrequency_rad_s;
    r.free_frequencies_rad_s(i) = rigid ? 0.0 : w;
    k_modal(i, i) = rigid ? 0.0 : w * w;
    c_modal(i, i) = rigid ? 0.0 : 2.0 * zeta * w;
  }
  r.modal_stiffness = k_modal.diagonal();
  r.modal_damping = c_modal.diagonal();
  const Eigen::MatrixXd& phi = r.basis;
  r.stiffness = k_modal + phi.transpose() * kb * phi;
  r.damping = c_modal + phi.transpose() * cb * phi;
  r.gyroscopic = phi.transpose() * fe.gyroscopic * phi;
  Eigen::VectorXd e_y = Eigen::VectorXd::Zero(fe.dofs());
  for (int i = 1; i < fe.dofs(); i += 4) e_y(i) = 1.0;
  r.vertical_unit_force = phi.transpose() * (fe.mass * e_y);
  return r;
}

ReducedRotor RigidReducedRotor(const RigidRotorParams& rigid,
                               const std::vector<LinearBearingParams>& bearings) {
  ReducedRotor r;
  r.size = 4;
  r.mass_kg = rigid.mass_kg;
  r.polar_inertia_kg_m2 = rigid.polar_inertia_kg_m2;
  r.node_positions_m = {rigid.centre_of_mass_m};
  r.centre_of_mass_m = rigid.centre_of_mass_m;
  // q = (x, theta_y | y, theta_x) scaled by sqrt(mass): the xz plane first, then the yz plane.
  const double sm = 1.0 / std::sqrt(rigid.mass_kg);
  const double si = 1.0 / std::sqrt(rigid.transverse_inertia_kg_m2);
  r.basis = Eigen::MatrixXd::Zero(4, 4);
  r.basis(0, 0) = sm;
  r.basis(3, 1) = si;
  r.basis(1, 2) = sm;
  r.basis(2, 3) = si;
  r.free_frequencies_rad_s = ModalVector::Zero(4);
  Eigen::Matrix4d g = Eigen::Matrix4d::Zero();
  g(2, 3) = rigid.polar_inertia_kg_m2;
  g(3, 2) = -rigid.polar_inertia_kg_m2;
  r.gyroscopic = r.basis.transpose() * g * r.basis;
  r.vertical_unit_force = r.basis.transpose() * Eigen::Vector4d(0.0, rigid.mass_kg, 0.0, 0.0);
  r.length_m = 0.0;
  r.modal_stiffness = ModalVector::Zero(4);
  r.modal_damping = ModalVector::Zero(4);
  r.stiffness = ModalMatrix::Zero(4, 4);
  r.damping = ModalMatrix::Zero(4, 4);
  for (const auto& b : bearings) {
    const StationShape s = r.ShapeAt(b.position_m);
    const Eigen::Matrix2d k =
        Eigen::Vector2d(b.stiffness_x_N_per_m, b.stiffness_y_N_per_m).asDiagonal();
    const Eigen::Matrix2d c =
        Eigen::Vector2d(b.damping_x_N_s_per_m, b.damping_y_N_s_per_m).asDiagonal();
    r.stiffness += s.transpose() * k * s;
    r.damping += s.transpose() * c * s;
  }
  return r;
}

ReductionInputs ReductionInputsOf(const ModelParams& p) {
  // The coast-down losses act on the spin alone: a fit that varies them reuses the reduction.
  RotorParams rotor = p.rotor;
  rotor.coast_down = {};
  if (p.rotor.kind == RotorKind::kRigid) return {rotor, p.bearings, {}};
  return {rotor, p.bearings, StationPositions(p)};
}

ReducedRotor BuildReducedRotor(const ModelParams& p) {
  if (p.rotor.kind == RotorKind::kRigid) return RigidReducedRotor(p.rotor.rigid, p.bearings);
  const FeRotor fe = AssembleFeRotor(p.rotor, StationPositions(p));
  Eigen::MatrixXd kb, cb;
  LinearBearingMatrices(fe, p.bearings, &kb, &cb);
  return ReduceFeRotor(fe, kb, cb, p.rotor.modes, p.rotor.modal_damping_ratio);
}

}  // namespace ambdrop
