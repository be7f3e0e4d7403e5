#pragma once
#include "controller_if/loop/controller_link.hpp"
#include "io/lcm/lcm_transport.hpp"

namespace ambdrop {

/// The controller over LCM: currents and power events from the endpoint's receive rings,
/// sensor readings into its publish ring. The endpoint's threads do the LCM work; these calls
/// only touch the rings (real-time safe).
class LcmControllerLink final : public ControllerLink, public TriggerSource {
 public:
  explicit LcmControllerLink(LcmEndpoint* endpoint, int sensor_count)
      : endpoint_(endpoint), sensor_count_(sensor_count) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override;
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override;
  bool Poll(double time_s, PowerEvent* out) noexcept override;
  /// Lock step: polls the receive ring until currents answer the last sample sent.
  bool AwaitAnswer(std::chrono::nanoseconds timeout) noexcept override;

 private:
  LcmEndpoint* endpoint_;
  int sensor_count_;
  std::int64_t samples_sent_ = 0;
  std::int64_t samples_answered_ = 0;
};

}  // namespace ambdrop
