#pragma once
// Step d of `ambdrop fit`: the parameters of one effect (or two together) that bring the model
// closest to the record, by Eigen's Levenberg-Marquardt on the record's residual vector, from
// several starts (contact makes the cost bumpy and phases have several minima).
#include <limits>
#include <string>
#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

struct ParameterEstimate {
  std::string effect;
  std::string name;
  double value = 0.0;
  /// One standard deviation from the Jacobian at the optimum, s^2 (J^T J)^-1 with s^2 the
  /// residual variance; NaN at a bound or where the record does not determine it. Residual
  /// samples are correlated in time, so it is a lower bound.
  double sigma = 0.0;
  /// The part of `sigma` the rotor's jitter at the trigger gives (AddStartJitterToSigmas,
  /// start_jitter_sigma.hpp); NaN where it was not measured.
  double start_sigma = std::numeric_limits<double>::quiet_NaN();
  /// The search stopped on one of the parameter's bounds.
  bool at_bound = false;
  /// False where the record leaves the value open (ParameterDecided), or where the record is
  /// explained without it (MarkValuesTheRecordDoesNotNeed): the model still runs with it, but
  /// it is no measurement of the machine.
  bool decided = true;
  /// The judged part's residual with this one value at its declared value and every other as
  /// fitted, where that still explains the record (declared_value_check.hpp); else NaN.
  double declared_rms = std::numeric_limits<double>::quiet_NaN();
  /// For a value with no declared one to set it back to (a law the model lacks): a value at
  /// the edge of what ParameterDecided calls decided (half or 1.5 times it for a size, a
  /// quarter of its range away for any other number), moved along its valley with its most
  /// correlated partner, where that still explains the record (declared_value_check.hpp); NaN
  /// where neither edge does.
  double explained_at = std::numeric_limits<double>::quiet_NaN();
  /// Where the record decides this value only together with another (declared_value_check.hpp):
  /// that value's name ("effect/parameter"), the slope of the record's valley between them
  /// (d other / d this along it) and the one combination the record decides,
  /// other - trade_slope * this, with its sigma. Empty `traded_with` otherwise.
  std::string traded_with;
  double trade_slope = std::numeric_limits<double>::quiet_NaN();
  double trade_combination = std::numeric_limits<double>::quiet_NaN();
  double trade_combination_sigma = std::numeric_limits<double>::quiet_NaN();
};

/// Whether a fitted value is one the record decides. Its sigma is a lower bound, so a value is
/// taken as open when even that spans a factor of 1.5 of a size known only to its decade or of
/// a size from 0 (sigma >= half the value), or a quarter of the range of any other number; a
/// sigma the record gives none of (the column flat, or the normal matrix singular with its
/// neighbours) leaves it open too, except at a bound (the record pushed it there) or on a
/// quantised number (a delay between samples: flat between them by construction). The 4-DOF
/// truth rig's Dahl ribbon records: slipping stiffness 3.3e3 +- 1.8e6, 5.1e4 +- 8.0e4 N/m.
bool ParameterDecided(const EffectParameter& p, double value, double sigma, bool at_bound);

/// The sigma below which ParameterDecided calls `value` decided (half the value for a size, a
/// quarter of the range for any other number): also how far a value is moved to ask whether
/// the record explains it as well there (declared_value_check.hpp).
double DecidedHalfWidth(const EffectParameter& p, double value);

struct EffectFit {
  std::vector<std::string> effects;
  std::vector<ParameterEstimate> parameters;
  std::vector<std::vector<double>> values;  ///< per effect, its parameter values
  /// The parameters' covariance from the Jacobian at the optimum, in their own units, row-major
  /// over `parameters`; NaN where a parameter sat at a bound or the normal matrix was singular.
  std::vector<double> covariance;
  double sse = 0.0;     ///< squared norm of the residual vector
  int evaluations = 0;  ///< model runs
};

/// The `--set` overrides of the effects at `values` (per effect), in order.
std::vector<std::string> EffectOverrides(const std::vector<const Effect*>& effects,
                                         const std::vector<std::vector<double>>& values);

/// Model params with the effects applied at `values` (per effect): the declared config read
/// again with their overrides. Throws ConfigError if the config refuses a value.
ModelParams WithEffects(const ConfigVariants& declared, const std::vector<const Effect*>& effects,
                        const std::vector<std::vector<double>>& values);

/// The residual of the declared model with the effects at `values`. A value the config refuses
/// (ConfigError: a station moved past its neighbour) gives RecordCost::Unreached(), so that a
/// search turns away from it instead of stopping; `refused`, if given, says so.
Eigen::VectorXd ResidualWithEffects(const ConfigVariants& declared, const RecordCost& cost,
                                    const std::vector<const Effect*>& effects,
                                    const std::vector<std::vector<double>>& values,
                                    bool* refused = nullptr);

/// Values an effect's parameters are known to fit well (its own single fit): searches start
/// there, and also from the parameters' own starts unless `only`.
struct KnownStart {
  std::vector<double> values;  ///< empty: nothing known
  bool only = false;
};

/// Fits the effects' parameters together. `max_runs_per_start` bounds the model runs of each
/// start (the Jacobian costs one run per parameter). With `screen` (the same record's early,
/// deterministic part: CostScope::kEarly), the starts are searched on it and the best is then
/// refined on `cost` itself: where the drop turns chaotic after its impacts, `cost` is too
/// rough for a gradient from afar, while the early part leads to the right basin.
/// `known`, if not empty, has one entry per effect.
EffectFit FitEffects(const ConfigVariants& declared, const RecordCost& cost,
                     const std::vector<const Effect*>& effects, int max_runs_per_start = 40,
                     const RecordCost* screen = nullptr, const std::vector<KnownStart>& known = {});

}  // namespace ambdrop
