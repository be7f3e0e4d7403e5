#pragma once
#include <vector>

#include "controller_if/loop/controller_link.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// Stands in for a controller on a rig without one (`[controller] kind = "none"`): each AMB's
/// currents follow its `current_profile` (e.g. exported from a recording by `ambdrop replay
/// --export-profile`). Open loop: the currents do not answer the sensors, so, as on the
/// machine, a current-driven AMB's negative stiffness lets small differences grow.
/// The currents for the period that starts at time t are the profile's at t, as `ambdrop sim`
/// applies them at each step when the period is one step.
class ProfileControllerLink final : public ControllerLink {
 public:
  explicit ProfileControllerLink(const Model& model);
  bool PollCurrents(CurrentsMessage* out) noexcept override;
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override;

 private:
  void Fill(double time_s) noexcept;

  std::vector<std::vector<CurrentSample>> profiles_;  // per AMB, model order
  CurrentsMessage pending_;
  bool has_pending_ = false;
};

}  // namespace ambdrop
