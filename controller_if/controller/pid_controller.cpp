#include "controller_if/controller/pid_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rt_core/amb_force.hpp"

namespace ambdrop {

PidAxis::PidAxis(const PidParams& params, double period_s, double feedforward_A, double limit_A)
    : p_(params), dt_(period_s), feedforward_A_(feedforward_A), limit_A_(limit_A) {}

double PidAxis::Update(double reading_m) noexcept {
  const double e = -p_.sensor_gain_V_per_m * reading_m;
  if (!primed_) {
    previous_error_ = e;
    primed_ = true;
  }
  derivative_ +=
      (p_.kd_s * (e - previous_error_) / dt_ - derivative_) * dt_ / (p_.derivative_filter_s + dt_);
  previous_error_ = e;
  const double candidate = integral_ + p_.ki_per_s * e * dt_;
  const double unlimited =
      p_.amplifier_gain_A_per_V * (p_.kp * e + candidate + derivative_) + feedforward_A_;
  // Anti-windup: keep the integral only while the amplifier is not saturated.
  if (std::abs(unlimited) <= limit_A_) integral_ = candidate;
  const double current =
      p_.amplifier_gain_A_per_V * (p_.kp * e + integral_ + derivative_) + feedforward_A_;
  return std::clamp(current, -limit_A_, limit_A_);
}

void PidAxis::HoldAtRest(double reading_m, double current_A) noexcept {
  const double e = -p_.sensor_gain_V_per_m * reading_m;
  integral_ = p_.ki_per_s != 0.0
                  ? (current_A - feedforward_A_) / p_.amplifier_gain_A_per_V - p_.kp * e
                  : 0.0;
  derivative_ = 0.0;  // of a constant reading; the first sample primes the error as always
}

ReferenceController::ReferenceController(const Model& model, double period_s, double physics_step_s)
    : linear_form_(model.params.controller.form == ControllerForm::kLinear),
      delayed_(model.params.controller.delay_samples > 0),
      amplified_(model.params.controller.amplifier.enabled),
      continuous_(amplified_ && physics_step_s > 0.0),
      ambs_(static_cast<int>(model.params.ambs.size())) {
  const ControllerParams& controller = model.params.controller;
  const PidParams& pid = controller.pid;
  const bool feedforward =
      linear_form_ ? controller.linear.gravity_feedforward : pid.gravity_feedforward;
  // A run starts where this controller holds the rotor (Model::levitated): moved there, the
  // controller starts at rest on the currents that hold it, its integrators full.
  const LevitatedStart& levitated = model.levitated;
  for (int a = 0; a < ambs_; ++a) {
    const AmbParams& amb = model.params.ambs[a];
    if (amb.law == AmbForceLaw::kEquivalent) {
      throw std::invalid_argument("amb '" + amb.name +
                                  "': the reference controller drives currents; the equivalent "
                                  "law has none (use linearised_currents or electromagnet)");
    }
    const std::string sensor = amb.sensor.empty() ? amb.name : amb.sensor;
    sensor_index_[a] = -1;
    for (std::size_t s = 0; s < model.params.sensors.size(); ++s) {
      if (model.params.sensors[s].name == sensor) sensor_index_[a] = static_cast<int>(s);
    }
    if (sensor_index_[a] < 0) {
      throw std::invalid_argument("amb '" + amb.name + "': no sensor named '" + sensor + "'");
    }
    const double limit = LimitedCurrent(amb, std::numeric_limits<double>::infinity());
    for (int axis = 0; axis < 2; ++axis) {
      feedforward_A_[a][axis] =
          feedforward ? CurrentForStaticForce(amb, model.amb_bias_force_N[a][axis]) : 0.0;
      const double feedforward_A = feedforward_A_[a][axis];
      const double start_A = levitated.moved ? levitated.current_A[a][axis] : feedforward_A;
      if (linear_form_) {
        linear_[a][axis] = LinearAxis(controller.linear, period_s, feedforward_A, limit);
        if (levitated.moved) {
          linear_[a][axis].HoldAtRest(levitated.reading_shift_m[a][axis], start_A);
        }
      } else {
        axes_[a][axis] = PidAxis(pid, period_s, feedforward_A, limit);
        if (levitated.moved) axes_[a][axis].HoldAtRest(levitated.reading_shift_m[a][axis], start_A);
      }
      start_A_[a][axis] = start_A;
      command_A_[a][axis] = start_A;
      delay_[a][axis] = CommandDelay(controller.delay_samples, start_A);
      if (amplified_) {
        amplifier_[a][axis] =
            AmplifierLoop(controller.amplifier, continuous_ ? physics_step_s : period_s, start_A);
      }
    }
  }
}

void ReferenceController::Update(const SensorReadings& readings, ControlInput* input) noexcept {
  for (int a = 0; a < ambs_; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const double reading = readings.reading_m[sensor_index_[a]][axis];
      double current =
          linear_form_ ? linear_[a][axis].Update(reading) : axes_[a][axis].Update(reading);
      if (delayed_) current = delay_[a][axis].Push(current);
      command_A_[a][axis] = current;
      if (continuous_) continue;
      if (amplified_) current = amplifier_[a][axis].Update(current);
      input->amb[a].current_A[axis] = current;
    }
  }
}

void ReferenceController::Advance(ControlInput* input) noexcept {
  if (!continuous_) return;
  for (int a = 0; a < ambs_; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      input->amb[a].current_A[axis] = amplifier_[a][axis].Update(command_A_[a][axis]);
    }
  }
}

void ReferenceController::Initial(ControlInput* input) const noexcept {
  for (int a = 0; a < ambs_; ++a) input->amb[a].current_A = start_A_[a];
}

}  // namespace ambdrop
