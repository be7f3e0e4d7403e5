#pragma once
#include <array>

#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"
#include "rt_core/state.hpp"

namespace ambdrop {

enum class [[nodiscard]] StepStatus{
    kOk,
    kNonFinite,       ///< a state became NaN or infinite
    kExcursionBound,  ///< a journal left its TDB by more than the configured bound
};

/// What the outside world sees after a step.
struct Observation {
  double time_s = 0.0;
  double spin_speed_rad_s = 0.0;
  double spin_angle_rad = 0.0;
  bool power_on = true;  ///< no full power failure (motor on)
  std::array<std::array<double, 2>, kMaxSensors> sensor_xy_m{};  ///< per sensor (x, y)
  std::array<std::array<double, 2>, kMaxTdbs> tdb_journal_xy_m{};
  std::array<TdbForce, kMaxTdbs> tdb{};
};

/// Fixed-step RK4 integrator of a Model. Step and Observe never allocate, lock or throw.
class Simulator {
 public:
  explicit Simulator(const Model& model);

  /// Initial state: the configured initial position (the powered equilibrium for the given
  /// initial currents, Model::levitated.q for the currents of a moved levitated start, or
  /// centred), the configured spin speed, TDBs at rest.
  State InitialState(const ControlInput& initial_input = {}) const;
  /// Advances one fixed step with the control input held over it.
  StepStatus Step(State* state, const ControlInput& input) noexcept;
  void Observe(const State& state, Observation* out) const noexcept;
  double Time(const State& state) const noexcept { return state.step_index * step_s_; }
  const Model& model() const noexcept { return model_; }

  /// Time derivative of y (exposed for energy and force tests).
  void Derivative(const StateVector& y, const ControlInput& input, StateVector* rate,
                  std::array<TdbForce, kMaxTdbs>* tdb_out) const noexcept;

  using DerivativeKernel = void (*)(const Model&, const StateVector&, const ControlInput&,
                                    StateVector*, std::array<TdbForce, kMaxTdbs>*) noexcept;

 private:
  const Model& model_;
  DerivativeKernel derivative_;
  double step_s_;
  StateVector k1_, k2_, k3_, k4_, stage_;
  std::array<TdbForce, kMaxTdbs> scratch_tdb_{};
};

}  // namespace ambdrop
