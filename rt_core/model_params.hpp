#pragma once
#include <string>
#include <vector>

#include "rt_core/amb_params.hpp"
#include "rt_core/rotor_params.hpp"
#include "rt_core/tdb_params.hpp"

namespace ambdrop {

struct SensorParams {
  std::string name;
  double position_m = 0.0;
};

struct GravityParams {
  bool enabled = true;
  double acceleration_m_s2 = 9.81;  ///< along -y
};

/// Scheduled shutdown: the AMB forces vanish at this time.
struct TriggerParams {
  bool enabled = true;
  double time_s = 0.2;
};

enum class InitialPosition {
  kEquilibrium,  ///< static equilibrium of the levitated rotor (pre-trigger forces)
  kCentred,      ///< every coordinate zero
};

struct SimulationParams {
  double step_s = 5e-6;
  double duration_s = 1.0;
  double output_interval_s = 5e-5;
  double spin_speed_rad_s = 0.0;  ///< held by the motor until the trigger
  InitialPosition initial_position = InitialPosition::kEquilibrium;
  /// Divergence guard: the run stops when a journal leaves its TDB by more than this many
  /// clearances, or a state becomes non-finite.
  double max_excursion_over_clearance = 50.0;
};

/// Everything a config describes; immutable once a Model is built from it.
struct ModelParams {
  std::string name;
  RotorParams rotor;
  std::vector<LinearBearingParams> bearings;
  std::vector<AmbParams> ambs;
  std::vector<TdbParams> tdbs;
  std::vector<SensorParams> sensors;
  std::vector<UnbalanceParams> unbalances;
  GravityParams gravity;
  TriggerParams trigger;
  SimulationParams simulation;
};

}  // namespace ambdrop
