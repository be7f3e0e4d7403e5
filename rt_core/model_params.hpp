#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rt_core/amb_params.hpp"
#include "rt_core/controller_form_params.hpp"
#include "rt_core/rotor_params.hpp"
#include "rt_core/tdb_params.hpp"

namespace ambdrop {

/// Zero-mean noise added to each sample, approximately Gaussian (Irwin-Hall sum of 12 uniforms,
/// bounded at +-6 sigma) from a seeded xoshiro256** stream, so runs repeat on any platform.
struct SensorNoiseParams {
  bool enabled = false;
  double std_dev_m = 0.0;
  std::uint64_t seed = 1;
  /// The sensor electronics' first-order bandwidth the noise passes (Hz): a coloured noise of
  /// the same std_dev_m, an AR(1) sequence at the sample period (0: white, one draw a sample).
  double bandwidth_Hz = 0.0;
  friend bool operator==(const SensorNoiseParams&, const SensorNoiseParams&) = default;
};

/// Synchronous runout: a pattern on the rotor surface that turns with it (1X and 2X).
struct SensorRunoutParams {
  bool enabled = false;
  double amplitude_1x_m = 0.0;
  double phase_1x_rad = 0.0;
  double amplitude_2x_m = 0.0;
  double phase_2x_rad = 0.0;
  friend bool operator==(const SensorRunoutParams&, const SensorRunoutParams&) = default;
};

/// Transport delay and first-order low-pass of the sensor electronics.
struct SensorLagParams {
  bool enabled = false;
  double delay_s = 0.0;    ///< between controller samples: read between them, linearly
  double cutoff_Hz = 0.0;  ///< 0: no filter
  friend bool operator==(const SensorLagParams&, const SensorLagParams&) = default;
};

enum class SensorOutput { kMetres, kCounts };

/// A displacement-sensor plane: what the controller reads is
///   gain_a * (displacement_a + runout_a) + offset_a   (per axis a = x, y),
/// delayed, filtered, plus noise, quantised, in metres or in ADC counts
/// (counts = round(reading * counts_per_m + counts_offset)).
struct SensorParams {
  std::string name;
  double position_m = 0.0;
  double gain = 1.0;      ///< m/m, a scale error of both axes (unless gain_x / gain_y is given)
  double offset_m = 0.0;  ///< of both axes (unless offset_x_m / offset_y_m is given)
  /// One axis' own gain and offset (a probe drifted on one axis); absent: the common value.
  std::optional<double> gain_x;
  std::optional<double> gain_y;
  std::optional<double> offset_x_m;
  std::optional<double> offset_y_m;
  /// The gain (m/m) and offset (m) of axis 0 (x) or 1 (y).
  double AxisGain(int axis) const noexcept { return (axis == 0 ? gain_x : gain_y).value_or(gain); }
  double AxisOffset_m(int axis) const noexcept {
    return (axis == 0 ? offset_x_m : offset_y_m).value_or(offset_m);
  }
  double quantisation_m = 0.0;  ///< 0: none
  SensorNoiseParams noise;
  SensorRunoutParams runout;
  SensorLagParams lag;
  SensorOutput output = SensorOutput::kMetres;
  double counts_per_m = 0.0;
  double counts_offset = 0.0;
  friend bool operator==(const SensorParams&, const SensorParams&) = default;
};

/// Seed 003's PID, per radial axis: i = Ga (kp e + ki/s e + kd s/(1 + tau_d s) e) with
/// e = -Gs * reading, plus the feedforward current that holds the static load.
struct PidParams {
  double sensor_gain_V_per_m = 20000.0;  ///< Gs
  double amplifier_gain_A_per_V = 0.4;   ///< Ga
  double kp = 0.0;
  double ki_per_s = 0.0;
  double kd_s = 0.0;
  double derivative_filter_s = 0.0;  ///< tau_d
  bool gravity_feedforward = true;
  friend bool operator==(const PidParams&, const PidParams&) = default;
};

enum class ControllerKind {
  kNone,         ///< currents from the AMBs' current profiles
  kInternalPid,  ///< the in-process controller (its form: ControllerParams::form)
};

struct ControllerParams {
  ControllerKind kind = ControllerKind::kNone;
  double rate_Hz = 20000.0;  ///< controller sample rate; an integer number of physics steps
  PidParams pid;
  ControllerForm form = ControllerForm::kPid;
  LinearControllerParams linear;
  int delay_samples = 0;  ///< the command computed from sample n is applied at sample n + d
  AmplifierParams amplifier;
  friend bool operator==(const ControllerParams&, const ControllerParams&) = default;
};

struct GravityParams {
  bool enabled = true;
  double acceleration_m_s2 = 9.81;  ///< along -y
  friend bool operator==(const GravityParams&, const GravityParams&) = default;
};

/// Scheduled shutdown: the AMB forces vanish at this time (with flux decay, they fade). It can
/// be partial (some AMBs, some axes: the motor keeps running) and power can come back.
struct TriggerParams {
  bool enabled = true;
  double time_s = 0.2;
  double restore_time_s = -1.0;   ///< power returns at this time; < 0: never
  std::vector<std::string> ambs;  ///< AMBs that lose power; empty: all (a full power failure)
  bool axis_x = true;             ///< axes that lose power
  bool axis_y = true;
  friend bool operator==(const TriggerParams&, const TriggerParams&) = default;
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
  /// Opt-in settled start (s): the in-process closed loop runs this long, powered and without
  /// trigger or output, before the run's t = 0, so that its filters, integrators and the
  /// rotor's synchronous orbit start steady (controller_if/loop/settled_start.hpp). 0: the run
  /// starts at the levitated equilibrium (rt_core/levitated_start.hpp).
  double settle_s = 0.0;
  /// Divergence guard: the run stops when a journal leaves its TDB by more than this many
  /// clearances, or a state becomes non-finite.
  double max_excursion_over_clearance = 50.0;
  /// Ceiling on duration_s / step_s: a run beyond it is a config error, not days of computing
  /// (1e9 steps: 5000 s at the default step; about 10 min at 1.6 M steps/s).
  std::int64_t max_steps = 1'000'000'000;
  friend bool operator==(const SimulationParams&, const SimulationParams&) = default;
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
  ControllerParams controller;
  friend bool operator==(const ModelParams&, const ModelParams&) = default;
};

}  // namespace ambdrop
