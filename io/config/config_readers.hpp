#pragma once
// One reader per section of the config schema (see config_loader.hpp). Each checks its own keys
// strictly and throws ConfigError on the first problem.
#include <limits>
#include <string>
#include <vector>

#include "io/config/toml_reader.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::config_detail {

SimulationParams ReadSimulation(const TableReader& root);
GravityParams ReadGravity(const TableReader& root);
TriggerParams ReadTrigger(const TableReader& root);

RotorParams ReadRotor(const TableReader& root);
/// `step_s`: the physics step, of which a given controller.rate_Hz's period must be a whole number.
ControllerParams ReadController(const TableReader& root, double step_s);

/// Where components may sit: on the shaft for a flexible rotor, anywhere finite for a rigid one.
struct AxialRange {
  NumberRule rule;
  double end_m = std::numeric_limits<double>::infinity();  ///< shaft length
};
AxialRange ShaftRange(const RotorParams& rotor);

/// The table's required `position_m`, within `range`.
double ReadAxialPosition(const TableReader& table, const AxialRange& range);

std::vector<LinearBearingParams> ReadBearings(const TableReader& root, const AxialRange& position);
std::vector<AmbParams> ReadAmbs(const TableReader& root, const AxialRange& position);
/// `amb_table`'s optional flux_decay table; `amb` holds the AMB's law and bias source.
FluxDecayParams ReadFluxDecay(const TableReader& amb_table, const AmbParams& amb);
/// The period at which the sensors are sampled (it bounds a lag), and how a message names it.
struct SensorSampling {
  double period_s = 0.0;
  std::string what;  ///< "the controller period (1/controller.rate_Hz)"
};
std::vector<SensorParams> ReadSensors(const TableReader& root, const AxialRange& position,
                                      const SensorSampling& sampling);
std::vector<TdbParams> ReadTdbs(const TableReader& root, const AxialRange& position);
std::vector<UnbalanceParams> ReadUnbalances(const TableReader& root, const AxialRange& position);

}  // namespace ambdrop::config_detail
