#include "tools/hil/gpio_trigger_source.hpp"

#include <chrono>

namespace ambdrop {

bool GpioTriggerSource::Poll(double, PowerEvent* out) noexcept {
  // A read error is counted by the trigger (counters().read_errors); the loop goes on.
  if (trigger_->pending_events() == 0) (void)trigger_->Poll(std::chrono::nanoseconds(0));
  GpioPowerEvent event;
  if (!trigger_->PopEvent(&event)) return false;
  *out = PowerEvent{};
  out->restore = !event.power_fail;
  return true;
}

}  // namespace ambdrop
