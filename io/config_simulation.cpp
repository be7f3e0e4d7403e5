#include <fmt/format.h>

#include "io/config_readers.hpp"

namespace ambdrop::config_detail {

SimulationParams ReadSimulation(const TableReader& root) {
  SimulationParams params;
  const auto table = root.OptionalTable("simulation");
  if (!table) return params;
  table->AllowOnly({"step_s", "duration_s", "output_interval_s", "spin_speed_rad_s",
                    "initial_position", "max_excursion_over_clearance"});
  params.step_s = table->Number("step_s", Positive(), params.step_s);
  params.duration_s = table->Number("duration_s", Positive(), params.duration_s);
  // Output is sampled from the integration steps, so it cannot be finer than one step.
  params.output_interval_s = table->Number(
      "output_interval_s",
      AtLeast(params.step_s, fmt::format("a number >= simulation.step_s = {}", params.step_s)),
      params.output_interval_s);
  params.spin_speed_rad_s =
      table->Number("spin_speed_rad_s", NonNegative(), params.spin_speed_rad_s);
  const std::string initial =
      table->Choice("initial_position", {"equilibrium", "centred"}, "equilibrium");
  params.initial_position =
      initial == "centred" ? InitialPosition::kCentred : InitialPosition::kEquilibrium;
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
  table->AllowOnly({"enabled", "time_s"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.time_s = table->Number("time_s", NonNegative(), params.time_s);
  return params;
}

}  // namespace ambdrop::config_detail
