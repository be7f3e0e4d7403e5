#pragma once
// Effects of the kind "the declared value is off", made from the key registry
// (io/config/config_keys.hpp) instead of written by hand: one key, or the same key on several items
// (every TDB's race inertia) moved together. Each is an Effect like the library's others: its
// parameter maps to `--set` lines of those keys.
#include <string>
#include <vector>

#include "io/config/config_keys.hpp"
#include "tools/fit/effect_library.hpp"

namespace ambdrop {

/// What the fit calls a key-made effect and what it can see it in.
struct KeyEffectInfo {
  std::string name;         ///< "tdb_race_inertia:de"
  std::string family;       ///< "tdb_race_inertia"
  std::string description;  ///< one line for the report
  std::vector<MeasuredQuantity> revealed_by;
};

/// One key's value refitted over its registry fit range (DefaultFitRange), starting at the
/// declared value. The parameter is the key's own value, named by the key's last segment.
Effect DeclaredValueOff(const ConfigKey& key, KeyEffectInfo info);
/// The same over a given range (one the config accepts throughout: RegistryCandidates narrows
/// the default where other keys bound it, a station that would leave the shaft).
Effect DeclaredValueOff(const ConfigKey& key, KeyEffectInfo info, FitRange range);

/// Several keys (the same key of several items) scaled by one common factor of their declared
/// values, over [1/2, 2]; for keys all declared 0, one common value over the first key's range.
/// The parameter is "scale" (or the key's name for the zero case).
Effect DeclaredValuesTogether(const std::vector<ConfigKey>& keys, KeyEffectInfo info);
/// The same with the scale kept where every key stays inside its range (one per key).
Effect DeclaredValuesTogether(const std::vector<ConfigKey>& keys, KeyEffectInfo info,
                              const std::vector<FitRange>& ranges);

}  // namespace ambdrop
