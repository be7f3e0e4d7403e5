#include "pid_axis.hpp"

#include <algorithm>

namespace ambdrop_truth {

PidAxis::PidAxis(const ControllerRig& c, double limit_A, double held_A)
    : c_(c),
      period_s_(1.0 / c.rate_Hz),
      limit_A_(limit_A),
      integral_V_(held_A / c.amplifier_gain_A_per_V) {}

double PidAxis::Update(double reading_m) {
  const double T = period_s_;
  const double e = -c_.sensor_gain_V_per_m * reading_m;
  const double integral = integral_V_ + c_.ki_per_s * 0.5 * T * (e + previous_error_V_);
  const double tau = c_.derivative_filter_s;
  derivative_V_ =
      ((2.0 * tau - T) * derivative_V_ + 2.0 * c_.kd_s * (e - previous_error_V_)) / (2.0 * tau + T);
  previous_error_V_ = e;
  const double command = c_.amplifier_gain_A_per_V * (c_.kp * e + integral + derivative_V_);
  const double limited = std::clamp(command, -limit_A_, limit_A_);
  if (limited == command) integral_V_ = integral;
  return limited;
}

}  // namespace ambdrop_truth
