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
  if (modes < 1 || modes > kMaxModes || modes > fe.dofs()) {
    throw std::invalid_argument("rotor.modes = " + std::to_string(modes) + ": expected 1.." +
                                std::to_string(std::min(kMaxModes, fe.dofs())) +
                                " (the mesh has " + std::to_string(fe.dofs()) + " DOF)");
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(fe.stiffness, fe.mass);
  if (eig.info() != Eigen::Success) throw std::runtime_error("free-free eigen analysis failed");

  ReducedRotor r;
  r.size = modes;
  r.basis = eig.eigenvectors().leftCols(modes);
  r.node_positions_m = fe.node_positions_m;
  r.mass_kg = fe.mass_kg;
  r.polar_inertia_kg_m2 = fe.polar_inertia_kg_m2;
  r.length_m = fe.length_m;
  r.free_frequencies_rad_s.resize(modes);
  ModalMatrix k_modal = ModalMatrix::Zero(modes, modes);
  ModalMatrix c_modal = ModalMatrix::Zero(modes, modes);
  for (int i = 0; i < modes; ++i) {
    const double w = std::sqrt(std::max(eig.eigenvalues()(i), 0.0));
    const bool rigid = w < kRigidBodyFrequency_rad_s;
    r.free_frequencies_rad_s(i) = rigid ? 0.0 : w;
    k_modal(i, i) = rigid ? 0.0 : w * w;
    c_modal(i, i) = rigid ? 0.0 : 2.0 * zeta * w;
  }
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
  // q = M^(1/2) (x, y, theta_x, theta_y): the basis is M^(-1/2).
  const Eigen::Vector4d m(rigid.mass_kg, rigid.mass_kg, rigid.transverse_inertia_kg_m2,
                          rigid.transverse_inertia_kg_m2);
  r.basis = m.cwiseSqrt().cwiseInverse().asDiagonal();
  r.free_frequencies_rad_s = ModalVector::Zero(4);
  Eigen::Matrix4d g = Eigen::Matrix4d::Zero();
  g(2, 3) = rigid.polar_inertia_kg_m2;
  g(3, 2) = -rigid.polar_inertia_kg_m2;
  r.gyroscopic = r.basis.transpose() * g * r.basis;
  r.vertical_unit_force = r.basis.transpose() * Eigen::Vector4d(0.0, rigid.mass_kg, 0.0, 0.0);
  r.stiffness = ModalMatrix::Zero(4, 4);
  r.damping = ModalMatrix::Zero(4, 4);
  for (const auto& b : bearings) {
    const StationShape s = r.ShapeAt(b.position_m);
    const Eigen::Matrix2d k = Eigen::Vector2d(b.stiffness_x_N_per_m, b.stiffness_y_N_per_m).asDiagonal();
    const Eigen::Matrix2d c = Eigen::Vector2d(b.damping_x_N_s_per_m, b.damping_y_N_s_per_m).asDiagonal();
    r.stiffness += s.transpose() * k * s;
    r.damping += s.transpose() * c * s;
  }
  return r;
}

ReducedRotor BuildReducedRotor(const ModelParams& p) {
  if (p.rotor.kind == RotorKind::kRigid) return RigidReducedRotor(p.rotor.rigid, p.bearings);
  const FeRotor fe = AssembleFeRotor(p.rotor, StationPositions(p));
  Eigen::MatrixXd kb, cb;
  LinearBearingMatrices(fe, p.bearings, &kb, &cb);
  return ReduceFeRotor(fe, kb, cb, p.rotor.modes, p.rotor.modal_damping_ratio);
}

}  // namespace ambdrop
