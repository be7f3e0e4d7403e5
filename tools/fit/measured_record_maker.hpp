#pragma once
// Measured-like records made from a truth rig: the rig run offline at its own (fine) step, sampled
// at a logger's rate through the emulator's own sensor model, with seeded noise added to the
// other channels. Issue 6 fits analysed configs to such records, where the truth is known.
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

/// The groups of channels a record carries (`--channels`).
struct MeasureChannelGroups {
  bool displacement = true;      ///< x_<sensor>, y_<sensor>: sensor readings (m)
  bool current = true;           ///< i_<amb>_x, i_<amb>_y: commanded control currents (A)
  bool tdb_normal_force = true;  ///< f_<tdb>: normal force (N)
  bool tdb_speed = true;         ///< w_<tdb>: inner-race speed (rad/s)
  bool rotor_speed = true;       ///< w_rotor (rad/s)
  /// cmd_<amb>_x, cmd_<amb>_y: the controller's commanded currents (A), which go on after
  /// power loss where i_* fades.
  bool controller_command = false;
  /// fs_<tdb>_x, fs_<tdb>_y: the support force a load cell under the TDB reads (N, untared).
  bool tdb_support_force = false;
};

struct MeasureOptions {
  double rate_Hz = 0.0;  ///< sample rate; 0: the truth config's controller.rate_Hz
  MeasureChannelGroups channels;
  /// Standard deviations of the additive noise (approximately Gaussian, PortableRandom).
  double current_noise_A = 0.0;  ///< on coil currents and controller commands
  double force_noise_N = 0.0;    ///< on normal and support forces
  double speed_noise_rad_s = 0.0;
  std::uint64_t seed = 1;  ///< of the additive noise; sensor noise keeps the config's seeds
  /// Rows before this run time are left out; t stays run time.
  double from_s = 0.0;
  std::function<void(double fraction_done)> on_progress;
};

/// A record and the [measurement] table that describes it to an analysed config.
struct SyntheticMeasurement {
  MeasuredRecord record;
  MeasurementParams measurement;  ///< one channel per record column, in column order
};

/// The truth run diverged; what() has the failure message and state dump.
class TruthRunDiverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Physics steps per sample at `rate_Hz`; throws std::invalid_argument unless whole.
std::int64_t StepsPerSample(const SimulationParams& simulation, double rate_Hz);

/// Runs the truth rig (with its output interval set to the sample period) and samples it.
/// Same inputs, same record, bit for bit. Throws TruthRunDiverged, std::invalid_argument (the
/// rate, a model that cannot be built, no row at or after from_s, two columns of one name).
SyntheticMeasurement MakeMeasuredRecord(const ModelParams& truth, const MeasureOptions& options);

/// The [measurement] table text (io/config/config_measurement.hpp) for an analysed config of the
/// same rig; names are the truth config's sensors, AMBs and TDBs.
std::string MeasurementTableToml(const ModelParams& truth, const MeasurementParams& measurement);

}  // namespace ambdrop
