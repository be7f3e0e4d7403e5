#include <fmt/format.h>

#include "io/config/config_readers.hpp"

namespace ambdrop::config_detail {
namespace {

// simulation.max_steps itself: far below int64, so that any step index and count stays exact.
constexpr std::int64_t kMaxStepsCeiling = std::int64_t{1} << 53;

}  // namespace

SimulationParams ReadSimulation(const TableReader& root) {
  SimulationParams params;
  const auto table = root.OptionalTable("simulation");
  if (!table) return params;
  table->AllowOnly({"step_s", "duration_s", "output_interval_s", "spin_speed_rad_s",
                    "initial_position", "settle_s", "max_excursion_over_clearance", "max_steps"});
  params.step_s = table->Number("step_s", Positive(), params.step_s);
  params.max_steps = table->Integer64("max_steps", 1, kMaxStepsCeiling, params.max_steps);
  // The steps are counted in int64 (llround of duration / step): beyond max_steps a run would
  // take days, beyond int64 it would not run at all.
  const double longest_s = static_cast<double>(params.max_steps) * params.step_s;
  // The error points at the key that made the run too long.
  const char* duration_key = table->Has("duration_s") ? "duration_s"
                             : table->Has("step_s")   ? "step_s"
                                                      : "max_steps";
  params.duration_s = table->Number("duration_s", Positive(), params.duration_s);
  if (!(params.duration_s <= longest_s)) {
    table->Fail(duration_key,
                fmt::format("simulation.duration_s <= {:.6g} s: at most simulation.max_steps = {} "
                            "steps of {:.6g} s (raise simulation.max_steps for a longer run)",
                            longest_s, params.max_steps, params.step_s),
                fmt::format("duration_s = {:.6g} s, {:.6g} steps", params.duration_s,
                            params.duration_s / params.step_s));
  }
  // Output is sampled from the integration steps, so it cannot be finer than one step.
  params.output_interval_s = table->Number(
      "output_interval_s",
      NumberRule{.lower = params.step_s,
                 .upper = longest_s,
                 .what = fmt::format("a number in [simulation.step_s, simulation.max_steps * "
                                     "simulation.step_s] = [{}, {:.6g}]",
                                     params.step_s, longest_s)},
      params.output_interval_s);
  params.spin_speed_rad_s =
      table->Number("spin_speed_rad_s", NonNegative(), params.spin_speed_rad_s);
  const std::string initial =
      table->Choice("initial_position", {"equilibrium", "centred"}, "equilibrium");
  params.initial_position =
      initial == "centred" ? InitialPosition::kCentred : InitialPosition::kEquilibrium;
  params.settle_s = table->Number(
      "settle_s",
      NumberRule{.lower = 0.0,
                 .upper = longest_s,
                 .what = fmt::format("a number in [0, simulation.max_steps * simulation.step_s] "
                                     "= [0, {:.6g}] (s)",
                                     longest_s)},
      params.settle_s);
  params.max_excursion_over_clearance = table->Number("max_excursion_over_clearance", Positive(),
                                                      params.max_excursion_over_clearance);
  return params;
}

GravityParams ReadGravity(const TableReader& root) {
  GravityParams params;
  const auto table = root.OptionalTable("gravity");
  if (!table) return params;
  table->AllowOnly({"enabled", "acceleration_m_s2"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.acceleration_m_s2 =
      table->Number("acceleration_m_s2", NonNegative(), params.acceleration_m_s2);
  return params;
}

TriggerParams ReadTrigger(const TableReader& root) {
  TriggerParams params;
  const auto table = root.OptionalTable("trigger");
  if (!table) return params;
  table->AllowOnly({"enabled", "time_s", "restore_time_s", "ambs", "axes"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.time_s = table->Number("time_s", NonNegative(), params.time_s);
  if (table->Has("restore_time_s")) {
    params.restore_time_s = table->Number(
        "restore_time_s",
        NumberRule{.lower = params.time_s,
                   .lower_inclusive = false,
                   .what = fmt::format("a number > trigger.time_s = {}", params.time_s)});
  }
  if (const toml::array* ambs = table->OptionalArray("ambs", "an array of AMB names")) {
    for (std::size_t i = 0; i < ambs->size(); ++i) {
      const auto* name = (*ambs)[i].as_string();
      if (name == nullptr) {
        ThrowBadValue((*ambs)[i], table->source_name(), table->KeyPath("ambs"),
                      "an array of AMB names (strings)");
      }
      params.ambs.push_back(name->get());
    }
  }
  const std::string axes = table->Choice("axes", {"xy", "x", "y"}, "xy");
  params.axis_x = axes != "y";
  params.axis_y = axes != "x";
  return params;
}

}  // namespace ambdrop::config_detail
