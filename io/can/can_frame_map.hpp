#pragma once
// The config-driven codec between CAN frames and the emulator's inputs and outputs.
//
// A signal is an integer of 1, 2 or 4 whole bytes (widths are in bytes, not bits) at a byte
// offset in the payload of one frame (id + 11/29-bit format), signed (two's complement) or
// unsigned, little- or big-endian. Its physical value is
//     physical = raw * scale + offset.
// Encoding rounds (physical - offset) / scale to the nearest integer (ties to even) and
// saturates at the raw range; each saturation, and each non-finite value (sent as raw 0), is
// counted per signal.
//
// Signal groups (directions are the emulator's):
//   currents_in  (in)   per AMB and axis: coil control current, A;
//   trigger_in   (in)   power_fail / power_restore: a raw value (after a mask) that switches the
//                       AMB power off / on, or "any frame with this id";
//   sensors_out  (out)  per sensor and axis: displacement, m (ADC counts by choosing the scale and
//                       offset: scale = m per count, offset = displacement at raw 0);
//   status_out   (out)  power_on (1/0), step_counter (wraps), spin_speed (rad/s, scaled),
//                       in_contact (1/0), overrun_counter (wraps).
// An id carries one direction only; outgoing signals may not overlap, nor incoming currents.
//
// FrameMap is immutable once built (all checks at setup, ConfigError on any problem); Decode and
// Encode are noexcept and allocation-free (sorted lookup tables built at setup). Mutable counts
// live in a caller-owned FrameMapCounters, so a run is copied by copying its state.
// The TOML schema is in io/config/config_can.hpp.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/can/can_bus.hpp"
#include "io/can/can_frame.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop {

inline constexpr int kMaxCanSignals = 64;  ///< signals in one frame map (both directions)
inline constexpr int kMaxCanFrames = 32;   ///< distinct frame ids per direction

enum class CanByteOrder : std::uint8_t {
  kLittle,  ///< least significant byte first (Intel)
  kBig,     ///< most significant byte first (Motorola)
};

/// Where a signal's raw integer sits.
struct CanSignalLayout {
  std::uint32_t id = 0;    ///< frame identifier, no flags
  bool extended = false;   ///< 29-bit identifier
  int byte_offset = 0;     ///< first payload byte, 0-based
  int width_bytes = 2;     ///< 1, 2 or 4
  bool is_signed = false;  ///< two's complement
  CanByteOrder byte_order = CanByteOrder::kLittle;

  /// The frame key used for lookups: id | CAN_EFF_FLAG for 29-bit ids.
  std::uint32_t key() const noexcept { return id | (extended ? kCanEffFlag : 0U); }
  int end() const noexcept { return byte_offset + width_bytes; }  ///< one past the last byte
};

/// physical = raw * scale + offset (both in the signal's physical unit).
struct CanScaling {
  double scale = 1.0;   ///< physical unit per raw count; finite, non-zero
  double offset = 0.0;  ///< physical value at raw 0
};

/// Smallest and largest raw value of a layout (e.g. -32768 and 32767 for 2 signed bytes).
std::int64_t RawMin(const CanSignalLayout& layout) noexcept;
std::int64_t RawMax(const CanSignalLayout& layout) noexcept;

/// The raw integer at `layout` in a payload (sign-extended when signed). No bounds check beyond
/// the 64-byte array: the caller checks the frame length.
std::int64_t ReadRaw(const CanSignalLayout& layout,
                     std::span<const std::uint8_t, kCanFdMaxLen> data) noexcept;
/// Writes the low width_bytes bytes of `raw` (two's complement) at `layout`.
void WriteRaw(const CanSignalLayout& layout, std::int64_t raw,
              std::span<std::uint8_t, kCanFdMaxLen> data) noexcept;

/// The raw value for `physical`: nearest integer to (physical - offset) / scale, clamped to the
/// layout's range. `*saturated` is set when it was clamped or `physical` was not finite (raw 0).
std::int64_t PhysicalToRaw(const CanSignalLayout& layout, const CanScaling& scaling,
                           double physical, bool* saturated) noexcept;
constexpr double RawToPhysical(const CanScaling& scaling, std::int64_t raw) noexcept {
  return static_cast<double>(raw) * scaling.scale + scaling.offset;
}

/// What a signal means.
enum class CanSignalRole : std::uint8_t {
  kCurrent,          ///< in: coil control current of AMB `index`, axis `axis`, A
  kPowerFail,        ///< in: a match switches the AMB power off
  kPowerRestore,     ///< in: a match switches the AMB power on
  kSensor,           ///< out: displacement at sensor `index`, axis `axis`, m
  kStatusPowerOn,    ///< out: 1 powered, 0 after a power failure
  kStatusStep,       ///< out: step counter, modulo 2^(8 width)
  kStatusSpinSpeed,  ///< out: rotor spin speed, rad/s, scaled
  kStatusInContact,  ///< out: 1 while any touchdown bearing is in contact
  kStatusOverruns,   ///< out: real-time loop overruns, modulo 2^(8 width)
};

/// True for the roles the emulator receives.
constexpr bool IsInput(CanSignalRole role) noexcept {
  return role == CanSignalRole::kCurrent || role == CanSignalRole::kPowerFail ||
         role == CanSignalRole::kPowerRestore;
}

/// One signal of a frame map, as configured.
struct CanSignalSpec {
  CanSignalRole role = CanSignalRole::kCurrent;
  CanSignalLayout layout;
  CanScaling scaling;  ///< kCurrent (A), kSensor (m), kStatusSpinSpeed (rad/s)
  int index = 0;       ///< AMB (kCurrent) or sensor (kSensor) index
  int axis = 0;        ///< 0 = x, 1 = y
  /// Triggers: the frame's mere arrival is the event (layout bytes unused); otherwise the
  /// unsigned raw value masked with `mask` must equal `value`.
  bool any_frame = false;
  std::uint32_t mask = 0xFFFFFFFFU;
  std::uint32_t value = 0;
  std::string name;      ///< dotted config path, e.g. "can.currents_in.de.x"
  std::string location;  ///< "file:line" of its table, for messages ("" when built in code)
};

/// Everything a FrameMap is built from.
struct FrameMapSpec {
  bool fd = false;               ///< frames are CAN FD (payload up to 64 bytes)
  bool bit_rate_switch = false;  ///< FD: sent frames set BRS
  /// Payload length of every sent frame, bytes; 0: the smallest length that holds the frame's
  /// signals (rounded up to an FD length step for FD).
  int tx_len_bytes = 0;
  std::vector<std::string> amb_names;     ///< kCurrent index → name
  std::vector<std::string> sensor_names;  ///< kSensor index → name
  std::vector<CanSignalSpec> signals;
};

/// What the controller commands, as last decoded (held between frames).
struct CanCommand {
  /// Coil control currents (x, y) per AMB, A, indexed as FrameMapSpec::amb_names.
  std::array<std::array<double, 2>, kMaxAmbs> current_A{};
  bool power_on = true;                    ///< false after power_fail, true after power_restore
  std::uint64_t power_fail_frames = 0;     ///< frames that matched power_fail
  std::uint64_t power_restore_frames = 0;  ///< frames that matched power_restore
};

/// What the emulator reports.
struct EmulatorOutputs {
  /// Displacement (x, y) per sensor, m, indexed as FrameMapSpec::sensor_names (the layout of
  /// Observation::sensor_xy_m).
  std::array<std::array<double, 2>, kMaxSensors> sensor_xy_m{};
  bool power_on = true;
  std::uint64_t step = 0;  ///< simulation step index
  double spin_speed_rad_s = 0.0;
  bool in_contact = false;  ///< any touchdown bearing in contact
  std::uint64_t overruns = 0;
};

/// Mutable counts of a frame map's use, owned by the caller.
struct FrameMapCounters {
  std::uint64_t decoded = 0;     ///< frames applied
  std::uint64_t unknown_id = 0;  ///< frames whose id the map does not receive: dropped
  /// Frames of a known id too short for its signals (or RTR): dropped whole.
  std::uint64_t malformed = 0;
  /// Frames with trigger signals none of which matched (normal when a trigger shares a frame
  /// with a steady "no event" value).
  std::uint64_t trigger_no_match = 0;
  std::uint64_t encoded_frames = 0;  ///< frames filled by Encode
  std::uint64_t saturated = 0;       ///< values clamped (or not finite) on encode, all signals
  /// Saturations per signal, indexed as FrameMapSpec::signals.
  std::array<std::uint64_t, kMaxCanSignals> saturated_by_signal{};
};

enum class DecodeResult : std::uint8_t {
  kApplied,    ///< the frame's signals were applied
  kUnknownId,  ///< no incoming signal has this id: counted, ignored
  kMalformed,  ///< known id, but too short (or RTR): counted, ignored
};

/// A frame of the map: its id, format and payload length (for incoming frames, the least
/// length that holds their signals).
struct CanFrameShape {
  std::uint32_t id = 0;
  bool extended = false;
  int len = 0;
};

/// The compiled codec. Copyable; immutable after construction.
class FrameMap {
 public:
  /// An empty map: every frame is unknown, Encode fills nothing.
  FrameMap() = default;
  /// Checks `spec` (ranges, duplicates, overlaps, directions) and builds the lookup tables.
  /// Throws ConfigError naming the signal, its location and the problem.
  explicit FrameMap(FrameMapSpec spec);

  /// Applies a received frame to `*command`. Never throws; unknown and malformed frames are
  /// counted and leave `*command` unchanged.
  [[nodiscard]] DecodeResult Decode(const CanFrame& frame, CanCommand* command,
                                    FrameMapCounters* counters) const noexcept;

  /// Fills the outgoing frames (in id order) from `outputs`; returns how many were written:
  /// output_frame_count(), or fewer if `frames` is shorter.
  std::size_t Encode(const EmulatorOutputs& outputs, std::span<CanFrame> frames,
                     FrameMapCounters* counters) const noexcept;

  std::size_t output_frame_count() const noexcept { return output_frames_.size(); }
  std::size_t input_frame_count() const noexcept { return input_frames_.size(); }
  const FrameMapSpec& spec() const noexcept { return spec_; }

  /// Shapes of the incoming and outgoing frames, in id order.
  std::vector<CanFrameShape> InputFrames() const;
  std::vector<CanFrameShape> OutputFrames() const;
  /// One exact kernel filter per incoming frame (for SocketCanOptions::socket.filters).
  std::vector<CanFilter> InputFilters() const;

 private:
  struct CompiledSignal {
    CanSignalLayout layout;
    CanScaling scaling;
    CanSignalRole role = CanSignalRole::kCurrent;
    int index = 0;
    int axis = 0;
    bool any_frame = false;
    std::uint32_t mask = 0;
    std::uint32_t value = 0;
    int spec_index = 0;  // position in spec_.signals
  };
  struct CompiledFrame {
    std::uint32_t key = 0;  // id | CAN_EFF_FLAG
    std::uint32_t id = 0;
    bool extended = false;
    bool has_trigger = false;
    int len = 0;  // incoming: least length; outgoing: length sent
    int first_signal = 0;
    int signal_count = 0;
  };

  FrameMapSpec spec_;
  std::vector<CompiledSignal> input_signals_;   // grouped by frame
  std::vector<CompiledSignal> output_signals_;  // grouped by frame
  std::vector<CompiledFrame> input_frames_;     // sorted by key
  std::vector<CompiledFrame> output_frames_;    // sorted by key
};

/// Worst-case time of one frame on the bus, s: classic frames by the usual bound with bit
/// stuffing, g + 8n + 13 + floor((g + 8n - 1)/4) bits (g = 34 for 11-bit, 54 for 29-bit ids;
/// interframe space included); FD frames by an estimate of the same kind with the data phase at
/// `data_bitrate_bit_s` when `brs`. For a bus-load check, not for timing analysis.
double CanFrameWorstCaseTime_s(bool extended, bool fd, bool brs, int len, double bitrate_bit_s,
                               double data_bitrate_bit_s) noexcept;

}  // namespace ambdrop
