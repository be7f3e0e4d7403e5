#pragma once
// One AMB axis of the general linear controller ([controller.linear]): a cascade of biquads on
// e = -Gs * reading (V), command i = Ga u + i_ff (A), limited to the AMB's current limit, with
// the anti-windup rule of the config.
#include <array>

#include "controller_if/controller/biquad.hpp"
#include "rt_core/controller_form_params.hpp"

namespace ambdrop {

class LinearAxis {
 public:
  LinearAxis() = default;
  /// Throws std::invalid_argument for a section that cannot be discretised, or back-calculation
  /// with no integrating section whose downstream sections pass DC.
  LinearAxis(const LinearControllerParams& params, double period_s, double feedforward_A,
             double limit_A);
  /// The limited command current from one reading.
  double Update(double reading_m) noexcept;
  /// Puts the axis at rest with the reading `reading_m` held and the command `current_A` (the
  /// levitated start, Model::levitated): the last integrating section holds what the command
  /// needs beyond the feedforward (at rest an integrating cascade sees no error: `reading_m` is
  /// then 0) and every other section rests at its DC gain on its constant input.
  void HoldAtRest(double reading_m, double current_A) noexcept;
  /// The command before the limit, of the last Update (for tests of the anti-windup rules).
  double unlimited_A() const noexcept { return unlimited_A_; }
  const Biquad& section(int i) const noexcept { return sections_[i]; }

 private:
  std::array<Biquad, kMaxControllerSections> sections_{};
  int count_ = 0;
  double sensor_gain_V_per_m_ = 0.0;
  double amplifier_gain_A_per_V_ = 0.0;
  double feedforward_A_ = 0.0;
  double limit_A_ = 0.0;
  AntiWindup anti_windup_ = AntiWindup::kNone;
  double back_calculation_gain_ = 0.0;  ///< T / Tt
  int back_calculation_section_ = -1;
  double downstream_dc_gain_ = 1.0;  ///< of the sections after it
  double unlimited_A_ = 0.0;
};

}  // namespace ambdrop
