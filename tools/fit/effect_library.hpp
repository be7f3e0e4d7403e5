#pragma once
// Step c/d of `ambdrop fit`: the model extensions a fit may add, each one of the config's
// effect switches with the parameters it fits. An effect is a function from its parameters to
// `--set` overrides of the declared config, so a fitted effect goes straight into the user's
// command line or config.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "io/config/config_measurement.hpp"
#include "io/config/config_variants.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

struct EffectParameter {
  std::string name;    ///< with its unit, as in the config: "x_m", "time_constant_s"
  double lower = 0.0;  ///< bounds the fit keeps to (SI)
  double upper = 0.0;
  std::vector<double> starts;  ///< start values for the multi-start search
  bool periodic = false;       ///< an angle: any value, taken modulo 2 pi
  /// > 0: the model only takes multiples of this (a delay in whole samples), so the cost is
  /// flat between them and the fit steps through them instead of following a gradient.
  double quantum = 0.0;
  /// A size that spans decades from 0 (an unbalance): "a small change" is a thousandth of its
  /// value, not of its range, which can be as large as the value itself.
  bool magnitude = false;
  /// A positive size known only to its decade (a ribbon's slipping stiffness): searched
  /// evenly in its logarithm between the bounds, which must then be positive.
  bool log_scale = false;
  /// The value at which it leaves the declared model as it is (a TDB offset's 0 where none is
  /// declared, a key's declared value); NaN where no value does (a law the model lacks).
  double declared = std::numeric_limits<double>::quiet_NaN();
};

struct Effect {
  std::string name;         ///< "tdb_misalignment:de"
  std::string family;       ///< "tdb_misalignment"
  std::string description;  ///< one line for the report
  std::vector<EffectParameter> parameters;
  /// Which measured quantities can reveal it; without any, the record cannot decide it.
  std::vector<MeasuredQuantity> revealed_by;
  /// Parameter values at which the effect is strong (generous: an effect judged invisible at
  /// them is not fitted). A record whose prediction they move less than the agreement limit
  /// cannot reveal the effect whatever its channels: a TDB drag torque shows in the
  /// displacements only once the race has caught up with the journal, which a short record
  /// does not reach.
  std::vector<double> probe;
  /// The `--set` overrides that switch it on with these parameter values
  /// ("tdb.de.misalignment.x_m=1.2e-05"): applied to the declared config through the same path
  /// as the command line's --set (io/config/config_variants.hpp), so the config's own checks hold,
  /// and printed by the report as they are. One effect may set several keys (a lag's time constant
  /// is its filter's cutoff).
  std::function<std::vector<std::string>(const std::vector<double>&)> overrides;
  /// One of the many "the declared value is off" candidates made from the key registry
  /// (tools/fit/registry_candidates.hpp): one parameter, screened first and fitted only if the
  /// screening ranks it among the most promising (SelectionRules::screened_fits).
  bool screened = false;
};

/// Every effect that applies to this rig, in a fixed order (the order candidates are reported
/// in): the hand-made families, then (unless `only_families`) "the declared value is off" for
/// every other physical key of the config (RegistryCandidates). The config's key registry gives
/// the ranges of the "declared value is off" effects.
std::vector<Effect> EffectLibrary(const ConfigVariants& declared, bool only_families = false);

/// Effects whose revealing quantities no channel of the record measures.
bool Decidable(const Effect& effect, const MeasurementParams& measurement);

}  // namespace ambdrop
