#pragma once
// The controller's side of the CAN loop: the config's reference PID answering the emulator's
// sensor frames with current frames, through the same [can] frame map seen from the other end
// (io/can/can_controller_view.hpp). `ambdrop-controller --can IFACE` runs it on a SocketCAN bus;
// tests run it on a CanBusDouble endpoint. Service() does not allocate or throw.
#include <array>
#include <chrono>
#include <cstdint>

#include "controller_if/controller/pid_controller.hpp"
#include "io/can/can_bus.hpp"
#include "io/can/can_controller_view.hpp"

namespace ambdrop {

/// Counts of a CanPidResponder, frames unless said otherwise.
struct CanResponderCounters {
  std::uint64_t frames_received = 0;
  std::uint64_t sensor_sets = 0;  ///< complete sensor samples answered with currents
  std::uint64_t frames_sent = 0;
  std::uint64_t send_drops = 0;   ///< Send returned kDropped
  std::uint64_t send_errors = 0;  ///< Send returned kInvalid or kError
  std::uint64_t receive_errors = 0;
};

/// The reference PID behind a CAN bus: each complete sensor set (CompletesSensors) runs one
/// PID update at `period_s` and sends the current frames at once.
class CanPidResponder {
 public:
  /// `bus` and `view` must outlive the responder. `period_s`: the PID's sample period, the
  /// bus's exchange period.
  CanPidResponder(CanBus* bus, const ControllerFrameView* view, const Model& model,
                  double period_s);

  /// Reads frames, waiting up to `timeout` while no sensor set has completed, and answers each
  /// completed set; returns once a set was answered and no frame is waiting, or when `timeout`
  /// passes with nothing. The number of sets answered.
  int Service(std::chrono::nanoseconds timeout) noexcept;

  /// The emulator's outputs as last decoded (sensors, status).
  const EmulatorOutputs& outputs() const noexcept { return outputs_; }
  const CanResponderCounters& counters() const noexcept { return counters_; }
  const FrameMapCounters& map_counters() const noexcept { return map_counters_; }

 private:
  void Answer() noexcept;

  CanBus* bus_;
  const ControllerFrameView* view_;
  const Model& model_;
  ReferenceController controller_;
  ControlInput input_;
  SensorReadings readings_;
  EmulatorOutputs outputs_;
  CanCommand command_;
  std::array<CanFrame, kMaxCanFrames> tx_{};
  FrameMapCounters map_counters_;
  CanResponderCounters counters_;
};

}  // namespace ambdrop
