#pragma once
// The amplifier's current loop between the controller's command and the coil current, sampled
// at a period T: the command is held over the period (it is what the controller wrote) and the
// loop's response to it is exact at the period's end (zero-order hold), so the discretisation
// adds no error of its own. The drivers that step the physics (sim, scenario, fit) advance it
// at their physics step (ReferenceController::Advance), as the analog loop of a real amplifier
// runs between the controller's samples; a driver without one (the stand-in controller process)
// at the controller period, where the held current leads the loop's mean over the period by T/2.
#include "rt_core/controller_form_params.hpp"

namespace ambdrop {

class AmplifierLoop {
 public:
  AmplifierLoop() = default;
  AmplifierLoop(const AmplifierParams& params, double period_s, double initial_A);
  /// The coil current at the end of one period with `command_A` held over it.
  double Update(double command_A) noexcept;

 private:
  int order_ = 1;
  double max_step_A_ = 0.0;        ///< slew limit over one period
  double max_rate_A_per_s_ = 0.0;  ///< over w, as rate_A_per_s_
  // Per period: [i, i'/w] <- Phi [i, i'] + Gamma command (order 2); order 1 uses Phi[0][0] and
  // Gamma[0].
  double phi_[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  double gamma_[2] = {0.0, 0.0};
  double current_A_ = 0.0;
  double rate_A_per_s_ = 0.0;  ///< i' / w (order 2)
};

}  // namespace ambdrop
