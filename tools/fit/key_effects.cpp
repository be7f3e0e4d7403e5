#include "tools/fit/key_effects.hpp"

#include <algorithm>
#include <utility>

#include "io/config_variants.hpp"

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
  const FitRange range = DefaultFitRange(key);
  Effect e;
  e.name = std::move(info.name);
  e.family = std::move(info.family);
  e.description = std::move(info.description);
  e.revealed_by = std::move(info.revealed_by);
  EffectParameter p{LastSegment(key.path), range.lower, range.upper,
                    StartsAround(key.value, range.lower, range.upper)};
  // Declared 0, it may be any size from nothing: a small change is relative to the value.
  p.magnitude = key.value == 0.0;
  e.parameters = {p};
  // The far end of the range from the declared value: strong, as a probe must be.
  e.probe = {range.upper - key.value >= key.value - range.lower ? range.upper : range.lower};
  const std::string path = key.path;
  e.overrides = [path](const std::vector<double>& v) {
    return std::vector<std::string>{path + "=" + OverrideNumber(v[0])};
  };
  return e;
}

Effect DeclaredValuesTogether(const std::vector<ConfigKey>& keys, KeyEffectInfo info) {
  const bool all_zero =
      std::all_of(keys.begin(), keys.end(), [](const ConfigKey& k) { return k.value == 0.0; });
  if (all_zero) {
    Effect e = DeclaredValueOff(keys.front(), std::move(info));
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
  e.parameters = {{"scale", 0.5, 2.0, {1.0, 0.7, 1.4}}};
  e.probe = {2.0};
  std::vector<std::pair<std::string, double>> declared;
  for (const ConfigKey& k : keys) declared.emplace_back(k.path, k.value);
  e.overrides = [declared](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const auto& [path, value] : declared) {
      out.push_back(path + "=" + OverrideNumber(v[0] * value));
    }
    return out;
  };
  return e;
}

}  // namespace ambdrop
