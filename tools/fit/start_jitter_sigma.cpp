#include "tools/fit/start_jitter_sigma.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "tools/fit/effect_selection.hpp"
#include "tools/fit/effect_selection_internal.hpp"
#include "tools/fit/parallel_for.hpp"
#include "tools/fit/simulate_on_record.hpp"
#include "tools/fit/start_sensitivity.hpp"

namespace ambdrop {
namespace {

// A small change of a parameter for its column of the Jacobian: a hundredth of its range, or
// of its value where it is known by its decade or is a size from 0. Larger than the search's
// own steps: contact makes the cost rough at finer scales, and what is wanted is the slope the
// start's jitter meets, over the values that jitter moves it by.
double ColumnStep(const EffectParameter& p, double value) {
  const double range = p.periodic ? 2.0 * std::numbers::pi : p.upper - p.lower;
  if (p.log_scale || p.magnitude) return 1e-2 * std::max(std::abs(value), 1e-3 * range);
  return 1e-2 * range;
}

}  // namespace

void AddStartJitterToSigmas(const ConfigVariants& declared, const RecordCost& cost,
                            const std::vector<Effect>& library, int draws, int threads,
                            EffectFit* fit) {
  if (fit == nullptr || fit->effects.empty() || draws <= 0) return;
  const MeasurementParams& m = cost.measurement();
  // A start taken from the record's estimate holds that estimate's own uncertainty instead.
  if (m.trigger_state_from_record) return;
  if (!ClosedLoop(cost.declared(), m, cost.run_options())) return;
  const double jitter_sigma_m = DisplacementNoiseMedian(cost);
  if (!(jitter_sigma_m > 0.0)) return;
  const std::vector<const Effect*> effects = EffectsOf(*fit, library);
  if (effects.size() != fit->effects.size()) return;
  // The parameters in fit->parameters' order (effect by effect), those a small change moves.
  struct Column {
    std::size_t effect, index, flat;
    double step;
  };
  std::vector<Column> columns;
  std::size_t flat = 0;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    for (std::size_t i = 0; i < effects[e]->parameters.size(); ++i, ++flat) {
      const EffectParameter& p = effects[e]->parameters[i];
      if (flat >= fit->parameters.size()) return;
      if (p.quantum > 0.0 || fit->parameters[flat].at_bound) continue;
      double step = ColumnStep(p, fit->values[e][i]);
      if (!p.periodic && fit->values[e][i] + step > p.upper) step = -step;
      columns.push_back({e, i, flat, step});
    }
  }
  if (columns.empty()) return;
  const ModelParams fitted = WithEffects(declared, effects, fit->values);
  const Eigen::VectorXd at = cost.Residual(fitted);
  const Eigen::Index rows = at.size();
  const Eigen::Index n = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd jacobian(rows, n);
  ParallelFor(columns.size(), threads, [&](std::size_t k) {
    std::vector<std::vector<double>> v = fit->values;
    v[columns[k].effect][columns[k].index] += columns[k].step;
    jacobian.col(static_cast<Eigen::Index>(k)) =
        (ResidualWithEffects(declared, cost, effects, v) - at) / columns[k].step;
  });
  // What the rotor's jitter at the trigger does to the prediction: runs of the fitted model
  // with its controller answering sensor noise of the record's level (as DrawJitter's).
  Eigen::MatrixXd moved(rows, draws);
  ParallelFor(static_cast<std::size_t>(draws), threads, [&](std::size_t k) {
    RecordRunOptions o = cost.run_options();
    o.jitter_sigma_m = jitter_sigma_m;
    o.jitter_seed = static_cast<std::uint64_t>(k) + 1;
    moved.col(static_cast<Eigen::Index>(k)) =
        cost.Residual(SimulateOnRecord(fitted, m, cost.record(), o)) - at;
  });
  if (!jacobian.allFinite() || !moved.allFinite()) return;
  // Each column in units of its own size, so that one of N/m beside one of m conditions the
  // least squares; a column the cost does not feel (a partner fitted on another part) stays
  // out, its sigma as it was.
  Eigen::VectorXd scale = jacobian.colwise().norm().transpose();
  const double largest = scale.maxCoeff();
  std::vector<Eigen::Index> live;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (scale(k) > 1e-6 * largest && scale(k) > 0.0) live.push_back(k);
  }
  if (live.empty()) return;
  Eigen::MatrixXd a(rows, static_cast<Eigen::Index>(live.size()));
  for (std::size_t k = 0; k < live.size(); ++k) {
    a.col(static_cast<Eigen::Index>(k)) = jacobian.col(live[k]) / scale(live[k]);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < a.cols()) return;
  // The fit to a record whose start had jittered so moves by minus the least-squares shift
  // that absorbs the jitter's move; its spread over the draws is the jitter's share.
  const Eigen::MatrixXd shifts = qr.solve(moved);
  for (std::size_t k = 0; k < live.size(); ++k) {
    const Column& c = columns[static_cast<std::size_t>(live[k])];
    const double spread = std::sqrt(shifts.row(static_cast<Eigen::Index>(k)).squaredNorm() /
                                    static_cast<double>(draws)) /
                          scale(live[k]);
    ParameterEstimate& est = fit->parameters[c.flat];
    est.start_sigma = spread;
    if (std::isfinite(est.sigma)) est.sigma = std::hypot(est.sigma, spread);
    est.decided = ParameterDecided(effects[c.effect]->parameters[c.index], est.value, est.sigma,
                                   est.at_bound);
  }
}

}  // namespace ambdrop
