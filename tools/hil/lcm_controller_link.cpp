#include "tools/hil/lcm_controller_link.hpp"

#include <thread>

namespace ambdrop {

bool LcmControllerLink::PollCurrents(CurrentsMessage* out) noexcept {
  HilCurrents c;
  bool any = false;
  while (endpoint_->TryPopCurrents(&c)) {
    any = true;
    out->current_A = c.current_A;
    out->sequence = static_cast<std::uint64_t>(c.sequence);
    out->receive_ns = c.receive_ns;
  }
  return any;
}

void LcmControllerLink::SendSensors(const SensorReadings& readings, std::int64_t step,
                                    double time_s) noexcept {
  HilSensorReadings r;
  r.step_index = step;
  r.time_s = time_s;
  r.sensor_count = sensor_count_;
  r.position_m = readings.reading_m;
  (void)endpoint_->TryPushSensors(r);  // a full ring drops and counts
  ++samples_sent_;
}

bool LcmControllerLink::AwaitAnswer(std::chrono::nanoseconds timeout) noexcept {
  if (samples_answered_ == samples_sent_) return true;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (endpoint_->pending_currents() == 0) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
  samples_answered_ = samples_sent_;
  return true;
}

bool LcmControllerLink::Poll(double, PowerEvent* out) noexcept {
  HilTrigger t;
  if (!endpoint_->TryPopTrigger(&t)) return false;
  out->restore = t.power_on;
  out->amb_mask = t.amb_mask;
  out->axis_x = (t.axis_mask & kAxisX) != 0;
  out->axis_y = (t.axis_mask & kAxisY) != 0;
  out->motor = t.amb_mask == kAllAmbs && out->axis_x && out->axis_y;
  return true;
}

}  // namespace ambdrop
