#include "tools/hil/can_pid_responder.hpp"

#include <span>

namespace ambdrop {

CanPidResponder::CanPidResponder(CanBus* bus, const ControllerFrameView* view, const Model& model,
                                 double period_s)
    : bus_(bus), view_(view), model_(model), controller_(model, period_s) {}

void CanPidResponder::Answer() noexcept {
  readings_.reading_m = outputs_.sensor_xy_m;
  controller_.Update(readings_, &input_);
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
    command_.current_A[a] = input_.amb[a].current_A;
  }
  const std::size_t count =
      view_->EncodeCurrents(command_, std::span<CanFrame>(tx_), &map_counters_);
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
  ++counters_.sensor_sets;
}

int CanPidResponder::Service(std::chrono::nanoseconds timeout) noexcept {
  int answered = 0;
  CanFrame frame;
  for (;;) {
    const CanStatus status =
        bus_->Receive(&frame, answered > 0 ? std::chrono::nanoseconds(0) : timeout);
    if (status == CanStatus::kError) ++counters_.receive_errors;
    if (status != CanStatus::kOk) return answered;
    ++counters_.frames_received;
    if (view_->Decode(frame, &outputs_, &map_counters_) == DecodeResult::kApplied &&
        view_->CompletesSensors(frame)) {
      Answer();
      ++answered;
    }
  }
}

}  // namespace ambdrop
