#include "tools/fit/fit_record.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "io/files/measured_csv.hpp"
#include "tools/fit/effect_selection.hpp"

namespace ambdrop {

std::unique_ptr<FitResult> FitRecord(const ConfigVariants& config, const MeasurementParams& m,
                                     const MeasuredRecord& record,
                                     const FitRecordOptions& options) {
  const ModelParams& declared = config.declared().params;
  auto fit = std::make_unique<FitResult>();
  RecordRunOptions run = options.run;
  if (!run.rotor_cache) run.rotor_cache = std::make_shared<ReducedRotorCache>();
  if (!run.prefix_cache) run.prefix_cache = std::make_shared<LevitatedPrefixCache>();
  if (options.choose_step) {
    fit->step = ChooseFitStep(config, m, record, run, options.rules);
  } else {
    fit->step.declared_s = fit->step.step_s =
        run.step_s > 0.0 ? run.step_s : declared.simulation.step_s;
    fit->step.why = "the declared step, as asked";
  }
  run.step_s = fit->step.step_s;
  // A second opinion on a departing start (closed loop from the model's own levitated state):
  // where the declared model departs at the drop's start but agrees there from the lead
  // window's estimate of the state at the trigger, the departure is the rotor's jitter when
  // the power failed, and the fit takes the start from the record (trigger_state =
  // "record_start"). Twice the median of drawn jitters spans most records, not the tail.
  MeasurementParams measurement = m;
  std::string second_opinion;
  if (!m.trigger_state_from_record && !m.trigger_state_for_start && ClosedLoop(declared, m, run) &&
      options.rules.jitter_draws > 0) {
    const auto start_and_limit = [&](const MeasurementParams& mm) {
      const RecordCost early(declared, mm, record, run, 3000, CostScope::kEarly);
      const Eigen::VectorXd r = early.Residual(declared);
      const double sens = StartSensitivity(config, early, r, options.rules.threads,
                                           std::min(kStartJitterDraws, options.rules.jitter_draws));
      const double limit = std::hypot(options.rules.explained_over_floor * early.NoiseFloor(),
                                      options.rules.model_floor_factor * sens);
      return std::pair<double, double>{OverallRms(early, r.squaredNorm()), limit};
    };
    const auto [own, own_limit] = start_and_limit(m);
    if (own > own_limit) {
      MeasurementParams estimated = m;
      estimated.trigger_state_for_start = true;
      const auto [from_record, record_limit] = start_and_limit(estimated);
      if (from_record <= record_limit) {
        measurement = estimated;
        second_opinion = fmt::format(
            "the drop's start departs from the model's own levitated state ({:.3g}, limit "
            "{:.3g}) and agrees from the lead window's estimate of the state at the trigger "
            "({:.3g}, limit {:.3g}): the rotor's jitter when the power failed; the start is "
            "taken from the record (trigger_state = \"record_start\")",
            own, own_limit, from_record, record_limit);
      }
    }
  }
  if (!second_opinion.empty() && options.choose_step) {
    // The parts' floors were measured with the model's own state at the start; the fit now
    // runs the start from the estimate, whose uncertainty its floor must span.
    RecordRunOptions declared_run = options.run;
    declared_run.rotor_cache = run.rotor_cache;
    declared_run.prefix_cache = run.prefix_cache;
    fit->step = ChooseFitStep(config, measurement, record, declared_run, options.rules);
    run.step_s = fit->step.step_s;
  }
  fit->measurement = measurement;
  const RecordCost cost(declared, measurement, record, run);
  fit->sensor_noise = cost.sensor_noise();
  for (const std::size_t c : cost.left_out()) {
    fit->left_out.push_back(
        fmt::format("'{}' ({})", m.channels[c].column, m.channels[c].Describe(declared)));
  }
  // Without a channel the residual is empty and any model "already within 0 of the record".
  if (cost.channels() == 0) {
    throw MeasuredRecordError(fmt::format(
        "{}: no channel of the record moves beyond its noise{}: there is nothing to hold the "
        "model against",
        record.source,
        fit->left_out.empty() ? std::string()
                              : fmt::format(" ({})", fmt::join(fit->left_out, ", "))));
  }
  fit->before = cost.Simulate(declared);
  // Its residual would score every sample it did not reach a full range off, and its step and
  // start sensitivities, from runs as broken, once widened the agreement limit past that:
  // a declared model that diverged 12 ms after the trigger was "already within 0.709 of the
  // record, inside the agreement limit 1.42", no effect needed.
  if (fit->before.status != StepStatus::kOk) {
    throw DeclaredModelStopped(fmt::format(
        "{}: the declared model does not run to the record's end at the fit's step ({:.3g} s): "
        "{}\nA model that cannot run the record cannot be held against it: make it run "
        "(`ambdrop sim` with the same config), then fit again",
        record.source, fit->step.step_s, fit->before.failure));
  }
  fit->library = EffectLibrary(config);
  fit->selection = SelectEffects(config, cost, fit->library, cost.NoiseFloor(), options.rules,
                                 options.choose_step ? &fit->step.floors : nullptr);
  if (!second_opinion.empty())
    fit->selection.reason = second_opinion + "; " + fit->selection.reason;
  for (const std::string& name : fit->selection.chosen) {
    for (const Effect& e : fit->library) {
      if (e.name == name) fit->chosen.push_back(&e);
    }
  }
  fit->fitted_overrides = EffectOverrides(fit->chosen, fit->selection.chosen_fit.values);
  fit->fitted = config.With(fit->fitted_overrides).params;
  fit->after = cost.Simulate(fit->fitted);
  fit->residual_before =
      ComputeResiduals(declared, measurement, record, fit->before, cost.compare_from_s());
  fit->residual_after =
      ComputeResiduals(declared, measurement, record, fit->after, cost.compare_from_s());
  fit->residual_before.overall = fit->selection.whole.rms_before;
  const auto share = [&](const SimulatedRecord& sim, ResidualReport* report) {
    const std::vector<double> sse = cost.ChannelSse(cost.Residual(sim));
    double total = 0.0;
    for (const double v : sse) total += v;
    for (std::size_t c = 0; c < sse.size() && c < report->channels.size(); ++c) {
      report->channels[c].cost_share = total > 0.0 ? sse[c] / total : 0.0;
    }
  };
  share(fit->before, &fit->residual_before);
  share(fit->after, &fit->residual_after);
  fit->residual_after.overall = OverallRms(cost, cost.Residual(fit->after).squaredNorm());
  return fit;
}

const ParameterEstimate* ChosenParameter(const FitResult& fit, const std::string& effect,
                                         const std::string& name) {
  for (const ParameterEstimate& p : fit.selection.chosen_fit.parameters) {
    if (p.effect == effect && p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace ambdrop
