#pragma once
// Step c/d of `ambdrop fit`: the model extensions a fit may add, each one of the config's
// effect switches with the parameters it fits. An effect changes ModelParams (the same fields
// the config's keys set) and can say itself as config keys, so a fitted effect goes straight
// into the user's config.
#include <functional>
#include <string>
#include <vector>

#include "io/config_measurement.hpp"
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
  /// Sets the effect with these parameter values on a copy of the declared params.
  std::function<void(const std::vector<double>&, ModelParams*)> apply;
  /// The config keys that switch it on with these values (TOML lines, "[table]" headers).
  std::function<std::string(const std::vector<double>&)> config;
};

/// Every effect that applies to this rig and that the declared config does not already have
/// switched on, in a fixed order (the order candidates are reported in).
std::vector<Effect> EffectLibrary(const ModelParams& declared);

/// Effects whose revealing quantities no channel of the record measures.
bool Decidable(const Effect& effect, const MeasurementParams& measurement);

}  // namespace ambdrop
