#include "controller_if/boundary/power_state.hpp"

#include <stdexcept>

#include "rt_core/power_loss_drive.hpp"

namespace ambdrop {

void PowerState::Apply(const PowerEvent& e, std::int64_t step, const ControlInput& input) noexcept {
  ++events_;
  if (e.motor) motor_on_ = e.restore;
  for (std::size_t a = 0; a < model_->params.ambs.size(); ++a) {
    if ((e.amb_mask & (1u << a)) == 0) continue;
    const bool axes[2] = {e.axis_x, e.axis_y};
    for (int axis = 0; axis < 2; ++axis) {
      if (!axes[axis]) continue;
      if (e.restore) {
        lost_at_[a][axis] = -1;
      } else if (lost_at_[a][axis] < 0) {
        lost_at_[a][axis] = step;
        frozen_current_A_[a][axis] = input.amb[a].current_A[axis];
      }
    }
  }
}

void PowerState::Fill(std::int64_t step, ControlInput* in) const noexcept {
  in->motor_on = motor_on_;
  const double dt = model_->params.simulation.step_s;
  for (std::size_t a = 0; a < model_->params.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      if (lost_at_[a][axis] < 0) {
        in->amb[a].force_scale[axis] = 1.0;
        in->amb[a].bias_scale[axis] = 1.0;
        continue;
      }
      const UnpoweredDrive d = PowerLossDrive(model_->params.ambs[a], frozen_current_A_[a][axis],
                                              (step - lost_at_[a][axis]) * dt);
      in->amb[a].current_A[axis] = d.current_A;
      in->amb[a].force_scale[axis] = d.force_scale;
      in->amb[a].bias_scale[axis] = d.bias_scale;
    }
  }
}

namespace {

PowerEvent Scheduled(const Model& model, bool restore) {
  const TriggerParams& t = model.params.trigger;
  PowerEvent e;
  e.restore = restore;
  e.axis_x = t.axis_x;
  e.axis_y = t.axis_y;
  e.motor = t.ambs.empty() && t.axis_x && t.axis_y;
  if (!t.ambs.empty()) {
    e.amb_mask = 0;
    for (const std::string& name : t.ambs) {
      bool found = false;
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        if (model.params.ambs[a].name == name) {
          e.amb_mask |= 1u << a;
          found = true;
        }
      }
      if (!found) throw std::invalid_argument("trigger.ambs: no AMB named '" + name + "'");
    }
  }
  return e;
}

}  // namespace

PowerEvent ScheduledFailure(const Model& model) {
  return Scheduled(model, false);
}
PowerEvent ScheduledRestore(const Model& model) {
  return Scheduled(model, true);
}

}  // namespace ambdrop
