#pragma once
#include <string>
#include <vector>

namespace ambdrop {

enum class AmbForceLaw {
  /// Equivalent stiffness and damping per axis from the controller's transfer function at the
  /// running speed (Jarroux 2019, Sec. 5): f = -k u - c du/dt (+ gravity bias).
  kEquivalent,
  /// Linearised actuator, f = ki i + ks u, with coil currents from a profile.
  kLinearisedCurrents,
};

/// Control currents of one radial AMB at one instant (linear interpolation in between).
struct CurrentSample {
  double time_s = 0.0;
  double current_x_A = 0.0;
  double current_y_A = 0.0;
};

struct AmbParams {
  std::string name;
  double position_m = 0.0;
  AmbForceLaw law = AmbForceLaw::kEquivalent;
  double stiffness_N_per_m = 0.0;  ///< equivalent law
  double damping_N_s_per_m = 0.0;  ///< equivalent law
  /// Equivalent law: add the constant force an integrating controller holds so that the
  /// levitated rotor sits on the magnetic centre under gravity.
  bool gravity_compensation = true;
  double current_gain_N_per_A = 0.0;           ///< ki, linearised law
  double position_gain_N_per_m = 0.0;          ///< ks (negative stiffness), linearised law
  std::vector<CurrentSample> current_profile;  ///< linearised law
};

}  // namespace ambdrop
