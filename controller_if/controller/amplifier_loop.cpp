#include "controller_if/controller/amplifier_loop.hpp"

#include <algorithm>
#include <numbers>

#include "controller_if/controller/controller_discretisation.hpp"

namespace ambdrop {

AmplifierLoop::AmplifierLoop(const AmplifierParams& p, double period_s, double initial_A)
    : order_(p.order),
      max_step_A_(p.slew_rate_A_per_s * period_s),
      max_rate_A_per_s_(p.slew_rate_A_per_s / (2.0 * std::numbers::pi * p.bandwidth_Hz)),
      current_A_(initial_A) {
  const double w = 2.0 * std::numbers::pi * p.bandwidth_Hz;
  const double t = period_s;
  if (order_ == 1) {
    // i' = w (c - i): a first-order loop whose bandwidth is its -3 dB frequency; exact over a
    // held command (Franklin, Powell & Workman, 3rd ed., Sec. 4.3.3).
    const auto e = SmallMatrixExp<2>({{{-w * t, w * t}, {0.0, 0.0}}});
    phi_[0][0] = e[0][0];
    gamma_[0] = e[0][1];
    return;
  }
  // i'' = w^2 (c - i) - 2 zeta w i' (a standard second-order loop, w its natural frequency:
  // the -3 dB frequency for zeta = 1/sqrt(2)).
  const double z = p.damping_ratio;
  // The state is [i, i' / w]: balanced, so its exponential needs few squarings.
  const auto e =
      SmallMatrixExp<3>({{{0.0, w * t, 0.0}, {-w * t, -2.0 * z * w * t, w * t}, {0.0, 0.0, 0.0}}});
  phi_[0][0] = e[0][0];
  phi_[0][1] = e[0][1];
  phi_[1][0] = e[1][0];
  phi_[1][1] = e[1][1];
  gamma_[0] = e[0][2];
  gamma_[1] = e[1][2];
}

double AmplifierLoop::Update(double command_A) noexcept {
  double next = 0.0;
  if (order_ == 1) {
    next = phi_[0][0] * current_A_ + gamma_[0] * command_A;
  } else {
    next = phi_[0][0] * current_A_ + phi_[0][1] * rate_A_per_s_ + gamma_[0] * command_A;
    rate_A_per_s_ = phi_[1][0] * current_A_ + phi_[1][1] * rate_A_per_s_ + gamma_[1] * command_A;
    rate_A_per_s_ = std::clamp(rate_A_per_s_, -max_rate_A_per_s_, max_rate_A_per_s_);
  }
  // The supply voltage bounds di/dt: L di/dt = V - R i (Schweitzer & Maslen, "Magnetic Bearings",
  // 2009, Sec. 5.2), taken here as a constant slew rate.
  current_A_ = std::clamp(next, current_A_ - max_step_A_, current_A_ + max_step_A_);
  return current_A_;
}

}  // namespace ambdrop
