#include "tools/fit/key_effects.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "io/config/config_variants.hpp"

namespace ambdrop {
namespace {

std::string LastSegment(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

// Starts inside [lower, upper]: the declared value first, then either side of it.
std::vector<double> StartsAround(double declared, double lower, double upper) {
  std::vector<double> starts = {std::clamp(declared, lower, upper)};
  if (declared > 0.0) {
    for (const double f : {0.7, 1.4}) starts.push_back(std::clamp(f * declared, lower, upper));
  } else {
    for (const double f : {0.01, 0.1}) starts.push_back(lower + f * (upper - lower));
  }
  return starts;
}

}  // namespace

Effect DeclaredValueOff(const ConfigKey& key, KeyEffectInfo info) {
  return DeclaredValueOff(key, std::move(info), DefaultFitRange(key));
}

Effect DeclaredValueOff(const ConfigKey& key, KeyEffectInfo info, FitRange range) {
  Effect e;
  e.name = std::move(info.name);
  e.family = std::move(info.family);
  e.description = std::move(info.description);
  e.revealed_by = std::move(info.revealed_by);
  EffectParameter p{LastSegment(key.path), range.lower, range.upper,
                    StartsAround(key.value, range.lower, range.upper)};
  // A station's scale is its gaps to its neighbours, not its distance from the axial origin:
  // from where it is declared and from either end of its range.
  if (IsStationKey(key)) {
    p.starts = {std::clamp(key.value, range.lower, range.upper), range.lower, range.upper};
  }
  // Declared 0, it may be any size from nothing: a small change is relative to the value.
  p.magnitude = key.value == 0.0;
  // A count (a delay in whole samples): the search steps through whole numbers.
  if (key.integer) {
    p.quantum = 1.0;
    p.magnitude = false;
    for (double& s : p.starts) s = std::round(s);
  }
  p.declared = key.value;
  e.parameters = {p};
  // The far end of the range from the declared value: strong, as a probe must be.
  e.probe = {range.upper - key.value >= key.value - range.lower ? range.upper : range.lower};
  const ConfigKey k = key;
  e.overrides = [k](const std::vector<double>& v) {
    return std::vector<std::string>{OverrideFor(k, v[0])};
  };
  return e;
}

Effect DeclaredValuesTogether(const std::vector<ConfigKey>& keys, KeyEffectInfo info) {
  std::vector<FitRange> ranges;
  for (const ConfigKey& k : keys) ranges.push_back(DefaultFitRange(k));
  return DeclaredValuesTogether(keys, std::move(info), ranges);
}

Effect DeclaredValuesTogether(const std::vector<ConfigKey>& keys, KeyEffectInfo info,
                              const std::vector<FitRange>& ranges) {
  const bool all_zero =
      std::all_of(keys.begin(), keys.end(), [](const ConfigKey& k) { return k.value == 0.0; });
  if (all_zero) {
    // One common value: inside every key's range.
    FitRange common = ranges.front();
    for (const FitRange& r : ranges) {
      common.lower = std::max(common.lower, r.lower);
      common.upper = std::min(common.upper, r.upper);
    }
    Effect e = DeclaredValueOff(keys.front(), std::move(info), common);
    std::vector<std::string> paths;
    for (const ConfigKey& k : keys) paths.push_back(k.path);
    e.overrides = [paths](const std::vector<double>& v) {
      std::vector<std::string> out;
      for (const std::string& p : paths) out.push_back(p + "=" + OverrideNumber(v[0]));
      return out;
    };
    return e;
  }
  Effect e;
  e.name = std::move(info.name);
  e.family = std::move(info.family);
  e.description = std::move(info.description);
  e.revealed_by = std::move(info.revealed_by);
  // A factor of 2 either way, as far as every key's own range lets the scale go (a key declared
  // 0 stays 0 whatever the scale).
  double lower = 0.5, upper = 2.0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const double v = keys[i].value;
    if (v > 0.0) {
      lower = std::max(lower, ranges[i].lower / v);
      upper = std::min(upper, ranges[i].upper / v);
    } else if (v < 0.0) {
      lower = std::max(lower, ranges[i].upper / v);
      upper = std::min(upper, ranges[i].lower / v);
    }
  }
  e.parameters = {
      {"scale", lower, upper, {1.0, std::clamp(0.7, lower, upper), std::clamp(1.4, lower, upper)}}};
  e.parameters[0].declared = 1.0;
  e.probe = {upper - 1.0 >= 1.0 - lower ? upper : lower};
  struct Declared {
    std::string path;
    double value;
    FitRange range;
  };
  std::vector<Declared> declared;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    declared.push_back({keys[i].path, keys[i].value, ranges[i]});
  }
  e.overrides = [declared](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const Declared& d : declared) {
      // Clamped: the scale's bound times the value can round just past the key's own.
      const double scaled = v[0] * d.value;
      out.push_back(
          d.path + "=" +
          OverrideNumber(d.value == 0.0 ? 0.0 : std::clamp(scaled, d.range.lower, d.range.upper)));
    }
    return out;
  };
  return e;
}

}  // namespace ambdrop
