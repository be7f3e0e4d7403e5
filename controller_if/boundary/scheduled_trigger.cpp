#include "controller_if/loop/controller_link.hpp"

namespace ambdrop {

ScheduledTrigger::ScheduledTrigger(double fail_time_s, PowerEvent failure, double restore_time_s,
                                   PowerEvent restore)
    : fail_time_s_(fail_time_s),
      restore_time_s_(restore_time_s),
      failure_(failure),
      restore_(restore) {
  restore_.restore = true;
}

bool ScheduledTrigger::Poll(double time_s, PowerEvent* out) noexcept {
  if (fired_ == 0 && time_s >= fail_time_s_) {
    fired_ = 1;
    *out = failure_;
    return true;
  }
  if (fired_ == 1 && restore_time_s_ >= 0.0 && time_s >= restore_time_s_) {
    fired_ = 2;
    *out = restore_;
    return true;
  }
  return false;
}

}  // namespace ambdrop
