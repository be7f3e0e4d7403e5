#include "tools/hil/can_controller_link.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

namespace ambdrop {

CanControllerLink::CanControllerLink(CanBus* bus, const FrameMap* map,
                                     const CanLinkOptions& options)
    : bus_(bus), map_(map), tdb_count_(std::clamp(options.tdb_count, 0, kMaxTdbs)) {
  // Decimation: the controller may run faster than the bus can carry a full exchange.
  if (options.controller_period_s > 0.0 && options.exchange_rate_Hz > 0.0) {
    const double ratio = 1.0 / (options.controller_period_s * options.exchange_rate_Hz);
    if (ratio > 1.0 + 1e-9) {
      send_every_ = std::llround(ratio);
      if (std::abs(ratio - static_cast<double>(send_every_)) > 1e-6 * ratio) {
        throw std::invalid_argument(
            "can.exchange_rate_Hz = " + std::to_string(options.exchange_rate_Hz) +
            ": the controller rate (" + std::to_string(1.0 / options.controller_period_s) +
            " Hz) must be a whole multiple of it, so that every n-th sensor sample is sent");
      }
    }
  }
  for (const CanSignalSpec& signal : map->spec().signals) {
    if (signal.role == CanSignalRole::kCurrent) current_keys_.push_back(signal.layout.key());
  }
  std::sort(current_keys_.begin(), current_keys_.end());
  current_keys_.erase(std::unique(current_keys_.begin(), current_keys_.end()), current_keys_.end());
}

void CanControllerLink::PushEvent(const PowerEvent& event) noexcept {
  ++counters_.power_events;
  if (event_count_ == kEventCapacity) {
    event_head_ = (event_head_ + 1) % kEventCapacity;  // the oldest goes
    --event_count_;
    ++counters_.power_events_lost;
  }
  events_[(event_head_ + event_count_) % kEventCapacity] = event;
  ++event_count_;
}

void CanControllerLink::Apply(const CanFrame& frame) noexcept {
  ++counters_.frames_received;
  const std::uint64_t fails = command_.power_fail_frames;
  const std::uint64_t restores = command_.power_restore_frames;
  if (map_->Decode(frame, &command_, &map_counters_) != DecodeResult::kApplied) return;
  const std::uint32_t key = frame.id | (frame.extended ? kCanEffFlag : 0U);
  if (std::binary_search(current_keys_.begin(), current_keys_.end(), key)) {
    fresh_currents_ = true;
    currents_receive_ns_ = frame.timestamp_ns;
  }
  // A CAN power event is a full failure (or return) of every AMB axis and the drive. A frame
  // that says both is a restore then a failure: the map leaves the power off, and so do we.
  PowerEvent event;
  if (command_.power_restore_frames != restores) {
    event.restore = true;
    PushEvent(event);
  }
  if (command_.power_fail_frames != fails) {
    event.restore = false;
    PushEvent(event);
  }
}

void CanControllerLink::Drain() noexcept {
  CanFrame frame;
  for (;;) {
    const CanStatus status = bus_->Receive(&frame, std::chrono::nanoseconds(0));
    if (status == CanStatus::kOk) {
      Apply(frame);
      continue;
    }
    if (status == CanStatus::kError) ++counters_.receive_errors;
    return;
  }
}

bool CanControllerLink::WaitForFrames(std::chrono::nanoseconds timeout) noexcept {
  CanFrame frame;
  const CanStatus status = bus_->Receive(&frame, timeout);
  if (status == CanStatus::kError) ++counters_.receive_errors;
  if (status != CanStatus::kOk) return false;
  Apply(frame);
  Drain();
  return true;
}

bool CanControllerLink::AwaitAnswer(std::chrono::nanoseconds timeout) noexcept {
  if (answered_exchanges_ == counters_.exchanges_sent) return true;  // nothing sent since
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  Drain();
  while (!fresh_currents_) {
    const auto left = deadline - std::chrono::steady_clock::now();
    if (left <= std::chrono::nanoseconds(0)) return false;
    (void)WaitForFrames(std::chrono::duration_cast<std::chrono::nanoseconds>(left));
  }
  answered_exchanges_ = counters_.exchanges_sent;
  return true;
}

bool CanControllerLink::PollCurrents(CurrentsMessage* out) noexcept {
  Drain();
  if (!fresh_currents_) return false;
  fresh_currents_ = false;
  out->current_A = command_.current_A;
  out->sequence = map_counters_.decoded;
  out->receive_ns = currents_receive_ns_;
  return true;
}

void CanControllerLink::ObserveState(const Observation& observation) noexcept {
  outputs_.power_on = observation.power_on;
  outputs_.spin_speed_rad_s = observation.spin_speed_rad_s;
  bool contact = false;
  for (int t = 0; t < tdb_count_; ++t) {
    contact = contact || observation.tdb[static_cast<std::size_t>(t)].normal_force_N > 0.0;
  }
  outputs_.in_contact = contact;
}

void CanControllerLink::SendSensors(const SensorReadings& readings, std::int64_t step,
                                    double) noexcept {
  const std::int64_t sample = samples_++;
  if (sample % send_every_ != 0) {
    ++counters_.samples_decimated;
    return;
  }
  outputs_.sensor_xy_m = readings.reading_m;
  outputs_.step = static_cast<std::uint64_t>(step);
  const std::uint64_t saturated = map_counters_.saturated;
  const std::size_t count = map_->Encode(outputs_, std::span<CanFrame>(tx_), &map_counters_);
  counters_.encode_saturations += map_counters_.saturated - saturated;
  for (std::size_t f = 0; f < count; ++f) {
    switch (bus_->Send(tx_[f])) {
      case CanStatus::kOk:
        ++counters_.frames_sent;
        break;
      case CanStatus::kDropped:
        ++counters_.send_drops;
        break;
      case CanStatus::kWouldBlock:
      case CanStatus::kInvalid:
      case CanStatus::kError:
        ++counters_.send_errors;
        break;
    }
  }
  ++counters_.exchanges_sent;
}

bool CanControllerLink::Poll(double, PowerEvent* out) noexcept {
  Drain();
  if (event_count_ == 0) return false;
  *out = events_[event_head_];
  event_head_ = (event_head_ + 1) % kEventCapacity;
  --event_count_;
  return true;
}

CanLinkCounters CanControllerLink::counters() const noexcept {
  CanLinkCounters counters = counters_;
  counters.decoded = map_counters_.decoded;
  counters.unknown_id = map_counters_.unknown_id;
  counters.malformed = map_counters_.malformed;
  counters.trigger_no_match = map_counters_.trigger_no_match;
  return counters;
}

}  // namespace ambdrop
