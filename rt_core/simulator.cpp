#include "rt_core/simulator.hpp"

#include <cmath>

namespace ambdrop {

Simulator::Simulator(const Model& model)
    : model_(model),
      step_s_(model.params.simulation.step_s),
      k1_(StateVector::Zero(model.state_size)),
      k2_(StateVector::Zero(model.state_size)),
      k3_(StateVector::Zero(model.state_size)),
      k4_(StateVector::Zero(model.state_size)),
      stage_(StateVector::Zero(model.state_size)) {}

State Simulator::InitialState(const ControlInput& input) const {
  const int n = model_.modes();
  State s;
  s.y = StateVector::Zero(model_.state_size);
  // A rotor that starts powered (levitated, or on linear bearings) starts at its static
  // equilibrium; one that starts dropped starts centred.
  const bool powered = model_.trigger_step != 0;
  if (model_.params.simulation.initial_position == InitialPosition::kEquilibrium && powered) {
    s.y.head(n) = PoweredEquilibrium(model_, input.current_A);
  }
  s.y(model_.spin_index()) = model_.params.simulation.spin_speed_rad_s;
  for (std::size_t i = 0; i < model_.tdbs.size(); ++i) {
    model_.tdbs[i]->InitialState(s.y.data() + model_.tdb_state_offset[i]);
  }
  s.power_on = model_.trigger_step != 0;
  return s;
}

void Simulator::Derivative(const StateVector& y, const ControlInput& input, StateVector* rate,
                           std::array<TdbForce, kMaxTdbs>* tdb_out) const noexcept {
  const Model& m = model_;
  const int n = m.modes();
  const auto q = y.head(n);
  const auto qd = y.segment(n, n);
  const double spin = y(m.spin_index());
  const double angle = y(m.spin_angle_index());

  // Generalized forces: gravity, then the powered AMBs.
  ModalVector force = m.gravity_force;
  if (input.power_on) {
    force += m.amb_bias_force;
    for (std::size_t a = 0; a < m.params.ambs.size(); ++a) {
      const AmbParams& amb = m.params.ambs[a];
      if (amb.law != AmbForceLaw::kLinearisedCurrents) continue;
      // f = ki i; the ks u part sits in stiffness_powered.
      const Eigen::Vector2d f(amb.current_gain_N_per_A * input.current_A[a][0],
                              amb.current_gain_N_per_A * input.current_A[a][1]);
      force.noalias() += m.amb_shapes[a].transpose() * f;
    }
  }

  // Touchdown bearings: journal motion at each TDB plane → contact forces and race rates.
  double torque = 0.0;
  for (std::size_t i = 0; i < m.tdbs.size(); ++i) {
    const StationShape& s = m.tdb_shapes[i];
    const Eigen::Vector2d xy = s * q;
    const Eigen::Vector2d v = s * qd;
    const JournalMotion journal{xy(0), xy(1), v(0), v(1), spin};
    TdbForce& out = (*tdb_out)[i];
    const int offset = m.tdb_state_offset[i];
    m.tdbs[i]->Evaluate(journal, y.data() + offset, rate->data() + offset, &out);
    force.noalias() += s.transpose() * Eigen::Vector2d(out.fx_N, out.fy_N);
    torque += out.torque_on_rotor_N_m;
  }

  // Spin: the motor holds the speed while powered; afterwards only friction acts (Ip W' = T).
  const double spin_rate = input.power_on ? 0.0 : torque / m.rotor.polar_inertia_kg_m2;

  // Unbalance, constant- and variable-speed terms (Jarroux 2019 Eq. (13), F_mu).
  for (std::size_t u = 0; u < m.params.unbalances.size(); ++u) {
    const UnbalanceParams& ub = m.params.unbalances[u];
    if (!ub.enabled) continue;
    const double me = ub.mass_kg * ub.eccentricity_m;
    const double phase = angle + ub.phase_rad;
    const double c = std::cos(phase);
    const double s = std::sin(phase);
    const Eigen::Vector2d f(me * (spin * spin * c + spin_rate * s),
                            me * (spin * spin * s - spin_rate * c));
    force.noalias() += m.unbalance_shapes[u].transpose() * f;
  }

  // q'' = F - C q' - K q - G (W q' + W' q)   (Jarroux 2019 Eq. (13), M = I).
  const ModalMatrix& k = input.power_on ? m.stiffness_powered : m.rotor.stiffness;
  const ModalMatrix& c = input.power_on ? m.damping_powered : m.rotor.damping;
  ModalVector gyro_arg = spin * qd;
  gyro_arg += spin_rate * q;
  auto qdd = rate->segment(n, n);
  qdd = force;
  qdd.noalias() -= c * qd;
  qdd.noalias() -= k * q;
  qdd.noalias() -= m.rotor.gyroscopic * gyro_arg;
  rate->head(n) = qd;
  (*rate)(m.spin_index()) = spin_rate;
  (*rate)(m.spin_angle_index()) = spin;
}

StepStatus Simulator::Step(State* state, const ControlInput& input) noexcept {
  const double h = step_s_;
  StateVector& y = state->y;
  // Classical RK4 with the control input held over the step.
  Derivative(y, input, &k1_, &scratch_tdb_);
  stage_ = y + (0.5 * h) * k1_;
  Derivative(stage_, input, &k2_, &scratch_tdb_);
  stage_ = y + (0.5 * h) * k2_;
  Derivative(stage_, input, &k3_, &scratch_tdb_);
  stage_ = y + h * k3_;
  Derivative(stage_, input, &k4_, &scratch_tdb_);
  stage_ = k2_ + k3_;
  stage_ *= 2.0;
  stage_ += k1_;
  stage_ += k4_;
  y += (h / 6.0) * stage_;
  ++state->step_index;
  state->power_on = input.power_on;

  if (!y.allFinite()) {
    ++state->faults.non_finite_state;
    return StepStatus::kNonFinite;
  }
  const int n = model_.modes();
  for (std::size_t i = 0; i < model_.tdbs.size(); ++i) {
    const TdbParams& p = model_.tdbs[i]->params();
    const Eigen::Vector2d xy = model_.tdb_shapes[i] * y.head(n);
    if (xy.norm() > model_.params.simulation.max_excursion_over_clearance * p.clearance_m) {
      ++state->faults.excursion_beyond_bound;
      return StepStatus::kExcursionBound;
    }
  }
  return StepStatus::kOk;
}

void Simulator::Observe(const State& state, Observation* out) const noexcept {
  const Model& m = model_;
  const int n = m.modes();
  const auto q = state.y.head(n);
  out->time_s = Time(state);
  out->spin_speed_rad_s = state.y(m.spin_index());
  out->spin_angle_rad = state.y(m.spin_angle_index());
  out->power_on = state.power_on;
  for (std::size_t i = 0; i < m.sensor_shapes.size(); ++i) {
    const Eigen::Vector2d xy = m.sensor_shapes[i] * q;
    out->sensor_xy_m[i] = {xy(0), xy(1)};
  }
  for (std::size_t i = 0; i < m.tdb_shapes.size(); ++i) {
    const Eigen::Vector2d xy = m.tdb_shapes[i] * q;
    out->tdb_journal_xy_m[i] = {xy(0), xy(1)};
  }
  // The TDB forces of the current state (a derivative evaluation on scratch storage).
  StateVector rate = StateVector::Zero(m.state_size);
  ControlInput input;
  input.power_on = state.power_on;
  Derivative(state.y, input, &rate, &out->tdb);
}

}  // namespace ambdrop
