#include "tools/fit/fit_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <vector>

#include "tools/fit/effect_selection.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {
namespace {

double MedianInterval(const std::vector<double>& t) {
  std::vector<double> d;
  for (std::size_t i = 1; i < t.size(); ++i) d.push_back(t[i] - t[i - 1]);
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

}  // namespace

FitStep ChooseFitStep(const ModelParams& declared, const MeasurementParams& measurement,
                      const MeasuredRecord& record, const RecordRunOptions& run,
                      const FitStepRules& rules) {
  FitStep out;
  out.declared_s = run.step_s > 0.0 ? run.step_s : declared.simulation.step_s;
  out.step_s = out.declared_s;
  const double sample_s = MedianInterval(record.time_s);
  RecordRunOptions fine = run;
  fine.step_s = out.declared_s;
  // The parts the verdict judges; the early one and the speeds may be empty.
  std::vector<RecordCost> costs;
  costs.emplace_back(declared, measurement, record, fine);
  for (const CostScope scope : {CostScope::kEarly, CostScope::kSpeeds}) {
    costs.emplace_back(declared, measurement, record, fine, 3000, scope);
    if (costs.back().size() == 0) costs.pop_back();
  }
  const SimulatedRecord at_declared = SimulateOnRecord(declared, measurement, record, fine);
  if (at_declared.status != StepStatus::kOk) {
    out.why = "the declared model stops early on the record at its own step: kept";
    return out;
  }
  std::vector<Eigen::VectorXd> reference;
  for (const RecordCost& c : costs) reference.push_back(c.Residual(at_declared));
  std::string stopped = "the largest tried";
  for (int factor = 2; factor <= rules.max_factor; factor *= 2) {
    const double coarse = out.declared_s * factor;
    if (coarse > 0.5 * sample_s) {
      stopped = fmt::format("{:.3g} s would exceed half the record's sample interval", coarse);
      break;
    }
    RecordRunOptions o = run;
    o.step_s = coarse;
    SimulatedRecord sim;
    try {
      sim = SimulateOnRecord(declared, measurement, record, o);
    } catch (const std::exception& e) {
      // A step the model refuses (a controller period that is no whole number of steps).
      stopped = fmt::format("the model does not take {:.3g} s ({})", coarse, e.what());
      break;
    }
    if (sim.status != StepStatus::kOk) {
      stopped = fmt::format("{:.3g} s stops early", coarse);
      break;
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < costs.size(); ++i) {
      const double move =
          OverallRms(costs[i], (costs[i].Residual(sim) - reference[i]).squaredNorm());
      const double noise = costs[i].NoiseFloor();
      worst = std::max(worst, noise > 0.0 ? move / noise : (move > 0.0 ? 1e300 : 0.0));
    }
    if (worst > rules.max_move_over_noise) {
      stopped = fmt::format("{:.3g} s moves it by {:.2g} noise floors", coarse, worst);
      break;
    }
    out.step_s = coarse;
    out.move_over_noise = worst;
  }
  out.why = out.step_s == out.declared_s
                ? fmt::format("the declared step {:.3g} s: {}", out.declared_s, stopped)
                : fmt::format(
                      "{:.3g} s ({} declared steps) moves the prediction by {:.2g} of the "
                      "record's noise floor (at most {:.2g}); {}",
                      out.step_s, static_cast<int>(std::lround(out.step_s / out.declared_s)),
                      out.move_over_noise, rules.max_move_over_noise, stopped);
  return out;
}

}  // namespace ambdrop
