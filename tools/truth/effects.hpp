#pragma once
// The hidden effects: each changes the rig the record is made from, never the declared rig
// sheet. A truth says what was hidden, in the generator's terms and as the ambdrop config keys
// that express it (or how closely they can).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "rig.hpp"

namespace ambdrop_truth {

struct Truth {
  std::string effect;  ///< the kind's name, as --effect takes it
  std::string entry;   ///< declared_off: which number of the sheet is off (else empty)
  std::string description;
  /// "exact": ambdrop's keys express it; "approximate": the nearest keys differ in form (said in
  /// `mapping_note`); "none": outside any library (the fit should not explain it).
  std::string mapping;
  std::string mapping_note;
  std::vector<std::pair<std::string, double>> generator_parameters;  ///< SI, generator's names
  std::vector<std::pair<std::string, std::string>> ambdrop_keys;     ///< --set key, value
};

/// Every effect kind, in battery order ("clean" first).
const std::vector<std::string>& EffectKinds();

/// Applies a kind to `rig` with strengths drawn from `seed` (within a fixed range per kind);
/// throws std::invalid_argument for an unknown kind. Besides EffectKinds(), "declared_off"
/// (one number of the sheet off, the entry drawn) and "declared_off:ENTRY" (that entry;
/// declared_off.hpp).
Truth ApplyEffect(const std::string& kind, std::uint64_t seed, Rig* rig);

}  // namespace ambdrop_truth
