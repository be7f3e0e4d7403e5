#include "tools/fit/jitter_draws.hpp"

#include <algorithm>
#include <vector>

#include "tools/fit/drop_features.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/parallel_for.hpp"

namespace ambdrop {
namespace {

// "backward_whirl at nde and de", or each plane's own where they differ.
std::string ModeText(const std::vector<PlaneWhirl>& planes, bool record) {
  const auto kind = [&](const PlaneWhirl& p) { return (record ? p.record : p.model).kind; };
  const bool same = std::all_of(planes.begin(), planes.end(), [&](const PlaneWhirl& p) {
    return kind(p) == kind(planes.front());
  });
  std::string text;
  if (same) {
    text = std::string(WhirlName(kind(planes.front()))) + " at ";
    for (std::size_t i = 0; i < planes.size(); ++i) {
      text += (i == 0 ? "" : i + 1 == planes.size() ? " and " : ", ") + planes[i].plane;
    }
    return text;
  }
  for (const PlaneWhirl& p : planes) {
    text += (text.empty() ? "" : ", ") + std::string(WhirlName(kind(p))) + " at " + p.plane;
  }
  return text;
}

bool SameMode(const std::vector<PlaneWhirl>& planes) {
  return std::all_of(planes.begin(), planes.end(),
                     [](const PlaneWhirl& p) { return p.record.kind == p.model.kind; });
}

}  // namespace

JitterDraws DrawJitter(const RecordCost& cost, const RecordCost& judged, double judged_limit,
                       int max_draws, int threads) {
  JitterDraws d;
  const ModelParams& params = cost.declared();
  const MeasurementParams& m = cost.measurement();
  const MeasuredRecord& r = cost.record();
  // Open loop no controller answers the noise; with measurement.trigger_state = "record" the
  // state at the trigger is the record's own, estimated from its lead window (whose
  // uncertainty the start sensitivity spans), so a drawn jitter would be replaced there.
  if (!ClosedLoop(params, m, cost.run_options()) || m.trigger_state_from_record) return d;
  // The record's jitter: what its controller answers.
  d.jitter_sigma_m = DisplacementNoiseMedian(cost);
  if (!(d.jitter_sigma_m > 0.0)) return d;
  const std::vector<PlaneWhirl> planes = ComparePlaneWhirls(params, m, r, cost.Simulate(params));
  d.mode_differs = !planes.empty() && !SameMode(planes);
  if (!planes.empty()) {
    d.record_mode = ModeText(planes, true);
    d.model_mode = ModeText(planes, false);
  }
  d.ran = true;
  constexpr int kBatch = 4;
  for (int first = 1; first <= max_draws && d.first_within == 0 && d.first_match == 0;
       first += kBatch) {
    const int count = std::min(kBatch, max_draws - first + 1);
    std::vector<char> match(static_cast<std::size_t>(count), 0);
    std::vector<double> rms(match.size(), 0.0);
    ParallelFor(match.size(), threads, [&](std::size_t i) {
      RecordRunOptions o = cost.run_options();
      o.jitter_sigma_m = d.jitter_sigma_m;
      o.jitter_seed = static_cast<std::uint64_t>(first) + i;
      const SimulatedRecord run = SimulateOnRecord(params, m, r, o);
      match[i] = d.mode_differs && SameMode(ComparePlaneWhirls(params, m, r, run));
      rms[i] = OverallRms(judged, judged.Residual(run).squaredNorm());
    });
    for (std::size_t i = 0; i < match.size(); ++i) {
      const int run = first + static_cast<int>(i);
      if (d.first_within == 0 && rms[i] <= judged_limit) {
        d.first_within = run;
        d.within_rms = rms[i];
      }
      if (d.first_match == 0 && match[i]) {
        d.first_match = run;
        d.match_rms = rms[i];
      }
    }
    d.draws += count;
  }
  return d;
}

}  // namespace ambdrop
