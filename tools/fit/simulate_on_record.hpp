#pragma once
// Step a of `ambdrop fit`: the declared model, driven by the record's measured inputs, on the
// record's time base. The run starts a short lead before the trigger from the state the
// displacement channels show then: AMB currents drive an open-loop, unstable plant, so a run
// started long before the trigger would drift away from the measurement on its own.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/simulator.hpp"
#include "tools/fit/levitated_prefix_cache.hpp"
#include "tools/fit/record_trigger_detect.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"

namespace ambdrop {

/// What drives the AMBs before the trigger.
enum class PreTrigger {
  /// The declared controller if the config has one, or AMBs of the equivalent law (closed loop
  /// from the record's start: the measured currents are then predictions to compare), else the
  /// measured currents.
  kAuto,
  kMeasuredCurrents,  ///< always the measured currents, from `lead_s` before the trigger
};

/// measurement.trigger_state = "record": corrections to the measured currents over the lead
/// window (lead_state_estimate.hpp): their noise, through a plant that the measured currents
/// drive open loop and that a magnet's bias makes unstable, would move the state at the trigger.
struct LeadCurrentCorrection {
  std::size_t first_row = 0;
  /// [amb][axis], by row from first_row (empty: none), interpolated between rows as the
  /// currents are.
  std::array<std::array<std::vector<double>, 2>, kMaxAmbs> A;
  /// The correction of an AMB axis at record time t (0 outside its rows).
  double At(const MeasuredRecord& r, std::size_t amb, int axis, double t) const;
};

struct RecordRunOptions {
  PreTrigger pre_trigger = PreTrigger::kAuto;
  double lead_s = 2e-3;  ///< open loop: simulated time before the trigger
  /// Model step; 0: the config's. The record's samples fall on the nearest step.
  double step_s = 0.0;
  /// Record time after which no row is wanted: the run stops there (rows after it stay NaN).
  /// A cost that compares only the drop's start need not pay for its whole settling.
  double end_s = std::numeric_limits<double>::infinity();
  /// Shared by the runs of one fit (copies of these options share it): the rig's rotor is
  /// reduced once. Null: each run reduces it.
  std::shared_ptr<ReducedRotorCache> rotor_cache;
  /// Shared by the runs of one fit: closed-loop runs whose levitated time repeats an earlier
  /// run's resume from it (levitated_prefix_cache.hpp). Null: every run from its start.
  std::shared_ptr<LevitatedPrefixCache> prefix_cache;
  /// Open loop: added to every displacement channel's value and slope at the start before the
  /// initial state is fitted to them; the start sensitivity's probes of how closely the record's
  /// noise pins that state (tools/fit/start_sensitivity.cpp).
  double start_position_shift_m = 0.0;
  double start_velocity_shift_m_s = 0.0;
  /// Open loop: start from this state (its time restarts at the run's start) instead of the
  /// one fitted to the record; with `state_correction` (modal positions then velocities, 2n)
  /// added to it. Used by the lead estimate of measurement.trigger_state = "record".
  std::shared_ptr<const State> initial_state;
  Eigen::VectorXd state_correction;
  /// Added to the measured currents that drive the run before the trigger (null: none).
  std::shared_ptr<const LeadCurrentCorrection> lead_current_correction;
  /// measurement.trigger_state = "record": added to the state at the trigger (2n, modal
  /// positions then velocities): the start sensitivity's probes along the uncertainty of the
  /// lead window's estimate (SimulatedRecord::lead_uncertainty).
  Eigen::VectorXd trigger_state_shift;
  /// Added to the current each measured AMB axis held when the power failed ([amb][axis]):
  /// the start sensitivity's probes of SimulatedRecord::held_current_sd_A.
  std::array<std::array<double, 2>, kMaxAmbs> held_current_shift_A{};
  /// Closed loop: the declared controller answers sensor noise of this standard deviation (m),
  /// drawn from `jitter_seed`, as the real rotor's does: the rotor's jitter when the power
  /// fails, which no model reproduces sample by sample (0: noise off, the expected reading).
  /// The predicted readings stay the expected ones (noise off).
  double jitter_sigma_m = 0.0;
  std::uint64_t jitter_seed = 1;
  /// That noise's first-order bandwidth (SensorNoiseParams::bandwidth_Hz), as the record's
  /// sensors show it (tools/fit/sensor_noise_colour.hpp); 0: white.
  double jitter_bandwidth_Hz = 0.0;
  /// Keep the modal positions and velocities at every simulated row (SimulatedRecord::states).
  bool keep_states = false;
};

/// Open loop: the initial state is fitted to a quadratic through each displacement channel's
/// samples within this many seconds of the start.
double OpenLoopStartHalfWindow(const MeasuredRecord& record);
/// The standard errors of that fit's value and slope at `t_start` per unit of the samples'
/// noise (m and m/s per m of noise): how closely a record pins the open-loop start.
std::pair<double, double> OpenLoopStartUncertainty(const MeasuredRecord& record, double t_start);

/// The declared model's own run on the record stops early (it diverged): what() says where,
/// why, and the state dump. Nothing can be held against a model that cannot run the record.
class DeclaredModelStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What the model says each measured channel should read.
struct SimulatedRecord {
  double trigger_time_s = 0.0;  ///< record time
  bool closed_loop = false;     ///< the currents are predictions before the trigger too
  std::size_t first_row = 0;    ///< first row simulated; rows before it are NaN
  std::size_t rows = 0;         ///< rows simulated (first_row + rows <= record rows)
  /// values[c][row] for channel c of MeasurementParams::channels, NaN where not simulated.
  std::vector<std::vector<double>> values;
  StepStatus status = StepStatus::kOk;
  std::string failure;  ///< why the run stopped early, with a state dump; "" if it did not
  /// measurement.trigger_state = "record": one standard deviation of the estimated state at
  /// the trigger along each of its (at most three) principal axes where the sensors see it,
  /// and along every principal axis of its scaled covariance (lead_state_estimate.hpp).
  std::vector<Eigen::VectorXd> lead_uncertainty;
  std::vector<Eigen::VectorXd> lead_uncertainty_all;
  /// The standard error of the current each AMB axis held when the power failed, where the
  /// declared law was fitted to the coil current's samples after the trigger (else 0).
  std::array<std::array<double, 2>, kMaxAmbs> held_current_sd_A{};
  /// With RecordRunOptions::keep_states: the modal positions and velocities (2n) when each
  /// simulated row was taken (empty for the others).
  std::vector<Eigen::VectorXd> states;
  /// ... and what that fit did, or why it kept the model's own state (LeadStateFit::note);
  /// "" without measurement.trigger_state = "record".
  std::string lead_fit;
  /// The RMS of the lead window's samples that fit leaves, in units of their noise
  /// (LeadStateFit::misfit); NaN without it.
  double lead_misfit = std::numeric_limits<double>::quiet_NaN();
  /// What the run was made of: its params and options, and whether its state at the trigger is
  /// the lead window's estimate. A cost whose start differs (measurement.trigger_state =
  /// "record_start": the drop's start from the estimate, the rest from the model's own state)
  /// runs them again its own way (RecordCost::Residual).
  std::shared_ptr<const ModelParams> params;
  RecordRunOptions options;
  bool state_from_record = false;
};

/// Whether the run is closed loop (the declared controller levitates the rotor until the
/// trigger) for these params, options and measurement: never with power_loss = "from_record",
/// whose currents drive the model from the run's start.
bool ClosedLoop(const ModelParams& params, const MeasurementParams& measurement,
                const RecordRunOptions& options);

/// Closed loop: the declared rig and controller run from time 0, as `ambdrop sim` would, with
/// the power failing at the record's trigger, sampled at the record's times (each row takes
/// the sample nearest to it); every channel, currents included, is a prediction.
/// Open loop: model time 0 is record time max(t_first, trigger - lead).
/// Before the trigger the measured currents drive the AMBs (an AMB axis without a current
/// channel carries its static load); at the trigger the rig's power failure ([trigger] ambs and
/// axes) happens. The initial rotor position and velocity are the least-squares fit of the
/// modal coordinates to the displacement channels around the start (through the sensors' gain
/// and offset), the spin speed is the rotor_speed channel's (or the config's), and the spin
/// angle is the config's speed times the start time (a rig spinning steadily from time 0).
/// With power_loss = "from_record" the coil-current channels go on driving their axes after the
/// trigger (rt_core/power_loss_drive.hpp, RecordedCurrentDrive) and their predicted values are
/// the record's own (inputs, not compared).
/// Predicted readings come through the declared sensor model without noise or quantisation.
SimulatedRecord SimulateOnRecord(const ModelParams& params, const MeasurementParams& measurement,
                                 const MeasuredRecord& record, const RecordRunOptions& options);

}  // namespace ambdrop
