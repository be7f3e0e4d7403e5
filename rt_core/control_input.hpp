#pragma once
#include <array>

#include "rt_core/limits.hpp"

namespace ambdrop {

/// What drives one AMB during a step.
struct AmbDrive {
  std::array<double, 2> current_A{};  ///< control current (x, y), current-driven laws
  /// Scale on the axis force: 1 powered, 0 without power, in between while the flux decays.
  std::array<double, 2> force_scale{1.0, 1.0};
  /// Scale on the bias current I0 of the current-driven laws (ki by it, ks by its square): 1
  /// unless a slew-limited ramp drains an electromagnet bias after power loss.
  std::array<double, 2> bias_scale{1.0, 1.0};
};

/// The currents of every AMB axis (x, y) at one output row: what the controller (or the current
/// profile) commands, and the control current the coils carry: the command within the
/// amplifier's limit (ControlCurrentLimit) while powered; after power loss the current it held
/// then, falling by the AMB's power-loss law (ReportedCoilCurrent), while the command goes on.
struct AmbCurrents {
  std::array<std::array<double, 2>, kMaxAmbs> command_A{};
  std::array<std::array<double, 2>, kMaxAmbs> coil_A{};
};

/// What the controller side hands the physics for one step (zero-order hold over the step).
struct ControlInput {
  bool motor_on = true;  ///< the drive holds the spin speed; off after the shutdown trigger
  std::array<AmbDrive, kMaxAmbs> amb{};

  /// Everything powered (the default) or everything off (after a full power failure).
  static ControlInput Powered() { return ControlInput{}; }
  static ControlInput PowerOff() {
    ControlInput in;
    in.motor_on = false;
    for (AmbDrive& a : in.amb) a.force_scale = {0.0, 0.0};
    return in;
  }
};

}  // namespace ambdrop
