#include "rt_core/levitated_start.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "rt_core/amb_force.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {
namespace {

// H(0) of one section as numerator / denominator, the constant coefficients of its continuous
// form (controller_if/controller/controller_discretisation.cpp), or of its z form at z = 1.
struct DcEnds {
  double numerator = 1.0;
  double denominator = 1.0;
};

DcEnds SectionDc(const ControllerSectionParams& s) {
  switch (s.kind) {
    case SectionKind::kGain:
    case SectionKind::kLeadLag:  // gain (1 + s/wz) / (1 + s/wp)
      return {s.gain, 1.0};
    case SectionKind::kPid:  // (kd + kp tau) s^2 + (kp + ki tau) s + ki over tau s^2 + s
      return s.ki_per_s != 0.0 ? DcEnds{s.ki_per_s, 0.0} : DcEnds{s.kp, 1.0};
    case SectionKind::kNotch:    // (s^2 + 2 zz w s + w^2) / (s^2 + 2 zp w s + w^2)
    case SectionKind::kLowPass:  // unit DC gain
      return {1.0, 1.0};
    case SectionKind::kSBiquad:  // coefficients of s^2, s, 1
      return {s.numerator[2], s.denominator[2]};
    case SectionKind::kZBiquad: {
      // At z = 1, zero up to the rounding of the coefficients (BiquadCoefficients::Integrates).
      const auto at_one = [](const std::array<double, 3>& c) {
        const double sum = c[0] + c[1] + c[2];
        return std::abs(sum) <= 1e-9 * (std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2])) ? 0.0
                                                                                          : sum;
      };
      return {at_one(s.numerator), at_one(s.denominator)};
    }
  }
  return {};
}

// One AMB axis's force f(i, u) along +u (N) at the commanded control current i and displacement
// u, as the step applies it (rt_core/plane_derivative.hpp, powered), with its derivatives and
// the position gain the model's powered stiffness already holds (so that only the rest is added).
struct AxisForce {
  double force_N = 0.0;
  double per_A = 0.0;           ///< df/di
  double per_m = 0.0;           ///< df/du
  double linear_N_per_m = 0.0;  ///< ks in Model::stiffness_powered
};

AxisForce ForceOf(const AmbParams& amb, double current_A, double u_m) {
  AxisForce f;
  const double i = LimitedCurrent(amb, current_A);
  const bool limited = i != current_A;
  if (amb.law == AmbForceLaw::kLinearisedCurrents) {
    // f = ki i + ks u.
    f.force_N = amb.current_gain_N_per_A * i + amb.position_gain_N_per_m * u_m;
    f.per_A = limited ? 0.0 : amb.current_gain_N_per_A;
    f.per_m = amb.position_gain_N_per_m;
    f.linear_N_per_m = amb.position_gain_N_per_m;
  } else if (amb.law == AmbForceLaw::kElectromagnet) {
    // f = k ((I0 + i)^2 / (g0 - u)^2 - (I0 - i)^2 / (g0 + u)^2)   (seed 003, Eq. (2)); the
    // derivatives of the law without the saturation cap, which a held rotor does not reach.
    const ElectromagnetParams& e = amb.electromagnet;
    const double k = ElectromagnetConstant(e);
    const double plus = e.bias_current_A + i;
    const double minus = e.bias_current_A - i;
    const double gp = e.nominal_gap_m - u_m;
    const double gm = e.nominal_gap_m + u_m;
    f.force_N = ElectromagnetForce(e, i, u_m);
    f.per_A = limited ? 0.0 : 2.0 * k * (plus / (gp * gp) + minus / (gm * gm));
    f.per_m = 2.0 * k * (plus * plus / (gp * gp * gp) + minus * minus / (gm * gm * gm));
    f.linear_N_per_m = ElectromagnetPositionGain(e);
  }
  return f;
}

}  // namespace

ControllerStaticLaw StaticLawOf(const ControllerParams& controller) {
  ControllerStaticLaw law;
  if (controller.form == ControllerForm::kPid) {
    const PidParams& pid = controller.pid;
    if (pid.ki_per_s != 0.0) {
      law.kind = ControllerStaticLaw::Kind::kHoldsReading;
    } else {
      law.kind = ControllerStaticLaw::Kind::kProportional;
      law.gain_A_per_m = pid.amplifier_gain_A_per_V * pid.kp * pid.sensor_gain_V_per_m;
    }
    return law;
  }
  const LinearControllerParams& linear = controller.linear;
  int integrators = 0;
  int blockers = 0;
  double dc_gain = 1.0;
  for (const ControllerSectionParams& s : linear.sections) {
    const DcEnds dc = SectionDc(s);
    if (dc.denominator == 0.0) {
      if (dc.numerator == 0.0) return law;  // 0/0 at DC: not derived
      ++integrators;
    } else if (dc.numerator == 0.0) {
      ++blockers;
    } else {
      dc_gain *= dc.numerator / dc.denominator;
    }
  }
  if (integrators > 0) {
    // An integrator behind or before a section that blocks DC has a finite DC gain of its own
    // (a limit): not derived.
    if (blockers == 0) law.kind = ControllerStaticLaw::Kind::kHoldsReading;
    return law;
  }
  law.kind = ControllerStaticLaw::Kind::kProportional;
  law.gain_A_per_m =
      blockers > 0 ? 0.0 : linear.amplifier_gain_A_per_V * dc_gain * linear.sensor_gain_V_per_m;
  return law;
}

LevitatedStart ComputeLevitatedStart(const Model& m) {
  LevitatedStart out;
  const ModelParams& p = m.params;
  if (p.controller.kind != ControllerKind::kInternalPid ||
      p.simulation.initial_position != InitialPosition::kEquilibrium || m.trigger_step == 0) {
    return out;
  }
  const ControllerStaticLaw law = StaticLawOf(p.controller);
  if (law.kind == ControllerStaticLaw::Kind::kUnknown) return out;
  const bool holds = law.kind == ControllerStaticLaw::Kind::kHoldsReading;
  const bool feedforward = p.controller.form == ControllerForm::kLinear
                               ? p.controller.linear.gravity_feedforward
                               : p.controller.pid.gravity_feedforward;

  // Each AMB's sensor (as ReferenceController finds it), and whether anything moves the start
  // off the reference: an offset the controller sees, or a static load its feedforward leaves
  // to it.
  const int ambs = static_cast<int>(p.ambs.size());
  std::vector<int> sensor(ambs, -1);
  bool offset = false;
  bool load_left = false;
  for (int a = 0; a < ambs; ++a) {
    const AmbParams& amb = p.ambs[a];
    if (amb.law == AmbForceLaw::kEquivalent) return out;  // the controller refuses it
    const std::string& name = amb.sensor.empty() ? amb.name : amb.sensor;
    for (std::size_t s = 0; s < p.sensors.size(); ++s) {
      if (p.sensors[s].name == name) sensor[a] = static_cast<int>(s);
    }
    if (sensor[a] < 0) return out;
    for (int axis = 0; axis < 2; ++axis) {
      if (p.sensors[sensor[a]].AxisOffset_m(axis) != 0.0) offset = true;
      if (!feedforward && m.amb_bias_force_N[a][axis] != 0.0) load_left = true;
    }
  }
  if (!offset && !load_left) return out;

  // The reference start: the static-load currents at the centre and their equilibrium.
  ControlInput reference;
  for (int a = 0; a < ambs; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      reference.amb[a].current_A[axis] =
          CurrentForStaticForce(p.ambs[a], m.amb_bias_force_N[a][axis]);
    }
  }
  const int n = m.modes();
  const ModalVector q_reference = PoweredEquilibrium(m, reference);

  // Newton on x = (q, i) for E(x) = 0: the force balance (n rows), then one controller row per
  // AMB axis (k = 2 a + axis).
  const int size = n + 2 * ambs;
  Eigen::VectorXd x(size);
  x.head(n) = q_reference;
  std::vector<std::array<double, 2>> feedforward_A(ambs), reference_reading_m(ambs);
  for (int a = 0; a < ambs; ++a) {
    const SensorParams& s = p.sensors[sensor[a]];
    for (int axis = 0; axis < 2; ++axis) {
      x(n + 2 * a + axis) = reference.amb[a].current_A[axis];
      feedforward_A[a][axis] = feedforward ? reference.amb[a].current_A[axis] : 0.0;
      reference_reading_m[a][axis] =
          s.AxisGain(axis) * m.sensor_shapes[sensor[a]].row(axis).dot(q_reference);
    }
  }
  const Eigen::MatrixXd stiffness = m.stiffness_powered;
  const Eigen::VectorXd static_force = m.gravity_force + m.amb_bias_force;
  const double force_scale = std::max(1.0, static_force.cwiseAbs().maxCoeff());
  Eigen::VectorXd e(size);
  Eigen::MatrixXd jacobian(size, size);
  const auto evaluate = [&] {
    const auto q = x.head(n);
    e.head(n) = static_force - stiffness * q;
    jacobian.setZero();
    jacobian.topLeftCorner(n, n) = -stiffness;
    for (int a = 0; a < ambs; ++a) {
      const SensorParams& s = p.sensors[sensor[a]];
      for (int axis = 0; axis < 2; ++axis) {
        const int k = n + 2 * a + axis;
        const Eigen::RowVectorXd at_amb = m.amb_shapes[a].row(axis);
        const AxisForce f = ForceOf(p.ambs[a], x(k), at_amb.dot(q));
        // The powered stiffness holds -ks S^T S; the rest of the law is added here.
        e.head(n) += (f.force_N - f.linear_N_per_m * at_amb.dot(q)) * at_amb.transpose();
        jacobian.topLeftCorner(n, n) += (f.per_m - f.linear_N_per_m) * at_amb.transpose() * at_amb;
        jacobian.col(k).head(n) += f.per_A * at_amb.transpose();
        const Eigen::RowVectorXd at_sensor =
            s.AxisGain(axis) * m.sensor_shapes[sensor[a]].row(axis);
        const double reading_shift =
            at_sensor.dot(q) + s.AxisOffset_m(axis) - reference_reading_m[a][axis];
        if (holds) {
          e(k) = reading_shift;
          jacobian.row(k).head(n) = at_sensor;
        } else {
          e(k) = x(k) - feedforward_A[a][axis] + law.gain_A_per_m * reading_shift;
          jacobian.row(k).head(n) = law.gain_A_per_m * at_sensor;
          jacobian(k, k) = 1.0;
        }
      }
    }
  };
  bool converged = false;
  for (int iteration = 0; iteration < 50 && !converged; ++iteration) {
    evaluate();
    const Eigen::VectorXd step = jacobian.completeOrthogonalDecomposition().solve(-e);
    if (!step.allFinite()) return out;
    x += step;
    converged = step.norm() <= 1e-13 * (1.0 + x.norm());
  }
  evaluate();
  double worst_reading = 0.0;
  for (int k = n; k < size; ++k) worst_reading = std::max(worst_reading, std::abs(e(k)));
  if (!converged || !x.allFinite() || e.head(n).cwiseAbs().maxCoeff() > 1e-9 * force_scale ||
      worst_reading > 1e-12) {
    return out;
  }
  // A held rotor floats inside its TDBs.
  for (std::size_t t = 0; t < m.tdb_shapes.size(); ++t) {
    const Eigen::Vector2d journal = m.tdb_shapes[t] * x.head(n);
    if (!(journal.norm() < p.tdbs[t].clearance_m)) return out;
  }

  out.moved = true;
  out.q = x.head(n);
  out.current_A.assign(ambs, {0.0, 0.0});
  out.reading_shift_m.assign(ambs, {0.0, 0.0});
  for (int a = 0; a < ambs; ++a) {
    const SensorParams& s = p.sensors[sensor[a]];
    for (int axis = 0; axis < 2; ++axis) {
      out.current_A[a][axis] = x(n + 2 * a + axis);
      out.reading_shift_m[a][axis] =
          holds ? 0.0
                : s.AxisGain(axis) * m.sensor_shapes[sensor[a]].row(axis).dot(x.head(n)) +
                      s.AxisOffset_m(axis) - reference_reading_m[a][axis];
    }
  }
  return out;
}

}  // namespace ambdrop
