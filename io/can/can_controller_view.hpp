#pragma once
// The frame map (io/can/can_frame_map.hpp) seen from the controller's side of the bus: it decodes
// what the emulator sends (sensors_out, status_out) and encodes what the emulator receives
// (currents_in, and trigger_in frames for test benches that drop the rotor over CAN). The same
// [can] table thus configures both ends, and a round trip through both is the identity up to
// the scales' quantisation.
//
// Built once from a validated FrameMap (setup: allocates); Decode and the Encode calls are
// noexcept and allocation-free. Counts go to a caller-owned FrameMapCounters (decoded,
// unknown_id, malformed, encoded_frames, saturated) with the same meaning as on the emulator's
// side.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "io/can/can_frame_map.hpp"

namespace ambdrop {

/// The controller's codec of a frame map: the map's directions reversed.
class ControllerFrameView {
 public:
  explicit ControllerFrameView(const FrameMap& map);

  /// Applies a frame the emulator sent to `*outputs`: sensor displacements (m), spin speed
  /// (rad/s), power_on, in_contact, and the step and overrun counters (their low bytes only:
  /// they wrap on the wire). Unknown ids and frames too short for their signals (or RTR) are
  /// counted and leave `*outputs` unchanged.
  [[nodiscard]] DecodeResult Decode(const CanFrame& frame, EmulatorOutputs* outputs,
                                    FrameMapCounters* counters) const noexcept;

  /// True when `frame` is the last frame of the emulator's sensor set (the highest id that
  /// carries a sensor signal; the emulator sends its frames in id order, which is also CAN's
  /// arbitration order), so a controller runs its control law once per exchange.
  bool CompletesSensors(const CanFrame& frame) const noexcept;

  /// Fills the current frames (in id order) from `command.current_A`; returns how many were
  /// written: current_frame_count(), or fewer if `frames` is shorter. Values beyond a signal's
  /// raw range saturate and are counted. A trigger signal that shares a current frame is left
  /// at raw 0.
  std::size_t EncodeCurrents(const CanCommand& command, std::span<CanFrame> frames,
                             FrameMapCounters* counters) const noexcept;

  /// A frame the emulator decodes as a power failure (`restore` false) or a power restore
  /// (true): the trigger's value in its masked bits, other bytes 0. False if the map has no such
  /// trigger.
  bool EncodeTrigger(bool restore, CanFrame* frame) const noexcept;

  std::size_t current_frame_count() const noexcept { return current_frames_.size(); }
  /// Kernel filters that pass exactly the frames the emulator sends.
  std::vector<CanFilter> InputFilters() const;

 private:
  struct Signal {
    CanSignalLayout layout;
    CanScaling scaling;
    CanSignalRole role = CanSignalRole::kCurrent;
    int index = 0;
    int axis = 0;
    int spec_index = 0;
  };
  struct Frame {
    std::uint32_t key = 0;  // id | CAN_EFF_FLAG
    std::uint32_t id = 0;
    bool extended = false;
    int len = 0;  // incoming: least length; outgoing: length sent
    int first_signal = 0;
    int signal_count = 0;
  };
  struct Trigger {
    bool present = false;
    CanSignalLayout layout;
    bool any_frame = false;
    std::uint32_t value = 0;
    int len = 0;
  };

  bool fd_ = false;
  bool brs_ = false;
  std::vector<Signal> input_signals_;  // sensors and status, grouped by frame
  std::vector<Frame> input_frames_;    // sorted by key
  std::vector<Signal> current_signals_;
  std::vector<Frame> current_frames_;  // sorted by key
  std::uint32_t last_sensor_key_ = 0;
  bool has_sensors_ = false;
  Trigger fail_;
  Trigger restore_;
};

}  // namespace ambdrop
