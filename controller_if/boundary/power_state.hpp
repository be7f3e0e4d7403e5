#pragma once
#include <array>
#include <cstdint>

#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// A change of power from any trigger source (GPIO edge, CAN frame, LCM message, schedule).
struct PowerEvent {
  bool restore = false;          ///< false: power fails; true: power comes back
  std::uint32_t amb_mask = ~0u;  ///< bit a: AMB a (model order) is affected
  bool axis_x = true;
  bool axis_y = true;
  bool motor = true;  ///< the drive loses (or regains) power too: a full failure
};

/// Which AMB axes have power and since when, and what that means for the step's input: an
/// unpowered axis keeps the current it had when power failed, falling by its power-loss law
/// (rt_core/power_loss_drive.hpp; gone at once without flux decay, and with a permanent-magnet
/// bias the bias force stays); without motor power the rotor coasts. Allocation-free.
class PowerState {
 public:
  explicit PowerState(const Model& model) : model_(&model) {}
  /// Applies an event at `step`; `input` holds the currents being applied at that moment.
  void Apply(const PowerEvent& event, std::int64_t step, const ControlInput& input) noexcept;
  /// Writes motor_on, force scales and the frozen currents of unpowered axes into `input`.
  void Fill(std::int64_t step, ControlInput* input) const noexcept;
  bool powered(int amb, int axis) const noexcept { return lost_at_[amb][axis] < 0; }
  bool motor_on() const noexcept { return motor_on_; }
  std::int64_t events() const noexcept { return events_; }

 private:
  const Model* model_;
  bool motor_on_ = true;
  std::array<std::array<std::int64_t, 2>, kMaxAmbs> lost_at_{
      {{-1, -1}, {-1, -1}, {-1, -1}, {-1, -1}}};
  std::array<std::array<double, 2>, kMaxAmbs> frozen_current_A_{};
  std::int64_t events_ = 0;
};

/// The config's scheduled trigger as events: the failure at trigger.time_s, the restore at
/// trigger.restore_time_s. `names` → mask through the model's AMB order.
PowerEvent ScheduledFailure(const Model& model);
PowerEvent ScheduledRestore(const Model& model);

}  // namespace ambdrop
