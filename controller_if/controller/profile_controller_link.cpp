#include "controller_if/controller/profile_controller_link.hpp"

#include "controller_if/controller/current_profile.hpp"

namespace ambdrop {

ProfileControllerLink::ProfileControllerLink(const Model& model) {
  for (const AmbParams& amb : model.params.ambs) profiles_.push_back(amb.current_profile);
  Fill(0.0);
}

void ProfileControllerLink::Fill(double time_s) noexcept {
  for (std::size_t a = 0; a < profiles_.size(); ++a) {
    pending_.current_A[a] = CurrentAt(profiles_[a], time_s);
  }
  ++pending_.sequence;
  has_pending_ = true;
}

bool ProfileControllerLink::PollCurrents(CurrentsMessage* out) noexcept {
  if (!has_pending_) return false;
  *out = pending_;
  has_pending_ = false;
  return true;
}

void ProfileControllerLink::SendSensors(const SensorReadings&, std::int64_t,
                                        double time_s) noexcept {
  Fill(time_s);
}

}  // namespace ambdrop
