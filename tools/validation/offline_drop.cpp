#include "tools/validation/offline_drop.hpp"

#include "controller_if/loop/offline_run.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "tools/validation/run_summary.hpp"

namespace ambdrop {

OfflineDrop RunOfflineDrop(const std::string& config_path,
                           const std::vector<std::string>& overrides, double late_after_trigger_s) {
  const ModelParams p = LoadConfig(config_path, overrides).params;
  const Model model = BuildModel(p);
  RunSummary summary(p);
  TdbPeakTracker peaks(p, p.trigger.time_s + late_after_trigger_s);
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    summary.Add(o);
    if (o.time_s >= p.trigger.time_s) peaks.Add(o);
  });
  OfflineDrop d;
  d.ok = r.status == StepStatus::kOk;
  d.failure_message = r.failure_message;
  d.tdbs = peaks.tdbs();
  for (std::size_t i = 0; i < p.tdbs.size(); ++i) d.whirl.push_back(summary.Whirl(i));
  return d;
}

}  // namespace ambdrop
