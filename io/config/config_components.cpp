#include <fmt/format.h>

#include <optional>
#include <tuple>
#include <utility>

#include "io/config/config_readers.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop::config_detail {
namespace {

/// Either `both_key` for both axes or `x_key` together with `y_key`; nullopt when none is given.
std::optional<std::pair<double, double>> ReadAxisPair(const TableReader& table,
                                                      std::string_view both_key,
                                                      std::string_view x_key,
                                                      std::string_view y_key) {
  if (table.Has(both_key)) {
    for (const std::string_view key : {x_key, y_key}) {
      table.Reject(key, fmt::format("no {} next to {} (give {} for both axes, or {} and {})", key,
                                    both_key, both_key, x_key, y_key));
    }
    const double value = table.Number(both_key, NonNegative());
    return std::pair(value, value);
  }
  if (!table.Has(x_key) && !table.Has(y_key)) return std::nullopt;
  const double x = table.Number(x_key, NonNegative());
  const double y = table.Number(y_key, NonNegative());
  return std::pair(x, y);
}

}  // namespace

std::vector<LinearBearingParams> ReadBearings(const TableReader& root, const AxialRange& position) {
  const auto tables = root.NamedTables("bearing");
  root.CheckCount("bearing", tables.size(), kMaxLinearBearings, "linear bearings");
  std::vector<LinearBearingParams> bearings;
  for (const auto& [name, table] : tables) {
    table.AllowOnly({"position_m", "stiffness_N_per_m", "stiffness_x_N_per_m",
                     "stiffness_y_N_per_m", "damping_N_s_per_m", "damping_x_N_s_per_m",
                     "damping_y_N_s_per_m"});
    LinearBearingParams bearing;
    bearing.name = name;
    bearing.position_m = ReadAxialPosition(table, position);
    const auto stiffness =
        ReadAxisPair(table, "stiffness_N_per_m", "stiffness_x_N_per_m", "stiffness_y_N_per_m");
    if (!stiffness) {
      table.FailMissing("stiffness_N_per_m",
                        "a non-negative number (N/m), or stiffness_x_N_per_m and "
                        "stiffness_y_N_per_m");
    }
    std::tie(bearing.stiffness_x_N_per_m, bearing.stiffness_y_N_per_m) = *stiffness;
    const auto damping =
        ReadAxisPair(table, "damping_N_s_per_m", "damping_x_N_s_per_m", "damping_y_N_s_per_m");
    if (damping) std::tie(bearing.damping_x_N_s_per_m, bearing.damping_y_N_s_per_m) = *damping;
    bearings.push_back(std::move(bearing));
  }
  return bearings;
}

namespace {

// A sensor plane and its error models, each a switch (noise, runout, lag).
SensorParams ReadSensor(const std::string& name, const TableReader& table,
                        const AxialRange& position, const SensorSampling& sampling) {
  table.AllowOnly({"position_m", "gain", "gain_x", "gain_y", "offset_m", "offset_x_m", "offset_y_m",
                   "quantisation_m", "noise", "runout", "lag", "output", "counts_per_m",
                   "counts_offset"});
  SensorParams s;
  s.name = name;
  s.position_m = ReadAxialPosition(table, position);
  s.gain = table.Number("gain", AnyNumber(), s.gain);
  s.offset_m = table.Number("offset_m", AnyNumber(), s.offset_m);
  // One axis' own gain or offset overrides the common one. Absent, it is logged at the common
  // value (so that a fit can move one axis with --set) but left unset, so that the common key
  // keeps driving that axis.
  const auto per_axis = [&](std::string_view key, double common) -> std::optional<double> {
    const double value = table.Number(key, AnyNumber(), common);
    return table.Has(key) ? std::optional<double>(value) : std::nullopt;
  };
  s.gain_x = per_axis("gain_x", s.gain);
  s.gain_y = per_axis("gain_y", s.gain);
  s.offset_x_m = per_axis("offset_x_m", s.offset_m);
  s.offset_y_m = per_axis("offset_y_m", s.offset_m);
  s.quantisation_m = table.Number("quantisation_m", NonNegative(), s.quantisation_m);
  if (const auto noise = table.OptionalTable("noise")) {
    noise->AllowOnly({"enabled", "std_dev_m", "seed", "bandwidth_Hz"});
    s.noise.enabled = noise->Bool("enabled", false);
    // A disabled table does not demand its number; given, it is still checked.
    s.noise.std_dev_m = s.noise.enabled ? noise->Number("std_dev_m", NonNegative())
                                        : noise->Number("std_dev_m", NonNegative(), 0.0);
    s.noise.seed = static_cast<std::uint64_t>(noise->Integer("seed", 0, 2147483647, 1));
    s.noise.bandwidth_Hz = noise->Number("bandwidth_Hz", NonNegative(), 0.0);
  }
  if (const auto runout = table.OptionalTable("runout")) {
    runout->AllowOnly(
        {"enabled", "amplitude_1x_m", "phase_1x_rad", "amplitude_2x_m", "phase_2x_rad"});
    s.runout.enabled = runout->Bool("enabled", false);
    s.runout.amplitude_1x_m = runout->Number("amplitude_1x_m", NonNegative(), 0.0);
    s.runout.phase_1x_rad = runout->Number("phase_1x_rad", AnyNumber(), 0.0);
    s.runout.amplitude_2x_m = runout->Number("amplitude_2x_m", NonNegative(), 0.0);
    s.runout.phase_2x_rad = runout->Number("phase_2x_rad", AnyNumber(), 0.0);
  }
  if (const auto lag = table.OptionalTable("lag")) {
    lag->AllowOnly({"enabled", "delay_s", "cutoff_Hz"});
    s.lag.enabled = lag->Bool("enabled", false);
    // The lag holds whole samples in a ring of kMaxSensorDelaySamples.
    const double longest_s = (kMaxSensorDelaySamples - 1) * sampling.period_s;
    s.lag.delay_s = lag->Number(
        "delay_s",
        NumberRule{.lower = 0.0,
                   .upper = longest_s,
                   .what = fmt::format(
                       "at most {} samples of {} = {:.6g} s: a number in [0, {:.6g}]",
                       kMaxSensorDelaySamples - 1, sampling.what, sampling.period_s, longest_s)},
        0.0);
    s.lag.cutoff_Hz = lag->Number("cutoff_Hz", NonNegative(), 0.0);
  }
  const std::string output = table.Choice("output", {"metres", "counts"}, "metres");
  if (output == "counts") {
    s.output = SensorOutput::kCounts;
    // Bounded so that a reading within the excursion bound stays a 64-bit count (llround).
    s.counts_per_m =
        table.Number("counts_per_m", NumberRule{.lower = 0.0,
                                                .lower_inclusive = false,
                                                .upper = 1e12,
                                                .what = "a positive number of at most 1e12"});
    s.counts_offset = table.Number("counts_offset", InRange(-1e12, 1e12), 0.0);
  } else {
    table.Reject("counts_per_m", "no counts_per_m with output = \"metres\"");
    table.Reject("counts_offset", "no counts_offset with output = \"metres\"");
  }
  return s;
}

}  // namespace

std::vector<SensorParams> ReadSensors(const TableReader& root, const AxialRange& position,
                                      const SensorSampling& sampling) {
  const auto tables = root.NamedTables("sensor");
  root.CheckCount("sensor", tables.size(), kMaxSensors, "sensors");
  std::vector<SensorParams> sensors;
  for (const auto& [name, table] : tables) {
    sensors.push_back(ReadSensor(name, table, position, sampling));
  }
  return sensors;
}

std::vector<UnbalanceParams> ReadUnbalances(const TableReader& root, const AxialRange& position) {
  const auto tables = root.NamedTables("unbalance");
  root.CheckCount("unbalance", tables.size(), kMaxUnbalances, "unbalances");
  std::vector<UnbalanceParams> unbalances;
  for (const auto& [name, table] : tables) {
    table.AllowOnly({"enabled", "position_m", "mass_kg", "eccentricity_m", "phase_rad"});
    UnbalanceParams unbalance;
    unbalance.name = name;
    unbalance.enabled = table.Bool("enabled", unbalance.enabled);
    unbalance.position_m = ReadAxialPosition(table, position);
    // A disabled unbalance does not demand its numbers (its position still places a station);
    // given, they are still checked.
    // A named reference: a lambda may not capture a structured binding before C++20's clang 16.
    const auto& reader = table;
    const auto number = [&](std::string_view key) {
      return unbalance.enabled ? reader.Number(key, NonNegative())
                               : reader.Number(key, NonNegative(), 0.0);
    };
    unbalance.mass_kg = number("mass_kg");
    unbalance.eccentricity_m = number("eccentricity_m");
    unbalance.phase_rad = table.Number("phase_rad", AnyNumber(), unbalance.phase_rad);
    unbalances.push_back(std::move(unbalance));
  }
  return unbalances;
}

}  // namespace ambdrop::config_detail
