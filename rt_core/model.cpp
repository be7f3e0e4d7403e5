#include "rt_core/model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rt_core/amb_force.hpp"
#include "rt_core/modal_reduction.hpp"
#include "rt_core/tdb_factory.hpp"

namespace ambdrop {
namespace {

void CheckCount(std::size_t count, int limit, const char* what) {
  if (static_cast<int>(count) > limit) {
    throw std::invalid_argument(std::string("too many ") + what + ": " + std::to_string(count) +
                                " (at most " + std::to_string(limit) + ")");
  }
}

// Vertical forces at the gravity-compensated AMBs that an integrating controller settles on:
// the static deflection at those AMBs is zero. With q = K^-1 (Fg + B f) and S_y q = 0:
// (S_y K^-1 B) f = -S_y K^-1 Fg, B = [S_y,a^T].
void GravityCompensation(Model* m) {
  const int n = m->modes();
  std::vector<int> compensated;
  for (int a = 0; a < static_cast<int>(m->params.ambs.size()); ++a) {
    const AmbParams& amb = m->params.ambs[a];
    if (amb.law != AmbForceLaw::kEquivalent || amb.gravity_compensation) compensated.push_back(a);
  }
  m->amb_bias_force = ModalVector::Zero(n);
  m->amb_bias_force_N.assign(m->params.ambs.size(), {0.0, 0.0});
  if (compensated.empty() || !m->params.gravity.enabled) return;
  const int na = static_cast<int>(compensated.size());
  Eigen::MatrixXd b(n, na);
  for (int i = 0; i < na; ++i) b.col(i) = m->amb_shapes[compensated[i]].row(1).transpose();
  const Eigen::MatrixXd k = m->stiffness_powered;
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> k_inv(k);
  const Eigen::MatrixXd kb = k_inv.solve(b);
  const Eigen::VectorXd kg = k_inv.solve(Eigen::VectorXd(m->gravity_force));
  const Eigen::MatrixXd a = b.transpose() * kb;
  const Eigen::VectorXd f = a.completeOrthogonalDecomposition().solve(-(b.transpose() * kg));
  for (int i = 0; i < na; ++i) {
    const int a = compensated[i];
    m->amb_bias_force_N[a] = {0.0, f(i)};
    // Only the equivalent law applies it by itself; the others get it through their currents.
    if (m->params.ambs[a].law == AmbForceLaw::kEquivalent) m->amb_bias_force += f(i) * b.col(i);
  }
}

PlaneVector Block(const ModalVector& v, int offset, int h) {
  return v.segment(offset, h);
}

PlaneMatrix Block(const ModalMatrix& a, int row, int col, int h) {
  return a.block(row, col, h, h);
}

void RequireZero(const ModalMatrix& a, int row, int col, int h, const char* what) {
  if (!a.block(row, col, h, h).isZero(0.0)) {
    throw std::logic_error(std::string("the two bending planes are coupled through ") + what);
  }
}

PlaneStation SplitStation(const StationShape& s, int h) {
  PlaneStation p;
  p.sx = s.row(0).segment(0, h).transpose();
  p.sy = s.row(1).segment(h, h).transpose();
  if (!s.row(0).segment(h, h).isZero(0.0) || !s.row(1).segment(0, h).isZero(0.0)) {
    throw std::logic_error("a station shape mixes the bending planes");
  }
  return p;
}

void SplitByPlane(Model* m) {
  const int h = m->modes() / 2;
  PlaneModel& p = m->planes;
  p.h = h;
  // The dense matrices must have the plane structure the kernel assumes.
  for (const ModalMatrix* a : {&m->stiffness_powered, &m->damping_powered}) {
    RequireZero(*a, 0, h, h, "stiffness or damping");
    RequireZero(*a, h, 0, h, "stiffness or damping");
  }
  RequireZero(m->rotor.gyroscopic, 0, 0, h, "a gyroscopic diagonal block");
  RequireZero(m->rotor.gyroscopic, h, h, h, "a gyroscopic diagonal block");
  p.modal_stiffness_x = Block(m->rotor.modal_stiffness, 0, h);
  p.modal_stiffness_y = Block(m->rotor.modal_stiffness, h, h);
  p.modal_damping_x = Block(m->rotor.modal_damping, 0, h);
  p.modal_damping_y = Block(m->rotor.modal_damping, h, h);
  for (const auto& b : m->params.bearings) {
    p.bearings.push_back({SplitStation(m->rotor.ShapeAt(b.position_m), h), b.stiffness_x_N_per_m,
                          b.stiffness_y_N_per_m, b.damping_x_N_s_per_m, b.damping_y_N_s_per_m});
  }
  for (std::size_t a = 0; a < m->params.ambs.size(); ++a) {
    const AmbParams& amb = m->params.ambs[a];
    const bool biased = amb.law == AmbForceLaw::kEquivalent && amb.gravity_compensation;
    p.ambs.push_back(
        {SplitStation(m->amb_shapes[a], h), amb, biased ? m->amb_bias_force_N[a][0] : 0.0,
         biased ? m->amb_bias_force_N[a][1] : 0.0, ControlCurrentLimit(amb),
         ElectromagnetConstant(amb.electromagnet), SaturatedCoilForce(amb.electromagnet)});
  }
  p.gyroscopic_xy = Block(m->rotor.gyroscopic, 0, h, h);
  p.gyroscopic_yx = Block(m->rotor.gyroscopic, h, 0, h);
  p.gravity_x = Block(m->gravity_force, 0, h);
  p.gravity_y = Block(m->gravity_force, h, h);
  for (const auto& s : m->tdb_shapes) p.tdbs.push_back(SplitStation(s, h));
  for (const auto& s : m->sensor_shapes) p.sensors.push_back(SplitStation(s, h));
  for (const auto& s : m->unbalance_shapes) p.unbalances.push_back(SplitStation(s, h));
}

// What BuildModel refuses before it builds anything.
void CheckModelParams(const ModelParams& params) {
  CheckCount(params.tdbs.size(), kMaxTdbs, "touchdown bearings");
  CheckCount(params.ambs.size(), kMaxAmbs, "AMBs");
  CheckCount(params.sensors.size(), kMaxSensors, "sensors");
  CheckCount(params.unbalances.size(), kMaxUnbalances, "unbalances");
  CheckCount(params.bearings.size(), kMaxLinearBearings, "linear bearings");
  if (!(params.simulation.step_s > 0.0))
    throw std::invalid_argument("simulation.step_s must be > 0");
  // Checked as a double before llround, which is undefined beyond int64.
  const double steps = params.simulation.duration_s / params.simulation.step_s;
  if (!(steps >= 0.0 && steps <= static_cast<double>(params.simulation.max_steps))) {
    throw std::invalid_argument(
        "simulation.duration_s / simulation.step_s = " + std::to_string(steps) +
        " steps, beyond simulation.max_steps = " + std::to_string(params.simulation.max_steps));
  }
}

// A scheduled time as a step; times after the run's end (which never come) as the step after it,
// so that no time, however large, overflows the conversion.
std::int64_t StepAt(double time_s, double dt, std::int64_t total_steps) {
  return std::llround(std::min(time_s / dt, static_cast<double>(total_steps + 1)));
}

}  // namespace

Model BuildModel(const ModelParams& params) {
  CheckModelParams(params);
  return BuildModel(params, BuildReducedRotor(params));
}

Model BuildModel(const ModelParams& params, const ReducedRotor& rotor) {
  CheckModelParams(params);
  Model m;
  m.params = params;
  m.rotor = rotor;
  const int n = m.rotor.size;
  for (const auto& a : params.ambs) m.amb_shapes.push_back(m.rotor.ShapeAt(a.position_m));
  for (const auto& t : params.tdbs) m.tdb_shapes.push_back(m.rotor.ShapeAt(t.position_m));
  for (const auto& s : params.sensors) m.sensor_shapes.push_back(m.rotor.ShapeAt(s.position_m));
  for (const auto& u : params.unbalances)
    m.unbalance_shapes.push_back(m.rotor.ShapeAt(u.position_m));

  m.state_size = 2 * n + 2;
  for (const auto& t : params.tdbs) {
    m.tdbs.push_back(MakeTouchdownBearing(t));
    CheckCount(static_cast<std::size_t>(m.tdbs.back()->StateSize()), kMaxTdbStates,
               "states in one TDB model");
    m.tdb_state_offset.push_back(m.state_size);
    m.state_size += m.tdbs.back()->StateSize();
  }

  m.gravity_force = ModalVector::Zero(n);
  if (params.gravity.enabled) {
    m.gravity_force = -params.gravity.acceleration_m_s2 * m.rotor.vertical_unit_force;
  }
  m.stiffness_powered = m.rotor.stiffness;
  m.damping_powered = m.rotor.damping;
  for (std::size_t a = 0; a < params.ambs.size(); ++a) {
    const AmbParams& amb = params.ambs[a];
    const StationShape& s = m.amb_shapes[a];
    switch (amb.law) {
      case AmbForceLaw::kEquivalent:
        m.stiffness_powered += amb.stiffness_N_per_m * s.transpose() * s;
        m.damping_powered += amb.damping_N_s_per_m * s.transpose() * s;
        break;
      case AmbForceLaw::kLinearisedCurrents:
        // f = ki i + ks u: the position term is a negative stiffness.
        m.stiffness_powered -= amb.position_gain_N_per_m * s.transpose() * s;
        break;
      case AmbForceLaw::kElectromagnet:
        m.stiffness_powered -= ElectromagnetPositionGain(amb.electromagnet) * s.transpose() * s;
        break;
    }
  }
  GravityCompensation(&m);
  SplitByPlane(&m);

  const double dt = params.simulation.step_s;
  m.total_steps = std::llround(params.simulation.duration_s / dt);
  m.trigger_step = params.trigger.enabled ? StepAt(params.trigger.time_s, dt, m.total_steps) : -1;
  m.restore_step = params.trigger.enabled && params.trigger.restore_time_s >= 0.0
                       ? StepAt(params.trigger.restore_time_s, dt, m.total_steps)
                       : -1;
  m.levitated = ComputeLevitatedStart(m);
  return m;
}

ControlInput StaticLoadInput(const Model& m) {
  ControlInput input;
  if (m.levitated.moved) {
    for (std::size_t a = 0; a < m.params.ambs.size(); ++a) {
      input.amb[a].current_A = m.levitated.current_A[a];
    }
    return input;
  }
  for (std::size_t a = 0; a < m.params.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      input.amb[a].current_A[axis] =
          CurrentForStaticForce(m.params.ambs[a], m.amb_bias_force_N[a][axis]);
    }
  }
  return input;
}

bool HoldsLevitatedStart(const Model& m, const ControlInput& input) {
  if (!m.levitated.moved) return false;
  for (std::size_t a = 0; a < m.params.ambs.size(); ++a) {
    if (input.amb[a].current_A != m.levitated.current_A[a]) return false;
  }
  return true;
}

ModalVector PoweredEquilibrium(const Model& m, const ControlInput& input) {
  const int n = m.modes();
  Eigen::VectorXd f = m.gravity_force + m.amb_bias_force;
  for (std::size_t a = 0; a < m.params.ambs.size(); ++a) {
    const AmbParams& amb = m.params.ambs[a];
    double ki = 0.0;
    if (amb.law == AmbForceLaw::kLinearisedCurrents) ki = amb.current_gain_N_per_A;
    if (amb.law == AmbForceLaw::kElectromagnet) ki = ElectromagnetCurrentGain(amb.electromagnet);
    const auto& i = input.amb[a].current_A;
    f += m.amb_shapes[a].transpose() *
         Eigen::Vector2d(ki * LimitedCurrent(amb, i[0]), ki * LimitedCurrent(amb, i[1]));
  }
  const Eigen::MatrixXd k = m.stiffness_powered;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(k);
  if (!lu.isInvertible()) return ModalVector::Zero(n);
  return lu.solve(f);
}

}  // namespace ambdrop
