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
///
/// The amplifier is an analog current loop: where the driver steps the physics (`physics_step_s`
/// > 0), it advances at every physics step (Advance) on the command the controller holds, as the
/// coil current of a real machine follows its command between the controller's samples. Stepped
/// at the controller's period instead, the current would jump to where the loop ends the period
/// and hold there: about half a period early (0.1 ms at 5 kHz), and a staircase whose images
/// the coil does not carry. On the independent flexible truth rig (a 1.5 kHz loop under a 5 kHz
/// controller) that put 3 to 7 times the record's power into the levitated currents above
/// 2 kHz, and their spectrum 5.6 times its spread off (docs/fit.md).
class ReferenceController {
 public:
  /// Throws std::invalid_argument for a controller the model cannot carry. `physics_step_s`:
  /// the step the driver calls Advance at (0: none; the amplifier then steps with Update).
  ReferenceController(const Model& model, double period_s, double physics_step_s = 0.0);
  /// New control commands from one sample of the sensors; the currents too, but where the
  /// amplifier advances at the physics step (Advance sets them).
  void Update(const SensorReadings& readings, ControlInput* input) noexcept;
  /// One physics step of the amplifier loop on the held commands: the coil currents at its end,
  /// which the physics holds over the step (as at the controller period: half a step early, a
  /// few microseconds). Nothing without an amplifier advanced at the physics step.
  void Advance(ControlInput* input) noexcept;
  bool advances_amplifier() const noexcept { return continuous_; }
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
  bool continuous_ = false;
  std::array<std::array<double, 2>, kMaxAmbs> command_A_{};
  std::array<std::array<double, 2>, kMaxAmbs> feedforward_A_{};
  std::array<std::array<double, 2>, kMaxAmbs> start_A_{};
  std::array<int, kMaxAmbs> sensor_index_{};
  int ambs_ = 0;
};

}  // namespace ambdrop
