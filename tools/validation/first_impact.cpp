#include "tools/validation/first_impact.hpp"

#include <algorithm>

#include "controller_if/loop/offline_run.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

void ImpactTracker::Add(double time_s, double y_m, const TdbForce& f) {
  static constexpr double kMinFlight = 0.5e-3;
  static constexpr double kMinRise = 5e-6;  // a knocked-away light race is not a rebound
  const bool contact = f.normal_force_N > 0.0;
  switch (phase_) {
    case kFalling:
      if (!contact) return;
      phase_ = kFirstContact;
      r_.bottom_m = y_m;
      r_.top_m = y_m;
      [[fallthrough]];
    case kFirstContact:
      r_.peak_support_N = std::max(r_.peak_support_N, f.support_force_N());
      r_.peak_normal_N = std::max(r_.peak_normal_N, f.normal_force_N);
      if (y_m < r_.bottom_m) {
        r_.bottom_m = y_m;
        r_.top_m = y_m;
      }
      r_.top_m = std::max(r_.top_m, y_m);
      if (contact) {
        last_contact_s_ = time_s;
      } else if (time_s - last_contact_s_ >= kMinFlight && y_m > r_.bottom_m + kMinRise) {
        phase_ = kFlight;
      }
      return;
    case kFlight:
      if (contact) {
        phase_ = kDone;
        r_.complete = true;
        return;
      }
      r_.top_m = std::max(r_.top_m, y_m);
      return;
    case kDone:
      return;
  }
}

DropAtRestResult DropAtRest(const std::string& config_path, std::vector<std::string> overrides) {
  overrides.insert(overrides.end(),
                   {"simulation.spin_speed_rad_s=0.0", "trigger.time_s=0.02",
                    "simulation.duration_s=0.12", "simulation.output_interval_s=5e-6"});
  const ModelParams p = LoadConfig(config_path, overrides).params;
  const Model model = BuildModel(p);
  std::vector<ImpactTracker> trackers(p.tdbs.size());
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    if (o.time_s < p.trigger.time_s) return;
    for (std::size_t i = 0; i < trackers.size(); ++i) {
      trackers[i].Add(o.time_s, o.tdb_journal_xy_m[i][1], o.tdb[i]);
    }
  });
  DropAtRestResult d;
  d.ok = r.status == StepStatus::kOk;
  d.failure_message = r.failure_message;
  for (std::size_t i = 0; i < trackers.size(); ++i) {
    d.names.push_back(p.tdbs[i].name);
    d.impacts.push_back(trackers[i].result());
  }
  return d;
}

}  // namespace ambdrop
