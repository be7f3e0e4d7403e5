#include "tools/fit/fit_record.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/files/measured_csv.hpp"

namespace ambdrop {

std::unique_ptr<FitResult> FitRecord(const ConfigVariants& config, const MeasurementParams& m,
                                     const MeasuredRecord& record,
                                     const FitRecordOptions& options) {
  const ModelParams& declared = config.declared().params;
  auto fit = std::make_unique<FitResult>();
  RecordRunOptions run = options.run;
  if (!run.rotor_cache) run.rotor_cache = std::make_shared<ReducedRotorCache>();
  if (options.choose_step) {
    fit->step = ChooseFitStep(config, m, record, run, options.rules);
  } else {
    fit->step.declared_s = fit->step.step_s =
        run.step_s > 0.0 ? run.step_s : declared.simulation.step_s;
    fit->step.why = "the declared step, as asked";
  }
  run.step_s = fit->step.step_s;
  const RecordCost cost(declared, m, record, run);
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
  fit->library = EffectLibrary(config);
  fit->selection = SelectEffects(config, cost, fit->library, cost.NoiseFloor(), options.rules,
                                 options.choose_step ? &fit->step.floors : nullptr);
  for (const std::string& name : fit->selection.chosen) {
    for (const Effect& e : fit->library) {
      if (e.name == name) fit->chosen.push_back(&e);
    }
  }
  fit->fitted_overrides = EffectOverrides(fit->chosen, fit->selection.chosen_fit.values);
  fit->fitted = config.With(fit->fitted_overrides).params;
  fit->after = cost.Simulate(fit->fitted);
  fit->residual_before = ComputeResiduals(declared, m, record, fit->before, cost.compare_from_s());
  fit->residual_after = ComputeResiduals(declared, m, record, fit->after, cost.compare_from_s());
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
