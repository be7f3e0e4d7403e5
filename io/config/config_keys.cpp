#include "io/config/config_keys.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "io/config/toml_reader.hpp"

namespace ambdrop {
namespace {

bool StartsWith(std::string_view path, std::string_view prefix) {
  return path.substr(0, prefix.size()) == prefix;
}

bool HasSegment(std::string_view path, std::string_view segment) {
  std::size_t at = 0;
  while ((at = path.find(segment, at)) != std::string_view::npos) {
    const bool starts = at == 0 || path[at - 1] == '.';
    const std::size_t end = at + segment.size();
    const bool ends = end == path.size() || path[end] == '.' || path[end] == '[';
    if (starts && ends) return true;
    at = end;
  }
  return false;
}

std::string_view LastSegment(std::string_view path) {
  const std::size_t dot = path.rfind('.');
  return dot == std::string_view::npos ? path : path.substr(dot + 1);
}

// A span a quantity of this unit may plausibly be off by when it is declared 0 (an offset, a
// drag, a phase): wide enough to hold what a real machine shows, narrow enough for a search.
double ZeroSpan(std::string_view unit) {
  static constexpr std::array<std::pair<std::string_view, double>, 15> kSpans = {{
      {"m", 1e-4},  // offsets, runout: a tenth of a millimetre
      {"rad", std::numbers::pi},
      {"N m", 0.1},     // drag torques
      {"N m s", 1e-3},  // viscous torques
      {"A", 1.0},       // current offsets
      {"s", 1e-3},      // delays, time constants
      {"1/s", 10.0},    // integral gains: a corner of a couple of hertz
      {"N", 100.0},
      {"N/m", 1e6},
      {"N s/m", 1e3},
      {"Hz", 100.0},
      {"kg", 0.1},
      {"kg m", 1e-4},  // unbalance
      {"kg m^2", 1e-3},
      {"", 0.1},  // coefficients and ratios
  }};
  for (const auto& [u, span] : kSpans) {
    if (u == unit) return span;
  }
  return 1.0;
}

}  // namespace

std::string KeyUnit(std::string_view key) {
  return config_detail::UnitOfKey(key);
}

const char* KeyClassName(KeyClass key_class) noexcept {
  switch (key_class) {
    case KeyClass::kPhysical:
      return "physical";
    case KeyClass::kMeasurement:
      return "measurement";
    case KeyClass::kSolver:
      return "solver";
    case KeyClass::kRun:
      return "run";
    case KeyClass::kInterface:
      return "interface";
  }
  return "unknown";
}

KeyClass ClassOfKey(std::string_view path) {
  // The spin at the start is the run's operating point, as the trigger time is its event.
  if (path == "simulation.spin_speed_rad_s") return KeyClass::kRun;
  if (StartsWith(path, "simulation.")) return KeyClass::kSolver;
  if (path == "controller.rate_Hz") return KeyClass::kSolver;
  if (StartsWith(path, "trigger.") || StartsWith(path, "scenario.")) return KeyClass::kRun;
  if (StartsWith(path, "can.") || StartsWith(path, "realtime.")) return KeyClass::kInterface;
  if (StartsWith(path, "measurement.")) return KeyClass::kMeasurement;
  // How the sensors are observed, not where or how they sit: noise and its seed, quantisation.
  const std::string_view last = LastSegment(path);
  if (HasSegment(path, "noise") || last.starts_with("quantisation")) {
    return KeyClass::kMeasurement;
  }
  if (last == "seed" || last == "elements" || last == "modes") return KeyClass::kSolver;
  return KeyClass::kPhysical;
}

FitRange DefaultFitRange(const ConfigKey& key) {
  const double v = key.value;
  const double span = ZeroSpan(key.unit);
  FitRange r;
  if (key.integer) {
    // A count (samples of delay, balls): whole numbers, half to twice a declared count, or a
    // couple either side of zero, inside the reader's range.
    const double half_width = std::max(std::floor(0.5 * std::abs(v)), 1.0);
    r = v > 0.0 && key.lower >= 0.0 ? FitRange{v - half_width, 2.0 * v}
                                    : FitRange{v - 2.0 * half_width, v + 2.0 * half_width};
    r.lower = std::max(r.lower, std::ceil(key.lower));
    r.upper = std::min(r.upper, std::floor(key.upper));
    return r;
  }
  if (IsStationKey(key)) {
    // A station along the shaft, its neighbours unknown: off by what a drawing or a mounting
    // gets wrong, not by a factor of two (which would move it past its neighbours). The
    // overload below knows them.
    const double half_width = std::max(0.1 * std::abs(v), 0.01);
    r = {v - half_width, v + half_width};
  } else if (key.unit == "rad") {
    r = {v - std::numbers::pi, v + std::numbers::pi};  // an angle: any value
  } else if (key.lower >= 0.0) {
    // A size: off by a factor of two either way, or from nothing to a plausible size.
    r = v > 0.0 ? FitRange{0.5 * v, 2.0 * v} : FitRange{0.0, span};
  } else {
    const double half_width = std::max(0.5 * std::abs(v), span);
    r = {v - half_width, v + half_width};
  }
  r.lower = std::max(r.lower, key.lower);
  r.upper = std::min(r.upper, key.upper);
  if (!key.lower_inclusive && r.lower <= key.lower) r.lower = std::nextafter(key.lower, r.upper);
  if (!key.upper_inclusive && r.upper >= key.upper) r.upper = std::nextafter(key.upper, r.lower);
  return r;
}

bool IsStationKey(const ConfigKey& key) {
  const std::string_view last = LastSegment(key.path);
  return key.unit == "m" && (last == "position_m" || last == "centre_of_mass_m");
}

FitRange DefaultFitRange(const ConfigKey& key, const std::vector<ConfigKey>& keys) {
  const FitRange own = DefaultFitRange(key);
  if (!IsStationKey(key) || !std::isfinite(key.value)) return own;
  // A drawing or a mounting gets a station wrong by some part of the distance to the next
  // part along the shaft, never past it (a disc does not swap places with a bearing), and
  // whatever the axial origin: ten per cent of z was ten per cent of where the origin happened
  // to be (a station 3 cm from the NDE end could move 3 mm, one at 54 cm, 54 mm). Stations
  // within a millimetre of it (a sensor at its magnet, an unbalance at its disc) are its own.
  // Nor by more than a tenth of the machine (the span of its stations): two magnets with
  // nothing declared between them are not a magnet's length of doubt.
  constexpr double kSameStation_m = 1e-3;
  constexpr double kShareOfGap = 0.9;
  constexpr double kShareOfMachine = 0.1;
  double below = -std::numeric_limits<double>::infinity();
  double above = std::numeric_limits<double>::infinity();
  double first = key.value, last = key.value;
  for (const ConfigKey& k : keys) {
    if (&k == &key || k.path == key.path || !k.in_force || !IsStationKey(k) ||
        !std::isfinite(k.value)) {
      continue;
    }
    first = std::min(first, k.value);
    last = std::max(last, k.value);
    if (k.value < key.value - kSameStation_m) below = std::max(below, k.value);
    if (k.value > key.value + kSameStation_m) above = std::min(above, k.value);
  }
  if (!std::isfinite(below) && !std::isfinite(above)) return own;
  const double cap = kShareOfMachine * (last - first);
  const double gap_below = std::isfinite(below) ? key.value - below : above - key.value;
  const double gap_above = std::isfinite(above) ? above - key.value : key.value - below;
  FitRange r{key.value - std::min(kShareOfGap * gap_below, cap),
             key.value + std::min(kShareOfGap * gap_above, cap)};
  r.lower = std::max(r.lower, key.lower);
  r.upper = std::min(r.upper, key.upper);
  if (!key.lower_inclusive && r.lower <= key.lower) r.lower = std::nextafter(key.lower, r.upper);
  if (!key.upper_inclusive && r.upper >= key.upper) r.upper = std::nextafter(key.upper, r.lower);
  return r;
}

const ConfigKey* FindKey(const std::vector<ConfigKey>& keys, std::string_view path) {
  const auto it =
      std::find_if(keys.begin(), keys.end(), [&](const ConfigKey& k) { return k.path == path; });
  return it == keys.end() ? nullptr : &*it;
}

void KeyLog::Record(ConfigKey key) {
  const auto same = std::find_if(keys_.begin(), keys_.end(),
                                 [&](const ConfigKey& k) { return k.path == key.path; });
  if (same != keys_.end()) keys_.erase(same);
  keys_.push_back(std::move(key));
}

}  // namespace ambdrop
