#pragma once
#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/controller_link.hpp"

namespace ambdrop {

/// The reference controller behind the ControllerLink interface: it computes new currents as
/// soon as a sensor sample arrives, and they are collected at the next period, as an external
/// controller's would be after one sample of transport.
class InternalControllerLink final : public ControllerLink {
 public:
  InternalControllerLink(const Model& model, double period_s);
  bool PollCurrents(CurrentsMessage* out) noexcept override;
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override;

 private:
  ReferenceController controller_;
  ControlInput scratch_;
  CurrentsMessage pending_;
  bool has_pending_ = false;
};

}  // namespace ambdrop
