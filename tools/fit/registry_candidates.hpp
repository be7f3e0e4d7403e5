#pragma once
// Issue 23: every declared number is a suspect. On a real machine the hidden difference is
// mostly a number the declared model already has, and it is off (a clearance worn larger, a
// bias trimmed, a race heavier than drawn, a sensor's gain drifted): so every physical key of
// the config is a candidate "the declared value is off", made from the key registry
// (io/config/config_keys.hpp) rather than by hand, beside the library's hand-made families.
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "tools/fit/effect_library.hpp"

namespace ambdrop {

/// Why a physical key of the registry is not offered, or "" if it is. Exposed for the tests
/// and for `ambdrop keys` readers: a key the library's own effects already set (it fits them
/// with their physics), a table switched off, the site's gravity, the shaft's drawing (section
/// lengths and diameters: the rotor's masses and stiffness are fitted through its materials and
/// discs), a key whose accepted range leaves nothing to search.
std::string NotACandidateBecause(const ConfigKey& key, const std::vector<ConfigKey>& keys,
                                 const std::vector<std::string>& set_by_library);

/// The paths the effects' overrides set (at their first starts), sorted and unique.
std::vector<std::string> KeysSetBy(const std::vector<Effect>& effects);

/// "The declared value is off" for every physical key of `config` that NotACandidateBecause
/// lets through, each alone (named by its path), and for a key that several TDBs, AMBs or
/// sensors have (not a station), all of theirs together, scaled by one factor (named
/// "tdb.*.spin.inertia_kg_m2"). Each range is the registry's default (DefaultFitRange with the
/// config's keys: a station up to its neighbours), narrowed
/// to what the config accepts with the other keys as declared (a sensor cannot leave the shaft).
/// Each is screened (Effect::screened); its family is the key without the item, so the one-item
/// and all-items forms of a key are one family. In registry order.
std::vector<Effect> RegistryCandidates(const ConfigVariants& config,
                                       const std::vector<Effect>& library);

}  // namespace ambdrop
