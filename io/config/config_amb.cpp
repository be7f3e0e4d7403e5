#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>

#include "io/config/config_readers.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop::config_detail {
namespace {

constexpr std::string_view kEquivalent = "equivalent";
constexpr std::string_view kLinearised = "linearised_currents";
constexpr std::string_view kElectromagnet = "electromagnet";

const std::vector<std::string_view> kEquivalentKeys = {"stiffness_N_per_m", "damping_N_s_per_m",
                                                       "gravity_compensation"};
const std::vector<std::string_view> kLinearisedKeys = {"current_gain_N_per_A",
                                                       "position_gain_N_per_m", "current_profile"};
constexpr std::string_view kPermanentMagnet = "permanent_magnet";

/// Keys of the other force law get a message naming the law, not just "unknown key".
void RejectKeysOfOtherLaw(const TableReader& table, std::string_view law,
                          const std::vector<std::string_view>& keys, std::string_view other_law) {
  for (const std::string_view key : keys) {
    table.Reject(key, fmt::format("no {} with law = \"{}\" (it belongs to law = \"{}\")", key, law,
                                  other_law));
  }
}

std::optional<double> FiniteNumber(const toml::node& node) {
  double value = 0.0;
  if (const auto* integer = node.as_integer()) {
    value = static_cast<double>(integer->get());
  } else if (const auto* floating = node.as_floating_point()) {
    value = floating->get();
  } else {
    return std::nullopt;
  }
  if (!std::isfinite(value)) return std::nullopt;
  return value;
}

std::vector<CurrentSample> ReadCurrentProfile(const TableReader& table) {
  const toml::array* points = table.OptionalArray(
      "current_profile", "an array of [time_s, current_x_A, current_y_A] triples");
  if (points == nullptr) return {};
  if (points->size() > static_cast<std::size_t>(kMaxProfilePoints)) {
    table.Fail("current_profile", fmt::format("at most {} points", kMaxProfilePoints),
               fmt::format("{} points", points->size()));
  }
  std::vector<CurrentSample> profile;
  for (std::size_t i = 0; i < points->size(); ++i) {
    const toml::node& point = (*points)[i];
    const std::string path = fmt::format("{}[{}]", table.KeyPath("current_profile"), i);
    const auto fail = [&](std::string_view expected) {
      ThrowBadValue(point, table.source_name(), path, expected);
    };
    const std::string_view expected_triple =
        "a triple [time_s, current_x_A, current_y_A] of finite numbers (s, A, A)";
    const toml::array* triple = point.as_array();
    if (triple == nullptr || triple->size() != 3) fail(expected_triple);
    std::optional<double> values[3];
    for (std::size_t j = 0; j < 3; ++j) {
      values[j] = FiniteNumber((*triple)[j]);
      if (!values[j]) fail(expected_triple);
    }
    // Interpolation between points needs a strictly increasing time axis.
    if (!profile.empty() && *values[0] <= profile.back().time_s) {
      fail(fmt::format("a time_s greater than that of the previous point ({} s)",
                       profile.back().time_s));
    }
    profile.push_back(
        CurrentSample{.time_s = *values[0], .current_x_A = *values[1], .current_y_A = *values[2]});
  }
  return profile;
}

// Keys every law accepts.
const std::vector<std::string_view> kCommonKeys = {"position_m", "law", "current_limit_A",
                                                   "flux_decay", "sensor"};

std::vector<std::string_view> WithCommon(std::vector<std::string_view> keys) {
  keys.insert(keys.end(), kCommonKeys.begin(), kCommonKeys.end());
  return keys;
}

void ReadCommon(const TableReader& table, const AxialRange& position, AmbParams* amb) {
  amb->position_m = ReadAxialPosition(table, position);
  amb->current_limit_A = table.Number("current_limit_A", Positive(), amb->current_limit_A);
  amb->sensor = table.String("sensor", amb->name);
  if (amb->law != AmbForceLaw::kEquivalent &&
      table.Choice("bias_source", {kElectromagnet, kPermanentMagnet}, kElectromagnet) ==
          kPermanentMagnet) {
    amb->bias_source = AmbBiasSource::kPermanentMagnet;
  }
  amb->flux_decay = ReadFluxDecay(table, *amb);
}

ElectromagnetParams ReadElectromagnet(const TableReader& amb) {
  const TableReader table = amb.Table("electromagnet");
  table.AllowOnly({"constant_N_m2_per_A2", "pole_area_m2", "turns", "nominal_gap_m",
                   "bias_current_A", "pole_half_angle_rad", "saturation"});
  ElectromagnetParams e;
  // k either as a rig sheet gives it or from the geometry it comes from, never both.
  const bool direct = table.Has("constant_N_m2_per_A2");
  if (direct) {
    for (const std::string_view key : {"pole_area_m2", "turns", "pole_half_angle_rad"}) {
      table.Reject(key, fmt::format("no {} next to constant_N_m2_per_A2 (give k directly, or "
                                    "turns, pole_area_m2 and pole_half_angle_rad that make it)",
                                    key));
    }
    e.constant_N_m2_per_A2 = table.Number("constant_N_m2_per_A2", Positive());
  } else {
    e.pole_area_m2 = table.Number("pole_area_m2", Positive());
    e.turns = table.Number("turns", Positive());
  }
  e.nominal_gap_m = table.Number("nominal_gap_m", Positive());
  e.bias_current_A = table.Number("bias_current_A", Positive());
  if (!direct) {
    e.pole_half_angle_rad = table.Number(
        "pole_half_angle_rad", InHalfOpenRange(0.0, 1.5707963267948966), e.pole_half_angle_rad);
  }
  if (const std::optional<TableReader> saturation = table.OptionalTable("saturation")) {
    saturation->AllowOnly({"enabled", "flux_density_T"});
    e.saturation_enabled = saturation->Bool("enabled", false);
    // The flux density caps the force through the pole face, B^2 A cos(alpha) / mu0: without
    // the geometry there is no face to cap it.
    if (direct && e.saturation_enabled) {
      saturation->Fail("enabled",
                       "false with constant_N_m2_per_A2 (saturation needs the pole geometry: give "
                       "turns, pole_area_m2 and pole_half_angle_rad instead of k)",
                       "true");
    }
    // A disabled table does not demand its number; given, it is still checked.
    e.saturation_flux_density_T = e.saturation_enabled
                                      ? saturation->Number("flux_density_T", Positive())
                                      : saturation->Number("flux_density_T", Positive(), 0.0);
  }
  return e;
}

AmbParams ReadAmb(const std::string& name, const TableReader& table, const AxialRange& position) {
  AmbParams amb;
  amb.name = name;
  const std::string law =
      table.Choice("law", {kEquivalent, kLinearised, kElectromagnet}, kEquivalent);
  if (law == kEquivalent) {
    RejectKeysOfOtherLaw(table, kEquivalent, kLinearisedKeys, kLinearised);
    table.Reject("electromagnet",
                 "no electromagnet table with law = \"equivalent\" (it belongs to law = "
                 "\"electromagnet\")");
    table.Reject("bias_source",
                 "no bias_source with law = \"equivalent\" (its stiffness holds the bias; declare "
                 "law = \"linearised_currents\" or \"electromagnet\")");
    table.AllowOnly(WithCommon({"stiffness_N_per_m", "damping_N_s_per_m", "gravity_compensation"}));
    amb.law = AmbForceLaw::kEquivalent;
    ReadCommon(table, position, &amb);
    amb.stiffness_N_per_m = table.Number("stiffness_N_per_m", NonNegative());
    amb.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
    amb.gravity_compensation = table.Bool("gravity_compensation", amb.gravity_compensation);
    return amb;
  }
  RejectKeysOfOtherLaw(table, law, kEquivalentKeys, kEquivalent);
  if (law == kLinearised) {
    table.Reject("electromagnet",
                 "no electromagnet table with law = \"linearised_currents\" (it belongs to law = "
                 "\"electromagnet\")");
    table.AllowOnly(WithCommon(
        {"current_gain_N_per_A", "position_gain_N_per_m", "current_profile", "bias_source"}));
    amb.law = AmbForceLaw::kLinearisedCurrents;
    ReadCommon(table, position, &amb);
    amb.current_gain_N_per_A = table.Number("current_gain_N_per_A", AnyNumber());
    amb.position_gain_N_per_m = table.Number("position_gain_N_per_m", NonNegative());
    amb.current_profile = ReadCurrentProfile(table);
    return amb;
  }
  table.Reject("current_gain_N_per_A",
               "no current_gain_N_per_A with law = \"electromagnet\" (the geometry sets it)");
  table.Reject("position_gain_N_per_m",
               "no position_gain_N_per_m with law = \"electromagnet\" (the geometry sets it)");
  table.AllowOnly(WithCommon({"electromagnet", "current_profile", "bias_source"}));
  amb.law = AmbForceLaw::kElectromagnet;
  ReadCommon(table, position, &amb);
  amb.electromagnet = ReadElectromagnet(table);
  amb.current_profile = ReadCurrentProfile(table);
  return amb;
}

}  // namespace

std::vector<AmbParams> ReadAmbs(const TableReader& root, const AxialRange& position) {
  const auto tables = root.NamedTables("amb");
  root.CheckCount("amb", tables.size(), kMaxAmbs, "magnetic bearings");
  std::vector<AmbParams> ambs;
  for (const auto& [name, table] : tables) ambs.push_back(ReadAmb(name, table, position));
  return ambs;
}

}  // namespace ambdrop::config_detail
