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

FitStep ChooseFitStep(const ConfigVariants& config, const MeasurementParams& measurement,
                      const MeasuredRecord& record, const RecordRunOptions& run,
                      const SelectionRules& selection, const FitStepRules& rules) {
  const ModelParams& declared = config.declared().params;
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
  // Each part's residual of the declared model run at `step_s`; false if the run stops early.
  const auto residuals_at = [&](double step_s, std::vector<Eigen::VectorXd>* out_residuals) {
    RecordRunOptions o = fine;
    o.step_s = step_s;
    const SimulatedRecord sim = SimulateOnRecord(declared, measurement, record, o);
    if (sim.status != StepStatus::kOk) return false;
    for (const RecordCost& c : costs) out_residuals->push_back(c.Residual(sim));
    return true;
  };
  std::vector<Eigen::VectorXd> reference;
  if (!residuals_at(out.declared_s, &reference)) {
    out.why = "the declared model stops early on the record at its own step: kept";
    return out;
  }
  // The converged prediction the step term is measured from: half the declared step, as the
  // selection measures it at the declared step.
  std::vector<Eigen::VectorXd> converged;
  if (!residuals_at(0.5 * out.declared_s, &converged)) {
    out.why = "the declared model stops early on the record at half its step: kept";
    return out;
  }
  const auto step_term = [&](std::size_t i, const Eigen::VectorXd& residual) {
    return OverallRms(costs[i], (residual - converged[i]).squaredNorm());
  };
  // Each part's limit from its noise and model floor (AgreementLimit).
  const auto limit = [&](double noise, double model_floor) {
    Selection s;
    s.noise_floor = noise;
    s.model_floor = model_floor;
    return AgreementLimit(s, selection);
  };
  std::vector<double> start;
  std::vector<double> step;
  for (std::size_t i = 0; i < costs.size(); ++i) {
    start.push_back(StartSensitivity(config, costs[i], reference[i], selection.threads,
                                     std::min(kStartJitterDraws, selection.jitter_draws)));
    step.push_back(step_term(i, reference[i]));
  }
  const std::vector<double> declared_step = step;
  // What max_move_over_noise noise floors widen a limit of noise alone by.
  const double allowed = limit(1.0, rules.max_move_over_noise) / limit(1.0, 0.0);
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
    double widest = 1.0;
    std::vector<double> coarse_step;
    for (std::size_t i = 0; i < costs.size(); ++i) {
      const Eigen::VectorXd residual = costs[i].Residual(sim);
      const double move = OverallRms(costs[i], (residual - reference[i]).squaredNorm());
      const double noise = costs[i].NoiseFloor();
      worst = std::max(worst, noise > 0.0 ? move / noise : (move > 0.0 ? 1e300 : 0.0));
      coarse_step.push_back(step_term(i, residual));
      // The drop's start is deterministic: its start sensitivity is the uncertain trigger
      // state, a shift the fits all share, not chaos that hides a bias. There the step's move
      // is held to the noise alone: on the magnet-biased flexible rig a 4x step moved the start
      // by 0.6 noise floors, within its 6.7 floors of start sensitivity, and the unbalance
      // fits on it came out 2.5x worse.
      const double spread = costs[i].scope() == CostScope::kEarly ? 0.0 : start[i];
      const double with = limit(noise, std::max(spread, coarse_step.back()));
      const double declared_limit_i = limit(noise, std::max(spread, declared_step[i]));
      widest = std::max(
          widest, declared_limit_i > 0.0 ? with / declared_limit_i : (with > 0.0 ? 1e300 : 1.0));
    }
    if (widest > allowed) {
      stopped = fmt::format(
          "{:.3g} s moves it by {:.2g} noise floors, which would widen the agreement limit by "
          "{:.2g} %",
          coarse, worst, 100.0 * (widest - 1.0));
      break;
    }
    out.step_s = coarse;
    out.move_over_noise = worst;
    out.limit_widening = widest;
    step = coarse_step;
  }
  for (std::size_t i = 0; i < costs.size(); ++i) {
    ModelFloors::Part& part = costs[i].scope() == CostScope::kEarly    ? out.floors.early
                              : costs[i].scope() == CostScope::kSpeeds ? out.floors.speeds
                                                                       : out.floors.whole;
    part.start_sensitivity = start[i];
    part.step_sensitivity = step[i];
  }
  out.why = out.step_s == out.declared_s
                ? fmt::format("the declared step {:.3g} s: {}", out.declared_s, stopped)
                : fmt::format(
                      "{:.3g} s ({} declared steps) moves the prediction by {:.2g} of the "
                      "record's noise floor and widens the agreement limit by {:.2g} % (at most "
                      "{:.2g} %, what {:.2g} noise floors would; after the first impacts a move "
                      "within the model's sensitivity to its start widens it not at all); {}",
                      out.step_s, static_cast<int>(std::lround(out.step_s / out.declared_s)),
                      out.move_over_noise, 100.0 * (out.limit_widening - 1.0),
                      100.0 * (allowed - 1.0), rules.max_move_over_noise, stopped);
  return out;
}

}  // namespace ambdrop
