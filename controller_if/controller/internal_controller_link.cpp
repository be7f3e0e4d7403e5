#include "controller_if/controller/internal_controller_link.hpp"

namespace ambdrop {

InternalControllerLink::InternalControllerLink(const Model& model, double period_s)
    : controller_(model, period_s) {
  controller_.Initial(&scratch_);
  for (int a = 0; a < kMaxAmbs; ++a) pending_.current_A[a] = scratch_.amb[a].current_A;
  has_pending_ = true;
}

bool InternalControllerLink::PollCurrents(CurrentsMessage* out) noexcept {
  if (!has_pending_) return false;
  *out = pending_;
  has_pending_ = false;
  return true;
}

void InternalControllerLink::SendSensors(const SensorReadings& readings, std::int64_t,
                                         double) noexcept {
  controller_.Update(readings, &scratch_);
  for (int a = 0; a < kMaxAmbs; ++a) pending_.current_A[a] = scratch_.amb[a].current_A;
  ++pending_.sequence;
  has_pending_ = true;
}

}  // namespace ambdrop
