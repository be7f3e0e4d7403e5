#include "tools/fit/current_sampler.hpp"

#include <cmath>
#include <limits>

#include "rt_core/power_loss_drive.hpp"

namespace ambdrop {

CurrentSampler::CurrentSampler(const ModelParams& params, double step_s)
    : params_(params), step_s_(step_s) {
  for (auto& a : lost_at_) a = {-1, -1};
}

void CurrentSampler::AddSample(std::int64_t step) {
  steps_.push_back(step);
  current_A_.emplace_back();
  commanded_A_.emplace_back();
}

const std::vector<CurrentSampler::Currents>& CurrentSampler::Finish() noexcept {
  FillBefore(std::numeric_limits<std::int64_t>::max());
  return current_A_;
}

void CurrentSampler::OnStart(const RecordedStart& start) noexcept {
  held_ = start.loop_current_A;
}

void CurrentSampler::OnInput(const RecordedInput& input) noexcept {
  FillBefore(input.step);
  switch (input.kind) {
    case RecordedInputKind::kCurrents:
      held_ = input.current_A;
      break;
    case RecordedInputKind::kWatchdogZero:
      held_ = {};
      break;
    case RecordedInputKind::kWatchdogStop:
      break;
  }
}

void CurrentSampler::OnPower(const RecordedPower& p) noexcept {
  FillBefore(p.step);
  for (std::size_t a = 0; a < params_.ambs.size(); ++a) {
    if ((p.event.amb_mask & (1u << a)) == 0) continue;
    const bool axes[2] = {p.event.axis_x, p.event.axis_y};
    for (int axis = 0; axis < 2; ++axis) {
      if (!axes[axis]) continue;
      if (p.event.restore) {
        lost_at_[a][axis] = -1;
      } else if (lost_at_[a][axis] < 0) {
        lost_at_[a][axis] = p.step;
        frozen_[a][axis] = held_[a][axis];
      }
    }
  }
}

void CurrentSampler::FillBefore(std::int64_t step) noexcept {
  while (filled_ < steps_.size() && steps_[filled_] < step) {
    Currents& c = current_A_[filled_];
    c = held_;
    commanded_A_[filled_] = held_;
    for (std::size_t a = 0; a < params_.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        if (lost_at_[a][axis] < 0) continue;
        const double t = static_cast<double>(steps_[filled_] - lost_at_[a][axis]) * step_s_;
        c[a][axis] = ReportedCoilCurrent(PowerLossDrive(params_.ambs[a], frozen_[a][axis], t));
      }
    }
    ++filled_;
  }
}

}  // namespace ambdrop
