#include "rt_core/simulator.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "rt_core/plane_derivative.hpp"

namespace ambdrop {

namespace {

template <std::size_t... H>
constexpr auto MakeKernelTable(std::index_sequence<H...>) {
  return std::array<Simulator::DerivativeKernel, sizeof...(H)>{
      &detail::PlaneDerivative<static_cast<int>(H) + 1>...};
}

// One compiled kernel per plane size 1..kMaxPlaneModes.
constexpr auto kKernels = MakeKernelTable(std::make_index_sequence<kMaxPlaneModes>{});

}  // namespace

Simulator::Simulator(const Model& model)
    : model_(model),
      derivative_(kKernels.at(static_cast<std::size_t>(model.planes.h - 1))),
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
  // equilibrium; one that starts dropped starts centred. Handed the currents of its controller's
  // moved levitated start, it starts there: the exact equilibrium the controller holds (a
  // record made before that start existed carries other currents and replays as it ran).
  const bool powered = model_.trigger_step != 0;
  if (model_.params.simulation.initial_position == InitialPosition::kEquilibrium && powered) {
    s.y.head(n) =
        HoldsLevitatedStart(model_, input) ? model_.levitated.q : PoweredEquilibrium(model_, input);
  }
  s.y(model_.spin_index()) = model_.params.simulation.spin_speed_rad_s;
  for (std::size_t i = 0; i < model_.tdbs.size(); ++i) {
    model_.tdbs[i]->InitialState(s.y.data() + model_.tdb_state_offset[i]);
  }
  s.power_on = powered;
  return s;
}

void Simulator::Derivative(const StateVector& y, const ControlInput& input, StateVector* rate,
                           std::array<TdbForce, kMaxTdbs>* tdb_out) const noexcept {
  derivative_(model_, y, input, rate, tdb_out);
}

StepStatus Simulator::Step(State* state, const ControlInput& input) noexcept {
  const double h = step_s_;
  const double half_h = 0.5 * h;
  const double sixth_h = h / 6.0;
  StateVector& y = state->y;
  // Classical RK4 with the control input held over the step. Each stage sum is one Eigen
  // expression: a single vectorised pass over the state.
  Derivative(y, input, &k1_, &scratch_tdb_);
  stage_ = y + half_h * k1_;
  Derivative(stage_, input, &k2_, &scratch_tdb_);
  stage_ = y + half_h * k2_;
  Derivative(stage_, input, &k3_, &scratch_tdb_);
  stage_ = y + h * k3_;
  Derivative(stage_, input, &k4_, &scratch_tdb_);
  y += sixth_h * (((k2_ + k3_) * 2.0 + k1_) + k4_);
  // x - x is 0 for a finite x and NaN otherwise, so the sum is 0 exactly when all are finite;
  // Eigen's vectorised sum is far cheaper than allFinite's element-by-element test.
  const bool not_finite = !((y - y).sum() == 0.0);
  ++state->step_index;
  state->power_on = input.motor_on;

  if (not_finite) {
    ++state->faults.non_finite_state;
    return StepStatus::kNonFinite;
  }
  const int n = model_.modes();
  for (std::size_t i = 0; i < model_.tdbs.size(); ++i) {
    const TdbParams& p = model_.tdbs[i]->params();
    // Two dot products, inlined: the matrix product went through Eigen's general GEMV call.
    const double x = model_.tdb_shapes[i].row(0).dot(y.head(n));
    const double yy = model_.tdb_shapes[i].row(1).dot(y.head(n));
    const double bound = model_.params.simulation.max_excursion_over_clearance * p.clearance_m;
    if (x * x + yy * yy > bound * bound) {
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
  // The TDB forces of the current state (a derivative evaluation on scratch storage; the
  // AMB drive does not change them).
  StateVector rate = StateVector::Zero(m.state_size);
  ControlInput input = state.power_on ? ControlInput::Powered() : ControlInput::PowerOff();
  Derivative(state.y, input, &rate, &out->tdb);
}

}  // namespace ambdrop
