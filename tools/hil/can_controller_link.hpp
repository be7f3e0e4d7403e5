#pragma once
// The controller over CAN: currents and power events come in as frames of the [can] frame map,
// sensor readings and status go out as frames. It joins controller_if's ControllerLink and
// TriggerSource to io's CanBus and FrameMap, so it lives in tools/.
//
// Every call runs on the real-time thread: non-blocking Send/Receive on the bus (a system call
// each on SocketCAN), decode and encode into fixed-size buffers; no allocation, no exceptions.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "controller_if/loop/controller_link.hpp"
#include "io/can/can_bus.hpp"
#include "io/can/can_frame_map.hpp"

namespace ambdrop {

/// Counts of a CanControllerLink since it was built, frames unless said otherwise.
struct CanLinkCounters {
  std::uint64_t frames_received = 0;     ///< frames read off the bus
  std::uint64_t decoded = 0;             ///< of which applied by the frame map
  std::uint64_t unknown_id = 0;          ///< of which with an id the map does not receive
  std::uint64_t malformed = 0;           ///< of which too short for their signals, or RTR
  std::uint64_t trigger_no_match = 0;    ///< trigger frames whose value meant no event
  std::uint64_t receive_errors = 0;      ///< Receive returned kError (the bus says why)
  std::uint64_t frames_sent = 0;         ///< Send returned kOk
  std::uint64_t send_drops = 0;          ///< Send returned kDropped (transmit queue full)
  std::uint64_t send_errors = 0;         ///< Send returned kInvalid or kError
  std::uint64_t exchanges_sent = 0;      ///< sensor samples sent as a full set of frames
  std::uint64_t samples_decimated = 0;   ///< sensor samples not sent (above the exchange rate)
  std::uint64_t encode_saturations = 0;  ///< values clamped to a signal's raw range on encode
  std::uint64_t power_events = 0;        ///< power events queued for Poll
  std::uint64_t power_events_lost = 0;   ///< oldest queued events overwritten (ring full)
};

/// How a CanControllerLink uses its bus.
struct CanLinkOptions {
  /// The controller period of the session (s): SendSensors is called once per period.
  double controller_period_s = 0.0;
  /// Frames of each id per second ([can].exchange_rate_Hz). When the controller rate is higher
  /// it must be a whole multiple of this rate, and only every n-th sample is sent.
  double exchange_rate_Hz = 0.0;
  /// TDBs of the model: status in_contact is any of them with a normal force.
  int tdb_count = 0;
};

/// ControllerLink and TriggerSource over a CanBus and a FrameMap.
///   PollCurrents: drains the bus without blocking, decodes every frame; currents are held
///     between frames (each AMB axis keeps its last value) and reported with the receive time
///     of the newest current frame.
///   Poll (trigger): power_fail / power_restore frames, queued as PowerEvents in a ring of
///     kEventCapacity as they are decoded, so none is lost between polls (when full, the oldest
///     is overwritten and counted: the newest say what the power is now).
///   SendSensors: every n-th sample (n = controller rate / exchange rate, at least 1) encodes
///     the sensors and the status (power_on, step_counter, spin_speed and in_contact from
///     ObserveState; overrun_counter is not known to the link and is sent as 0) and sends the
///     frames in id order. A full transmit queue drops the frame and counts it.
/// A link used only as a trigger (`--trigger can` beside another controller) never sends.
class CanControllerLink final : public ControllerLink, public TriggerSource {
 public:
  static constexpr std::size_t kEventCapacity = 16;

  /// `bus` and `map` must outlive the link. Throws std::invalid_argument when the controller
  /// rate is above the exchange rate but not a whole multiple of it.
  CanControllerLink(CanBus* bus, const FrameMap* map, const CanLinkOptions& options);

  bool PollCurrents(CurrentsMessage* out) noexcept override;
  void ObserveState(const Observation& observation) noexcept override;
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override;
  bool Poll(double time_s, PowerEvent* out) noexcept override;

  /// Waits up to `timeout` for one frame and decodes it, then drains the rest without waiting;
  /// true if any frame came. For lock-step runs (tests, a synchronous controller); the loop
  /// itself never waits on the bus.
  bool WaitForFrames(std::chrono::nanoseconds timeout) noexcept;
  /// Lock step: waits (WaitForFrames) until currents answer the last exchange sent.
  bool AwaitAnswer(std::chrono::nanoseconds timeout) noexcept override;

  /// Sensor samples per exchange (1: every sample is sent).
  std::int64_t send_every() const noexcept { return send_every_; }
  CanLinkCounters counters() const noexcept;
  const CanCommand& command() const noexcept { return command_; }

 private:
  void Drain() noexcept;
  void Apply(const CanFrame& frame) noexcept;
  void PushEvent(const PowerEvent& event) noexcept;

  CanBus* bus_;
  const FrameMap* map_;
  int tdb_count_;
  std::int64_t send_every_ = 1;
  std::int64_t samples_ = 0;
  CanCommand command_;
  FrameMapCounters map_counters_;
  CanLinkCounters counters_;
  bool fresh_currents_ = false;
  std::uint64_t answered_exchanges_ = 0;  // exchanges whose answer AwaitAnswer has seen
  std::int64_t currents_receive_ns_ = 0;
  std::vector<std::uint32_t> current_keys_;  // sorted keys of frames that carry currents
  EmulatorOutputs outputs_;
  std::array<CanFrame, kMaxCanFrames> tx_{};
  std::array<PowerEvent, kEventCapacity> events_{};
  std::size_t event_head_ = 0;
  std::size_t event_count_ = 0;
};

}  // namespace ambdrop
