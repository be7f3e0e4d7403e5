#include "tools/fit/registry_candidates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "io/config/config_loader.hpp"

#include "tools/fit/key_effects.hpp"

namespace ambdrop {
namespace {

using Q = MeasuredQuantity;

// Tables of named items ([tdb.de], [amb.nde], [sensor.de]): a key of theirs is one item's, and
// the same key of every item is the group form.
bool IsItemTable(const std::string& segment) {
  return segment == "tdb" || segment == "amb" || segment == "sensor" || segment == "bearing";
}

struct ItemKey {
  std::string item;     ///< "de"; "" when the key is not an item's
  std::string pattern;  ///< the path with the item as '*': "tdb.*.clearance_m"
  std::string family;   ///< the path without the item: "tdb.clearance_m"
};

ItemKey SplitItem(const std::string& path) {
  const std::size_t first = path.find('.');
  if (first == std::string::npos) return {"", path, path};
  const std::size_t second = path.find('.', first + 1);
  const std::string table = path.substr(0, first);
  if (second == std::string::npos || !IsItemTable(table)) return {"", path, path};
  const std::string item = path.substr(first + 1, second - first - 1);
  if (item.find('[') != std::string::npos) return {"", path, path};
  const std::string rest = path.substr(second);
  return {item, table + ".*" + rest, table + rest};
}

// Any measured channel may show a physical number: whether this record does is the screening's
// question (its reach), not a rule written per key.
std::vector<Q> EveryQuantity() {
  return {Q::kDisplacement,   Q::kCurrent,         Q::kTdbSpeed,         Q::kRotorSpeed,
          Q::kTdbNormalForce, Q::kTdbSupportForce, Q::kControllerCommand};
}

std::string Declared(const ConfigKey& k) {
  return fmt::format("{}{:.4g}{}{}", k.declared ? "declared " : "default ", k.value,
                     k.unit.empty() ? "" : " ", k.unit);
}

bool IsStation(const std::string& path) {
  return path.ends_with(".position_m") || path.ends_with(".centre_of_mass_m");
}

bool Accepts(const ConfigVariants& config, const ConfigKey& key, double value) {
  try {
    config.With({OverrideFor(key, value)});
    return true;
  } catch (const ConfigError&) {
    return false;
  }
}

// The part of `range` the config accepts with every other key as declared: each end the config
// refuses is drawn in towards the declared value (bisection, to 1/256 of the way).
FitRange AcceptedRange(const ConfigVariants& config, const ConfigKey& key, FitRange range) {
  const double v = std::clamp(key.value, range.lower, range.upper);
  if (key.integer) {
    // Whole numbers, each end drawn in one at a time.
    range.lower = std::ceil(range.lower);
    range.upper = std::floor(range.upper);
    while (range.lower < v && !Accepts(config, key, range.lower)) range.lower += 1.0;
    while (range.upper > v && !Accepts(config, key, range.upper)) range.upper -= 1.0;
    return range;
  }
  for (double* end : {&range.lower, &range.upper}) {
    if (Accepts(config, key, *end)) continue;
    double good = v, bad = *end;
    for (int i = 0; i < 8; ++i) {
      const double mid = 0.5 * (good + bad);
      (Accepts(config, key, mid) ? good : bad) = mid;
    }
    *end = good;
  }
  return range;
}

}  // namespace

std::vector<std::string> KeysSetBy(const std::vector<Effect>& effects) {
  std::vector<std::string> paths;
  for (const Effect& e : effects) {
    std::vector<double> first;
    for (const EffectParameter& p : e.parameters) {
      first.push_back(p.starts.empty() ? p.lower : p.starts.front());
    }
    for (const std::string& line : e.overrides(first)) {
      paths.push_back(line.substr(0, line.find('=')));
    }
  }
  std::sort(paths.begin(), paths.end());
  paths.erase(std::unique(paths.begin(), paths.end()), paths.end());
  return paths;
}

std::string NotACandidateBecause(const ConfigKey& key, const std::vector<ConfigKey>& keys,
                                 const std::vector<std::string>& set_by_library) {
  if (key.key_class != KeyClass::kPhysical) {
    return fmt::format("a {} key, not the machine's", KeyClassName(key.key_class));
  }
  if (!key.in_force) return "its table is switched off";
  if (std::binary_search(set_by_library.begin(), set_by_library.end(), key.path)) {
    return "an effect of the library sets it";
  }
  // Known at the site to a part in a thousand, and it would stand in for any mass error.
  if (key.path.starts_with("gravity.")) return "the site's gravity";
  if (key.path.starts_with("rotor.sections[")) return "the shaft's drawing";
  if (!std::isfinite(key.value)) return "not a finite number";
  const FitRange range = DefaultFitRange(key, keys);
  if (!(range.lower < range.upper)) return "its accepted range leaves nothing to search";
  return {};
}

std::vector<Effect> RegistryCandidates(const ConfigVariants& config,
                                       const std::vector<Effect>& library) {
  const std::vector<std::string> set_by_library = KeysSetBy(library);
  std::vector<Effect> effects;
  // Group forms in the order their pattern first appears.
  std::vector<std::string> patterns;
  std::map<std::string, std::vector<std::pair<ConfigKey, FitRange>>> groups;
  for (const ConfigKey& key : config.declared().keys) {
    if (!NotACandidateBecause(key, config.declared().keys, set_by_library).empty()) continue;
    const FitRange range = AcceptedRange(config, key, DefaultFitRange(key, config.declared().keys));
    if (!(range.lower < range.upper)) continue;
    const ItemKey split = SplitItem(key.path);
    effects.push_back(DeclaredValueOff(
        key,
        {key.path, split.family,
         fmt::format("the value of {} is off ({})", key.path, Declared(key)), EveryQuantity()},
        range));
    effects.back().screened = true;
    // Every station moved by one factor is no one's mistake; a count is not scaled.
    if (split.item.empty() || IsStation(key.path) || key.integer) continue;
    auto [it, added] = groups.try_emplace(split.pattern);
    if (added) patterns.push_back(split.pattern);
    it->second.emplace_back(key, range);
  }
  for (const std::string& pattern : patterns) {
    const auto& members = groups[pattern];
    if (members.size() < 2) continue;
    std::vector<ConfigKey> keys;
    std::vector<FitRange> ranges;
    for (const auto& [k, r] : members) {
      keys.push_back(k);
      ranges.push_back(r);
    }
    Effect e = DeclaredValuesTogether(
        keys,
        {pattern, SplitItem(keys.front().path).family,
         fmt::format("the value of {} is off on all {} of them, by one factor", pattern,
                     keys.size()),
         EveryQuantity()},
        ranges);
    e.screened = true;
    effects.push_back(std::move(e));
  }
  return effects;
}

}  // namespace ambdrop
