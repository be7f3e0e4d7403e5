#pragma once
// One axis of the controller: seed 003's PID kp + ki/s + kd s/(1 + tau_d s) on the error
// e = -Gs * reading (V), command i = Ga * u (A). Discretised at the period T as a real
// controller might be, not as ambdrop's reference PID is: the integral by the trapezoidal rule,
// the filtered derivative by Tustin's substitution s = (2/T)(z - 1)/(z + 1) (Franklin, Powell &
// Workman, "Digital Control of Dynamic Systems", Sec. 6.3.1):
//   I_k = I_{k-1} + ki T/2 (e_k + e_{k-1})
//   D_k = ((2 tau_d - T) D_{k-1} + 2 kd (e_k - e_{k-1})) / (2 tau_d + T)
// While the command is limited the integral holds (conditional integration).
#include "rig.hpp"

namespace ambdrop_truth {

class PidAxis {
 public:
  PidAxis() = default;
  /// `limit_A` bounds the command; `held_A` is the command it starts holding at e = 0 (the
  /// integral carries it: the rotor has been levitated for a long time).
  PidAxis(const ControllerRig& c, double limit_A, double held_A);
  /// The limited command for one sensor reading (m).
  double Update(double reading_m);

 private:
  ControllerRig c_{};
  double period_s_ = 0.0;
  double limit_A_ = 0.0;
  double integral_V_ = 0.0;
  double derivative_V_ = 0.0;
  double previous_error_V_ = 0.0;
};

}  // namespace ambdrop_truth
