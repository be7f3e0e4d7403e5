#include "io/can/can_controller_view.hpp"

#include <algorithm>
#include <map>

namespace ambdrop {
namespace {

/// The payload length a frame is sent with: what holds its signals, at least the map's
/// tx_len_bytes, rounded up to an FD length step for FD.
int SentLength(const FrameMapSpec& spec, int least) {
  int len = std::max(least, spec.tx_len_bytes);
  if (spec.fd) len = CanFdRoundUpLength(len);
  return len;
}

}  // namespace

ControllerFrameView::ControllerFrameView(const FrameMap& map)
    : fd_(map.spec().fd), brs_(map.spec().fd && map.spec().bit_rate_switch) {
  const FrameMapSpec& spec = map.spec();
  // The FrameMap has checked ranges, overlaps and directions; this only regroups by frame.
  std::map<std::uint32_t, std::vector<int>> incoming;  // what the emulator sends
  std::map<std::uint32_t, std::vector<int>> currents;
  for (std::size_t i = 0; i < spec.signals.size(); ++i) {
    const CanSignalSpec& s = spec.signals[i];
    if (s.role == CanSignalRole::kCurrent) {
      currents[s.layout.key()].push_back(static_cast<int>(i));
    } else if (s.role == CanSignalRole::kPowerFail || s.role == CanSignalRole::kPowerRestore) {
      Trigger& trigger = s.role == CanSignalRole::kPowerFail ? fail_ : restore_;
      trigger.present = true;
      trigger.layout = s.layout;
      trigger.any_frame = s.any_frame;
      trigger.value = s.value;
    } else {
      incoming[s.layout.key()].push_back(static_cast<int>(i));
      if (s.role == CanSignalRole::kSensor) {
        last_sensor_key_ =
            has_sensors_ ? std::max(last_sensor_key_, s.layout.key()) : s.layout.key();
        has_sensors_ = true;
      }
    }
  }
  // A trigger frame is as long as the emulator expects its id to be (a trigger may share a
  // frame with currents).
  for (const CanFrameShape& shape : map.InputFrames()) {
    for (Trigger* trigger : {&fail_, &restore_}) {
      if (trigger->present && trigger->layout.id == shape.id &&
          trigger->layout.extended == shape.extended) {
        trigger->len = SentLength(spec, shape.len);
      }
    }
  }
  const auto compile = [this, &spec](const std::map<std::uint32_t, std::vector<int>>& by_key,
                                     bool outgoing, std::vector<Frame>* frames,
                                     std::vector<Signal>* signals) {
    for (const auto& [key, members] : by_key) {
      Frame frame;
      frame.key = key;
      frame.first_signal = static_cast<int>(signals->size());
      frame.signal_count = static_cast<int>(members.size());
      for (const int index : members) {
        const CanSignalSpec& s = spec.signals[static_cast<std::size_t>(index)];
        frame.id = s.layout.id;
        frame.extended = s.layout.extended;
        frame.len = std::max(frame.len, s.layout.end());
        signals->push_back(Signal{.layout = s.layout,
                                  .scaling = s.scaling,
                                  .role = s.role,
                                  .index = s.index,
                                  .axis = s.axis,
                                  .spec_index = index});
      }
      if (outgoing) {
        // A trigger in the same frame needs its bytes sent too.
        for (const Trigger* trigger : {&fail_, &restore_}) {
          if (trigger->present && !trigger->any_frame && trigger->layout.key() == key) {
            frame.len = std::max(frame.len, trigger->layout.end());
          }
        }
        frame.len = SentLength(spec, frame.len);
      }
      frames->push_back(frame);
    }
  };
  compile(incoming, false, &input_frames_, &input_signals_);
  compile(currents, true, &current_frames_, &current_signals_);
}

DecodeResult ControllerFrameView::Decode(const CanFrame& frame, EmulatorOutputs* outputs,
                                         FrameMapCounters* counters) const noexcept {
  const std::uint32_t key = frame.id | (frame.extended ? kCanEffFlag : 0U);
  const auto it =
      std::lower_bound(input_frames_.begin(), input_frames_.end(), key,
                       [](const Frame& entry, std::uint32_t wanted) { return entry.key < wanted; });
  if (it == input_frames_.end() || it->key != key) {
    ++counters->unknown_id;
    return DecodeResult::kUnknownId;
  }
  if (frame.rtr || frame.len < it->len) {
    ++counters->malformed;
    return DecodeResult::kMalformed;
  }
  const std::span<const std::uint8_t, kCanFdMaxLen> data(frame.data);
  for (int i = it->first_signal; i < it->first_signal + it->signal_count; ++i) {
    const Signal& signal = input_signals_[static_cast<std::size_t>(i)];
    const std::int64_t raw = ReadRaw(signal.layout, data);
    switch (signal.role) {
      case CanSignalRole::kSensor:
        outputs->sensor_xy_m[static_cast<std::size_t>(signal.index)]
                            [static_cast<std::size_t>(signal.axis)] =
            RawToPhysical(signal.scaling, raw);
        break;
      case CanSignalRole::kStatusSpinSpeed:
        outputs->spin_speed_rad_s = RawToPhysical(signal.scaling, raw);
        break;
      case CanSignalRole::kStatusPowerOn:
        outputs->power_on = raw != 0;
        break;
      case CanSignalRole::kStatusInContact:
        outputs->in_contact = raw != 0;
        break;
      case CanSignalRole::kStatusStep:
        outputs->step = static_cast<std::uint64_t>(raw);
        break;
      case CanSignalRole::kStatusOverruns:
        outputs->overruns = static_cast<std::uint64_t>(raw);
        break;
      case CanSignalRole::kCurrent:
      case CanSignalRole::kPowerFail:
      case CanSignalRole::kPowerRestore:
        break;  // sent by the controller; never compiled here
    }
  }
  ++counters->decoded;
  return DecodeResult::kApplied;
}

bool ControllerFrameView::CompletesSensors(const CanFrame& frame) const noexcept {
  return has_sensors_ && (frame.id | (frame.extended ? kCanEffFlag : 0U)) == last_sensor_key_;
}

std::size_t ControllerFrameView::EncodeCurrents(const CanCommand& command,
                                                std::span<CanFrame> frames,
                                                FrameMapCounters* counters) const noexcept {
  const std::size_t count = std::min(frames.size(), current_frames_.size());
  for (std::size_t f = 0; f < count; ++f) {
    const Frame& shape = current_frames_[f];
    CanFrame& out = frames[f];
    out = CanFrame{};
    out.id = shape.id;
    out.extended = shape.extended;
    out.fd = fd_;
    out.brs = brs_;
    out.len = static_cast<std::uint8_t>(shape.len);
    const std::span<std::uint8_t, kCanFdMaxLen> data(out.data);
    for (int i = shape.first_signal; i < shape.first_signal + shape.signal_count; ++i) {
      const Signal& signal = current_signals_[static_cast<std::size_t>(i)];
      bool saturated = false;
      const std::int64_t raw =
          PhysicalToRaw(signal.layout, signal.scaling,
                        command.current_A[static_cast<std::size_t>(signal.index)]
                                         [static_cast<std::size_t>(signal.axis)],
                        &saturated);
      if (saturated) {
        ++counters->saturated;
        ++counters->saturated_by_signal[static_cast<std::size_t>(signal.spec_index)];
      }
      WriteRaw(signal.layout, raw, data);
    }
  }
  counters->encoded_frames += count;
  return count;
}

bool ControllerFrameView::EncodeTrigger(bool restore, CanFrame* frame) const noexcept {
  const Trigger& trigger = restore ? restore_ : fail_;
  if (!trigger.present) return false;
  *frame = CanFrame{};
  frame->id = trigger.layout.id;
  frame->extended = trigger.layout.extended;
  frame->fd = fd_;
  frame->brs = brs_;
  frame->len = static_cast<std::uint8_t>(trigger.len);
  if (!trigger.any_frame) {
    WriteRaw(trigger.layout, trigger.value, std::span<std::uint8_t, kCanFdMaxLen>(frame->data));
  }
  return true;
}

std::vector<CanFilter> ControllerFrameView::InputFilters() const {
  std::vector<CanFilter> filters;
  for (const Frame& frame : input_frames_) {
    filters.push_back(CanFilter::Exact(frame.id, frame.extended));
  }
  return filters;
}

}  // namespace ambdrop
