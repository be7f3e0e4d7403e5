#include "io/can/can_frame_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string_view>
#include <tuple>
#include <utility>

#include "io/config/config_loader.hpp"

namespace ambdrop {
namespace {

std::string_view RoleName(CanSignalRole role) {
  switch (role) {
    case CanSignalRole::kCurrent:
      return "current";
    case CanSignalRole::kPowerFail:
      return "power_fail";
    case CanSignalRole::kPowerRestore:
      return "power_restore";
    case CanSignalRole::kSensor:
      return "sensor";
    case CanSignalRole::kStatusPowerOn:
      return "power_on";
    case CanSignalRole::kStatusStep:
      return "step_counter";
    case CanSignalRole::kStatusSpinSpeed:
      return "spin_speed";
    case CanSignalRole::kStatusInContact:
      return "in_contact";
    case CanSignalRole::kStatusOverruns:
      return "overrun_counter";
  }
  return "?";
}

bool IsScaled(CanSignalRole role) {
  return role == CanSignalRole::kCurrent || role == CanSignalRole::kSensor ||
         role == CanSignalRole::kStatusSpinSpeed;
}

bool IsTrigger(CanSignalRole role) {
  return role == CanSignalRole::kPowerFail || role == CanSignalRole::kPowerRestore;
}

/// Whether the signal occupies payload bytes (an any_frame trigger does not).
bool UsesBytes(const CanSignalSpec& signal) {
  return !(IsTrigger(signal.role) && signal.any_frame);
}

std::string Where(const CanSignalSpec& signal) {
  return signal.location.empty() ? std::string() : signal.location + ": ";
}

[[noreturn]] void Fail(const CanSignalSpec& signal, std::string_view what) {
  throw ConfigError(fmt::format("{}signal '{}': {}", Where(signal), signal.name, what));
}

std::string DescribeBytes(const CanSignalSpec& signal) {
  return fmt::format("bytes {}..{} of id {:#x}{}", signal.layout.byte_offset,
                     signal.layout.end() - 1, signal.layout.id,
                     signal.layout.extended ? " (29-bit)" : "");
}

void CheckSignal(const FrameMapSpec& spec, const CanSignalSpec& signal) {
  const CanSignalLayout& layout = signal.layout;
  const std::uint32_t max_id = layout.extended ? kCanEffMaxId : kCanSffMaxId;
  if (layout.id > max_id) {
    Fail(signal, fmt::format("id {:#x} does not fit a {}-bit identifier (max {:#x})", layout.id,
                             layout.extended ? 29 : 11, max_id));
  }
  if (!UsesBytes(signal)) return;
  if (layout.width_bytes != 1 && layout.width_bytes != 2 && layout.width_bytes != 4) {
    Fail(signal, fmt::format("width of {} bytes; expected 1, 2 or 4", layout.width_bytes));
  }
  const int max_len = spec.fd ? kCanFdMaxLen : kCanMaxLen;
  if (layout.byte_offset < 0 || layout.end() > max_len) {
    Fail(signal, fmt::format("bytes {}..{} do not fit a {} payload of {} bytes", layout.byte_offset,
                             layout.end() - 1, spec.fd ? "CAN FD" : "classic CAN", max_len));
  }
  if (!IsInput(signal.role) && spec.tx_len_bytes > 0 && layout.end() > spec.tx_len_bytes) {
    Fail(signal, fmt::format("bytes {}..{} do not fit the sent length tx_len_bytes = {}",
                             layout.byte_offset, layout.end() - 1, spec.tx_len_bytes));
  }
  if (IsScaled(signal.role) &&
      (!std::isfinite(signal.scaling.scale) || signal.scaling.scale == 0.0 ||
       !std::isfinite(signal.scaling.offset))) {
    Fail(signal, fmt::format("scale {} and offset {}: expected a finite non-zero scale and a "
                             "finite offset",
                             signal.scaling.scale, signal.scaling.offset));
  }
  if (IsTrigger(signal.role)) {
    if (layout.is_signed) Fail(signal, "a trigger compares unsigned bits: signed must be false");
    const std::uint64_t width_mask = static_cast<std::uint64_t>(RawMax(layout));
    if (signal.mask == 0 || (signal.mask & ~width_mask) != 0) {
      Fail(signal, fmt::format("mask {:#x}: expected a non-zero mask within {} byte(s) ({:#x})",
                               signal.mask, layout.width_bytes, width_mask));
    }
    if ((signal.value & ~signal.mask) != 0) {
      Fail(signal, fmt::format("value {:#x} has bits outside the mask {:#x}; it could never "
                               "match",
                               signal.value, signal.mask));
    }
  }
}

void CheckIndex(const FrameMapSpec& spec, const CanSignalSpec& signal) {
  if (signal.axis != 0 && signal.axis != 1) Fail(signal, "axis must be 0 (x) or 1 (y)");
  const std::size_t count =
      signal.role == CanSignalRole::kCurrent ? spec.amb_names.size() : spec.sensor_names.size();
  if (signal.index < 0 || static_cast<std::size_t>(signal.index) >= count) {
    Fail(signal, fmt::format("{} index {} out of range (there are {})",
                             signal.role == CanSignalRole::kCurrent ? "AMB" : "sensor",
                             signal.index, count));
  }
}

/// Signals that read or write the same bytes of one frame: an error for every outgoing pair
/// and for incoming pairs with a current (triggers may read the same status byte).
void CheckOverlaps(const FrameMapSpec& spec, const std::vector<int>& members) {
  for (std::size_t i = 0; i < members.size(); ++i) {
    for (std::size_t j = i + 1; j < members.size(); ++j) {
      const CanSignalSpec& a = spec.signals[static_cast<std::size_t>(members[i])];
      const CanSignalSpec& b = spec.signals[static_cast<std::size_t>(members[j])];
      if (!UsesBytes(a) || !UsesBytes(b)) continue;
      if (IsTrigger(a.role) && IsTrigger(b.role)) continue;
      const bool overlap =
          a.layout.byte_offset < b.layout.end() && b.layout.byte_offset < a.layout.end();
      if (!overlap) continue;
      Fail(b, fmt::format("{} overlap signal '{}' ({}{})", DescribeBytes(b), a.name,
                          a.location.empty() ? "" : a.location + ", ", DescribeBytes(a)));
    }
  }
}

}  // namespace

std::int64_t RawMin(const CanSignalLayout& layout) noexcept {
  if (!layout.is_signed) return 0;
  return -(std::int64_t{1} << (8 * layout.width_bytes - 1));
}

std::int64_t RawMax(const CanSignalLayout& layout) noexcept {
  const int bits = 8 * layout.width_bytes - (layout.is_signed ? 1 : 0);
  return (std::int64_t{1} << bits) - 1;
}

std::int64_t ReadRaw(const CanSignalLayout& layout,
                     std::span<const std::uint8_t, kCanFdMaxLen> data) noexcept {
  const int width = layout.width_bytes;
  std::uint64_t bits = 0;
  for (int i = 0; i < width; ++i) {
    // Byte i of the value, least significant first.
    const int position =
        layout.byte_order == CanByteOrder::kLittle ? layout.byte_offset + i : layout.end() - 1 - i;
    bits |= std::uint64_t{data[static_cast<std::size_t>(position)]} << (8 * i);
  }
  const std::uint64_t sign_bit = std::uint64_t{1} << (8 * width - 1);
  if (layout.is_signed && (bits & sign_bit) != 0) {
    return static_cast<std::int64_t>(bits) - static_cast<std::int64_t>(sign_bit << 1);
  }
  return static_cast<std::int64_t>(bits);
}

void WriteRaw(const CanSignalLayout& layout, std::int64_t raw,
              std::span<std::uint8_t, kCanFdMaxLen> data) noexcept {
  const std::uint64_t bits = static_cast<std::uint64_t>(raw);  // two's complement
  for (int i = 0; i < layout.width_bytes; ++i) {
    const int position =
        layout.byte_order == CanByteOrder::kLittle ? layout.byte_offset + i : layout.end() - 1 - i;
    data[static_cast<std::size_t>(position)] = static_cast<std::uint8_t>(bits >> (8 * i));
  }
}

std::int64_t PhysicalToRaw(const CanSignalLayout& layout, const CanScaling& scaling,
                           double physical, bool* saturated) noexcept {
  *saturated = false;
  if (!std::isfinite(physical)) {
    *saturated = true;
    return 0;
  }
  // Ties to even (the default rounding mode); infinities from a huge quotient clamp below.
  const double rounded = std::nearbyint((physical - scaling.offset) / scaling.scale);
  const std::int64_t low = RawMin(layout);
  const std::int64_t high = RawMax(layout);
  if (rounded < static_cast<double>(low)) {
    *saturated = true;
    return low;
  }
  if (rounded > static_cast<double>(high)) {
    *saturated = true;
    return high;
  }
  return static_cast<std::int64_t>(rounded);
}

FrameMap::FrameMap(FrameMapSpec spec) : spec_(std::move(spec)) {
  const auto fail_spec = [](const std::string& what) { throw ConfigError("frame map: " + what); };
  if (spec_.signals.size() > static_cast<std::size_t>(kMaxCanSignals)) {
    fail_spec(fmt::format("{} signals, at most {}", spec_.signals.size(), kMaxCanSignals));
  }
  if (spec_.amb_names.size() > static_cast<std::size_t>(kMaxAmbs)) {
    fail_spec(fmt::format("{} AMBs, at most {}", spec_.amb_names.size(), kMaxAmbs));
  }
  if (spec_.sensor_names.size() > static_cast<std::size_t>(kMaxSensors)) {
    fail_spec(fmt::format("{} sensors, at most {}", spec_.sensor_names.size(), kMaxSensors));
  }
  if (spec_.tx_len_bytes != 0 &&
      (spec_.fd ? !IsCanFdLength(spec_.tx_len_bytes)
                : (spec_.tx_len_bytes < 0 || spec_.tx_len_bytes > kCanMaxLen))) {
    fail_spec(
        fmt::format("tx_len_bytes = {} is not a {} length", spec_.tx_len_bytes,
                    spec_.fd ? "CAN FD (0..8, 12, 16, 20, 24, 32, 48, 64)" : "classic (0..8)"));
  }

  // Each signal alone; then one signal per role (and per index and axis); then by frame.
  std::map<std::tuple<CanSignalRole, int, int>, int> seen;
  std::map<std::uint32_t, std::vector<int>> inputs_by_key;
  std::map<std::uint32_t, std::vector<int>> outputs_by_key;
  for (std::size_t i = 0; i < spec_.signals.size(); ++i) {
    const CanSignalSpec& signal = spec_.signals[i];
    CheckSignal(spec_, signal);
    const bool indexed =
        signal.role == CanSignalRole::kCurrent || signal.role == CanSignalRole::kSensor;
    if (indexed) CheckIndex(spec_, signal);
    const auto role_key =
        std::make_tuple(signal.role, indexed ? signal.index : 0, indexed ? signal.axis : 0);
    if (const auto [it, inserted] = seen.emplace(role_key, static_cast<int>(i)); !inserted) {
      const CanSignalSpec& first = spec_.signals[static_cast<std::size_t>(it->second)];
      Fail(signal,
           fmt::format("a second {} signal for the same quantity as '{}'{}", RoleName(signal.role),
                       first.name, first.location.empty() ? "" : " (" + first.location + ")"));
    }
    (IsInput(signal.role) ? inputs_by_key : outputs_by_key)[signal.layout.key()].push_back(
        static_cast<int>(i));
  }
  for (const auto& [key, members] : inputs_by_key) {
    if (const auto it = outputs_by_key.find(key); it != outputs_by_key.end()) {
      const CanSignalSpec& in = spec_.signals[static_cast<std::size_t>(members.front())];
      const CanSignalSpec& out = spec_.signals[static_cast<std::size_t>(it->second.front())];
      Fail(out, fmt::format("id {:#x} is sent by the emulator and also received (signal '{}'{}): "
                            "an id carries one direction only",
                            out.layout.id, in.name, in.location.empty() ? "" : ", " + in.location));
    }
  }
  for (const auto* by_key : {&inputs_by_key, &outputs_by_key}) {
    if (by_key->size() > static_cast<std::size_t>(kMaxCanFrames)) {
      fail_spec(fmt::format("{} distinct {} frame ids, at most {}", by_key->size(),
                            by_key == &inputs_by_key ? "incoming" : "outgoing", kMaxCanFrames));
    }
    for (const auto& [key, members] : *by_key) CheckOverlaps(spec_, members);
  }

  // Compile: frames sorted by key, each with its signals contiguous.
  const auto compile = [this](const std::map<std::uint32_t, std::vector<int>>& by_key,
                              bool outgoing, std::vector<CompiledFrame>* frames,
                              std::vector<CompiledSignal>* signals) {
    for (const auto& [key, members] : by_key) {
      CompiledFrame frame;
      frame.key = key;
      frame.first_signal = static_cast<int>(signals->size());
      frame.signal_count = static_cast<int>(members.size());
      for (const int index : members) {
        const CanSignalSpec& s = spec_.signals[static_cast<std::size_t>(index)];
        frame.id = s.layout.id;
        frame.extended = s.layout.extended;
        frame.has_trigger = frame.has_trigger || IsTrigger(s.role);
        if (UsesBytes(s)) frame.len = std::max(frame.len, s.layout.end());
        signals->push_back(CompiledSignal{.layout = s.layout,
                                          .scaling = s.scaling,
                                          .role = s.role,
                                          .index = s.index,
                                          .axis = s.axis,
                                          .any_frame = s.any_frame,
                                          .mask = s.mask,
                                          .value = s.value,
                                          .spec_index = index});
      }
      if (outgoing) {
        if (spec_.tx_len_bytes > 0) frame.len = spec_.tx_len_bytes;
        if (spec_.fd) frame.len = CanFdRoundUpLength(frame.len);
      }
      frames->push_back(frame);
    }
  };
  compile(inputs_by_key, false, &input_frames_, &input_signals_);
  compile(outputs_by_key, true, &output_frames_, &output_signals_);
}

DecodeResult FrameMap::Decode(const CanFrame& frame, CanCommand* command,
                              FrameMapCounters* counters) const noexcept {
  const std::uint32_t key = frame.id | (frame.extended ? kCanEffFlag : 0U);
  const auto it = std::lower_bound(
      input_frames_.begin(), input_frames_.end(), key,
      [](const CompiledFrame& entry, std::uint32_t wanted) { return entry.key < wanted; });
  if (it == input_frames_.end() || it->key != key) {
    ++counters->unknown_id;
    return DecodeResult::kUnknownId;
  }
  if (frame.rtr || frame.len < it->len) {
    ++counters->malformed;
    return DecodeResult::kMalformed;
  }
  const std::span<const std::uint8_t, kCanFdMaxLen> data(frame.data);
  bool power_fail = false;
  bool power_restore = false;
  for (int i = it->first_signal; i < it->first_signal + it->signal_count; ++i) {
    const CompiledSignal& signal = input_signals_[static_cast<std::size_t>(i)];
    if (signal.role == CanSignalRole::kCurrent) {
      command->current_A[static_cast<std::size_t>(signal.index)]
                        [static_cast<std::size_t>(signal.axis)] =
          RawToPhysical(signal.scaling, ReadRaw(signal.layout, data));
      continue;
    }
    const bool match =
        signal.any_frame ||
        (static_cast<std::uint32_t>(ReadRaw(signal.layout, data)) & signal.mask) == signal.value;
    if (!match) continue;
    (signal.role == CanSignalRole::kPowerFail ? power_fail : power_restore) = true;
  }
  // A frame that says both leaves the power off: failing safe.
  if (power_restore) {
    command->power_on = true;
    ++command->power_restore_frames;
  }
  if (power_fail) {
    command->power_on = false;
    ++command->power_fail_frames;
  }
  if (it->has_trigger && !power_fail && !power_restore) ++counters->trigger_no_match;
  ++counters->decoded;
  return DecodeResult::kApplied;
}

std::size_t FrameMap::Encode(const EmulatorOutputs& outputs, std::span<CanFrame> frames,
                             FrameMapCounters* counters) const noexcept {
  const std::size_t count = std::min(frames.size(), output_frames_.size());
  for (std::size_t f = 0; f < count; ++f) {
    const CompiledFrame& shape = output_frames_[f];
    CanFrame& out = frames[f];
    out = CanFrame{};
    out.id = shape.id;
    out.extended = shape.extended;
    out.fd = spec_.fd;
    out.brs = spec_.fd && spec_.bit_rate_switch;
    out.len = static_cast<std::uint8_t>(shape.len);
    const std::span<std::uint8_t, kCanFdMaxLen> data(out.data);
    for (int i = shape.first_signal; i < shape.first_signal + shape.signal_count; ++i) {
      const CompiledSignal& signal = output_signals_[static_cast<std::size_t>(i)];
      bool saturated = false;
      std::int64_t raw = 0;
      switch (signal.role) {
        case CanSignalRole::kSensor:
          raw = PhysicalToRaw(signal.layout, signal.scaling,
                              outputs.sensor_xy_m[static_cast<std::size_t>(signal.index)]
                                                 [static_cast<std::size_t>(signal.axis)],
                              &saturated);
          break;
        case CanSignalRole::kStatusSpinSpeed:
          raw = PhysicalToRaw(signal.layout, signal.scaling, outputs.spin_speed_rad_s, &saturated);
          break;
        case CanSignalRole::kStatusPowerOn:
          raw = outputs.power_on ? 1 : 0;
          break;
        case CanSignalRole::kStatusInContact:
          raw = outputs.in_contact ? 1 : 0;
          break;
        // Counters wrap: WriteRaw keeps the low bytes, i.e. the value modulo 2^(8 width).
        case CanSignalRole::kStatusStep:
          raw = static_cast<std::int64_t>(outputs.step);
          break;
        case CanSignalRole::kStatusOverruns:
          raw = static_cast<std::int64_t>(outputs.overruns);
          break;
        case CanSignalRole::kCurrent:
        case CanSignalRole::kPowerFail:
        case CanSignalRole::kPowerRestore:
          break;  // incoming only; never compiled here
      }
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

std::vector<CanFrameShape> FrameMap::InputFrames() const {
  std::vector<CanFrameShape> shapes;
  for (const CompiledFrame& frame : input_frames_) {
    shapes.push_back({.id = frame.id, .extended = frame.extended, .len = frame.len});
  }
  return shapes;
}

std::vector<CanFrameShape> FrameMap::OutputFrames() const {
  std::vector<CanFrameShape> shapes;
  for (const CompiledFrame& frame : output_frames_) {
    shapes.push_back({.id = frame.id, .extended = frame.extended, .len = frame.len});
  }
  return shapes;
}

std::vector<CanFilter> FrameMap::InputFilters() const {
  std::vector<CanFilter> filters;
  for (const CompiledFrame& frame : input_frames_) {
    filters.push_back(CanFilter::Exact(frame.id, frame.extended));
  }
  return filters;
}

double CanFrameWorstCaseTime_s(bool extended, bool fd, bool brs, int len, double bitrate_bit_s,
                               double data_bitrate_bit_s) noexcept {
  const int payload_bits = 8 * len;
  if (!fd) {
    // Classic: header, CRC and trailer g + 13 bits, stuffing over the g + 8n stuffable bits.
    const int g = extended ? 54 : 34;
    const int bits = g + payload_bits + 13 + (g + payload_bits - 1) / 4;
    return bits / bitrate_bit_s;
  }
  // FD: arbitration up to BRS (with stuffing) and the trailer (CRC delimiter, ACK, EOF,
  // interframe space) at the nominal rate; control, data, stuff count and CRC (with its fixed
  // stuff bits) at the data rate.
  const int arbitration_bits = extended ? 36 + 8 : 17 + 4;
  const int trailer_bits = 13;
  const int crc_bits = len <= 16 ? 17 : 21;
  const int data_phase_bits =
      5 + payload_bits + (5 + payload_bits - 1) / 4 + 4 + crc_bits + (4 + crc_bits + 3) / 4;
  const double data_rate = brs ? data_bitrate_bit_s : bitrate_bit_s;
  return (arbitration_bits + trailer_bits) / bitrate_bit_s + data_phase_bits / data_rate;
}

}  // namespace ambdrop
