#pragma once
#include <array>

#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/controller/amplifier_loop.hpp"
#include "controller_if/controller/command_delay.hpp"
#include "controller_if/controller/discrete_controller.hpp"
#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// One axis of seed 003's PID, discretised at the controller period dt:
///   e = -Gs * reading (V);  u = kp e + ki * sum(e dt) + D,
///   D = kd s / (1 + tau_d s) e  by backward Euler:  D += (kd (e - e_prev) / dt - D) dt / (tau_d +
///   dt), i = Ga u + i_ff (A).
/// The integrator stops growing while the output is limited (anti-windup).
class PidAxis {
 public:
  PidAxis() = default;
  PidAxis(const PidParams& params, double period_s, double feedforward_A, double limit_A);
  double Update(double reading_m) noexcept;
  /// Puts the axis at rest with the reading `reading_m` held and the command `current_A` (the
  /// levitated start, Model::levitated): the integral holds what the command needs beyond the
  /// feedforward and the proportional term; without integral action there is nothing to hold.
  void HoldAtRest(double reading_m, double current_A) noexcept;
  double integral_V() const noexcept { return integral_; }

 private:
  PidParams p_{};
  double dt_ = 0.0;
  double feedforward_A_ = 0.0;
  double limit_A_ = 0.0;
  double integral_ = 0.0;
  double derivative_ = 0.0;
  double previous_error_ = 0.0;
  bool primed_ = false;
};

/// The in-process controller: per AMB axis, a PidAxis ([controller.pid]) or a LinearAxis
/// ([controller.linear]) fed by the AMB's sensor plane (AmbParams::sensor), with the gravity
/// feedforward the model computed; then the computation delay and the amplifier loop, when the
/// config asks for them. Every in-process driver (sim, scenario, hil internal, the fit, the
/// stand-in controllers) builds it from the model, so all run the same controller.
class ReferenceController {
 public:
  /// Throws std::invalid_argument for a controller the model cannot carry.
  ReferenceController(const Model& model, double period_s);
  /// New control currents from one sample of the sensors.
  void Update(const SensorReadings& readings, ControlInput* input) noexcept;
  /// The currents before the first sample: the feedforward alone, or those that hold the
  /// levitated start when it moved (Model::levitated; StaticLoadInput gives the same).
  void Initial(ControlInput* input) const noexcept;

 private:
  std::array<std::array<PidAxis, 2>, kMaxAmbs> axes_{};
  std::array<std::array<LinearAxis, 2>, kMaxAmbs> linear_{};
  std::array<std::array<CommandDelay, 2>, kMaxAmbs> delay_{};
  std::array<std::array<AmplifierLoop, 2>, kMaxAmbs> amplifier_{};
  bool linear_form_ = false;
  bool delayed_ = false;
  bool amplified_ = false;
  std::array<std::array<double, 2>, kMaxAmbs> feedforward_A_{};
  std::array<std::array<double, 2>, kMaxAmbs> start_A_{};
  std::array<int, kMaxAmbs> sensor_index_{};
  int ambs_ = 0;
};

}  // namespace ambdrop
