#include "tools/fit/fit_record.hpp"

namespace ambdrop {

std::unique_ptr<FitResult> FitRecord(const ModelParams& declared, const MeasurementParams& m,
                                     const MeasuredRecord& record,
                                     const FitRecordOptions& options) {
  auto fit = std::make_unique<FitResult>();
  const RecordCost cost(declared, m, record, options.run);
  fit->before = cost.Simulate(declared);
  fit->library = EffectLibrary(declared);
  fit->selection = SelectEffects(cost, fit->library, cost.NoiseFloor(), options.rules);
  for (const std::string& name : fit->selection.chosen) {
    for (const Effect& e : fit->library) {
      if (e.name == name) fit->chosen.push_back(&e);
    }
  }
  fit->fitted = WithEffects(declared, fit->chosen, fit->selection.chosen_fit.values);
  fit->after = cost.Simulate(fit->fitted);
  fit->residual_before = ComputeResiduals(declared, m, record, fit->before, cost.compare_from_s());
  fit->residual_after = ComputeResiduals(declared, m, record, fit->after, cost.compare_from_s());
  fit->residual_before.overall = fit->selection.rms_before;
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
