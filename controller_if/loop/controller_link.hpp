#pragma once
#include <array>
#include <chrono>
#include <cstdint>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop {

/// One sample of control currents as the controller sent it.
struct CurrentsMessage {
  std::array<std::array<double, 2>, kMaxAmbs> current_A{};  ///< (x, y) per AMB, A
  std::uint64_t sequence = 0;
  std::int64_t receive_ns = 0;  ///< clock time it arrived (ns)
};

/// What the controller sees of ambdrop: currents in, sensor readings out. Implementations: the
/// in-process reference controller, LCM, SocketCAN (and its double). Both calls are non-blocking,
/// allocation-free and noexcept: they run on the real-time thread.
class ControllerLink {
 public:
  virtual ~ControllerLink() = default;
  /// The newest currents that arrived since the last call; false if none did.
  virtual bool PollCurrents(CurrentsMessage* out) noexcept = 0;
  /// One sample of the sensors for the controller (dropped and counted if the link is full).
  virtual void SendSensors(const SensorReadings& readings, std::int64_t step,
                           double time_s) noexcept = 0;
  /// Lock step (`ambdrop hil --virtual-clock --lockstep`): waits until the controller's answer
  /// to the last sample sent has arrived, at most `timeout`; true if it has (or no answer is
  /// due: the in-process controller, a sample the link did not send). Not for the real-time
  /// loop, which never waits on the controller.
  virtual bool AwaitAnswer(std::chrono::nanoseconds timeout) noexcept {
    (void)timeout;
    return true;
  }
  /// The emulator's state at the sample SendSensors is about to send, for links that report
  /// status besides the sensors (CAN's status frame: power, spin, contact). Called just before
  /// each SendSensors; links without a status channel ignore it.
  virtual void ObserveState(const Observation& observation) noexcept { (void)observation; }
};

/// A source of power events (GPIO edge, CAN or LCM message, a scheduled time). Polled once per
/// controller period on the real-time thread: non-blocking, allocation-free, noexcept.
class TriggerSource {
 public:
  virtual ~TriggerSource() = default;
  /// The next pending event at `time_s` (run time, s); false if none.
  virtual bool Poll(double time_s, PowerEvent* out) noexcept = 0;
};

/// Power fails at a run time (and may come back later): `ambdrop hil --trigger at:SECONDS`.
class ScheduledTrigger final : public TriggerSource {
 public:
  ScheduledTrigger(double fail_time_s, PowerEvent failure, double restore_time_s = -1.0,
                   PowerEvent restore = {});
  bool Poll(double time_s, PowerEvent* out) noexcept override;

 private:
  double fail_time_s_;
  double restore_time_s_;
  PowerEvent failure_;
  PowerEvent restore_;
  int fired_ = 0;
};

}  // namespace ambdrop
