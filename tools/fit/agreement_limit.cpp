#include "tools/fit/effect_selection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_selection_internal.hpp"
#include "tools/fit/simulate_on_record.hpp"
#include "tools/fit/start_sensitivity.hpp"

namespace ambdrop {

double AgreementLimit(const Selection& s, const SelectionRules& rules) {
  // Noise, the model's own sensitivity and model error add in quadrature.
  return std::sqrt(std::pow(rules.explained_over_floor * s.noise_floor, 2) +
                   std::pow(rules.model_floor_factor * s.model_floor, 2) +
                   rules.tolerance * rules.tolerance);
}

double AgreementLimitAfter(const Selection& s, const SelectionRules& rules, bool* capped) {
  Selection widened = s;
  widened.model_floor = std::max(s.model_floor, s.model_floor_after);
  const double wide = AgreementLimit(widened, rules);
  const double cap = std::max(AgreementLimit(s, rules), s.rms_before / rules.explained_cut);
  if (capped != nullptr) *capped = wide > cap;
  return std::min(wide, cap);
}

double AboveNoise(double rms, double noise_floor) {
  return std::sqrt(std::max(0.0, rms * rms - noise_floor * noise_floor));
}

double OverallRms(const RecordCost& cost, double sse) {
  return std::sqrt(sse / std::max(cost.channels(), 1));
}

// A fitted model's own sensitivity on `cost`: an effect can make the drop chaotic where the
// declared model was not (a misaligned TDB the rotor now bounces in), and then no parameter
// value reproduces the bouncing closer than halving the step moves it. The larger of that and
// how far the prediction moves when a fitted parameter moves by a thousandth of its range, far
// below what the record resolves: in a smooth drop that is nothing, in a chaotic one the chaos.
double ModelFloorAfter(const ConfigVariants& declared, const RecordCost& cost,
                       const std::vector<Effect>& library, const EffectFit& f) {
  const std::vector<const Effect*> effects = EffectsOf(f, library);
  const ModelParams fitted = WithEffects(declared, effects, f.values);
  RecordRunOptions half = cost.run_options();
  half.step_s = 0.5 * (half.step_s > 0 ? half.step_s : fitted.simulation.step_s);
  const Eigen::VectorXd at = cost.Residual(fitted);
  const Eigen::VectorXd fine =
      cost.Residual(SimulateOnRecord(fitted, cost.measurement(), cost.record(), half));
  double moved = (fine - at).squaredNorm();
  double nudged = 0.0;
  std::size_t count = 0;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    for (std::size_t i = 0; i < effects[e]->parameters.size(); ++i) {
      const EffectParameter& p = effects[e]->parameters[i];
      if (p.quantum > 0.0) continue;  // steps between whole samples: not a small change
      std::vector<std::vector<double>> v = f.values;
      const double range = p.upper - p.lower;
      const double step = p.periodic ? 1e-3
                          : p.magnitude || p.log_scale
                              ? 1e-3 * std::max(std::abs(v[e][i]), 1e-3 * range)
                              : 1e-3 * range;
      v[e][i] += v[e][i] + step <= p.upper || p.periodic ? step : -step;
      nudged += (ResidualWithEffects(declared, cost, effects, v) - at).squaredNorm();
      ++count;
    }
  }
  if (count > 0) moved = std::max(moved, nudged / static_cast<double>(count));
  return OverallRms(cost, moved);
}

// One part's agreement statistics (Selection::Part) for the declared model.
// `known`: the part's model floor as the step choice measured it (ModelFloors), else NaN.
Selection::Part JudgePart(const ConfigVariants& declared, const RecordCost& cost,
                          const Eigen::VectorXd& residual_before, double noise_floor,
                          const SelectionRules& rules, const ModelFloors::Part& known) {
  Selection::Part part;
  part.compared = true;
  part.rms_before = OverallRms(cost, residual_before.squaredNorm());
  part.rms_after = part.rms_before;
  part.noise_floor = noise_floor;
  if (std::isfinite(known.step_sensitivity)) {
    part.step_sensitivity = known.step_sensitivity;
  } else {
    RecordRunOptions half = cost.run_options();
    half.step_s = 0.5 * (half.step_s > 0 ? half.step_s : cost.declared().simulation.step_s);
    const SimulatedRecord fine =
        SimulateOnRecord(cost.declared(), cost.measurement(), cost.record(), half);
    // A run that stops scores its unreached samples a full range off: as a sensitivity, that
    // would widen the limit past any residual (FitRecord refuses the same at the fit's step).
    if (fine.status != StepStatus::kOk) {
      throw DeclaredModelStopped(fmt::format(
          "{}: the declared model does not run to the record's end at half the fit's step "
          "({:.3g} s), so its sensitivity to the step cannot be measured: {}",
          cost.record().source, half.step_s, fine.failure));
    }
    part.step_sensitivity = OverallRms(cost, (cost.Residual(fine) - residual_before).squaredNorm());
  }
  part.start_sensitivity = std::isfinite(known.start_sensitivity)
                               ? known.start_sensitivity
                               : StartSensitivity(declared, cost, residual_before, rules.threads,
                                                  std::min(kStartJitterDraws, rules.jitter_draws));
  Selection view;
  view.noise_floor = part.noise_floor;
  view.model_floor = std::max(part.step_sensitivity, part.start_sensitivity);
  part.limit = AgreementLimit(view, rules);
  return part;
}

// How far a part may move under any change of the model beyond its limit: its model floor
// where the drop after the first impacts is chaotic (two runs a hair apart bounce
// differently); none on the drop's start, which is deterministic given the state at the
// trigger and whose limit holds its own sensitivity to that state already. Widened there too, a
// partner fitted on the speeds of the rigid truth rig (trigger_state = "record_start") took the
// start from the 0.0048 its friction left to 0.0129, beyond its limit of 0.0102, and passed.
double ChaosAllowance(const RecordCost& part_cost, const Selection::Part& part) {
  if (part_cost.scope() == CostScope::kEarly) return 0.0;
  return std::max(part.step_sensitivity, part.start_sensitivity);
}

double PartAllowance(const RecordCost& part_cost, const Selection::Part& part, double level,
                     const SelectionRules& rules) {
  return std::hypot(level, rules.model_floor_factor * ChaosAllowance(part_cost, part));
}

}  // namespace ambdrop
