#pragma once
// `ambdrop hil --trigger gpio:...`: the debounced GPIO power-fail input (io/gpio/gpio_trigger.hpp)
// as a TriggerSource of the session. It joins io's GpioTrigger to controller_if's TriggerSource, so
// it lives in tools/.
#include "controller_if/loop/controller_link.hpp"
#include "io/gpio/gpio_trigger.hpp"

namespace ambdrop {

/// Polls the GPIO trigger once per controller period without waiting (one ppoll on the line's
/// file descriptor, plus one read when edges are queued) and hands its accepted events out as
/// full power failures and restores (every AMB axis and the drive). Allocation-free, noexcept.
class GpioTriggerSource final : public TriggerSource {
 public:
  /// `trigger` must be started (GpioTrigger::Start) and outlive this source.
  explicit GpioTriggerSource(GpioTrigger* trigger) : trigger_(trigger) {}
  bool Poll(double time_s, PowerEvent* out) noexcept override;

 private:
  GpioTrigger* trigger_;
};

}  // namespace ambdrop
