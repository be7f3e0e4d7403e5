#pragma once
// measurement.trigger_state = "record": where the rotor really was when the power failed.
// The record's noise moves a levitated rotor by more than any model predicts sample by sample
// (its controller answers that noise), and a rotor that the power loss leaves unstable (a
// magnet's bias keeps its negative stiffness) goes where that motion sends it. So over a lead
// window before the trigger the model is driven open loop by the record's measured currents,
// from its own closed-loop state at the window's start, and both are fitted to the window's
// displacement samples: every modal coordinate and velocity of that state, without a prior
// (over the window the modes' own frequencies tell apart what the sensors' shapes alone cannot:
// a bending mode left at the model's own jitter sent the drop elsewhere), and corrections of
// the measured
// currents, with their own noise as the prior (a maximum a posteriori estimate, as a
// fixed-interval smoother would make it). The currents' noise matters: through a plant that is
// unstable without its controller, 5 mA of it over 6 ms moved the drop's first 8 ms by 10 % on
// the independent flexible rig. One Gauss-Newton step on finite-difference sensitivities: the
// levitated motion is micrometres, where the plant is linear. A window through the model pins
// the velocity far better than a local polynomial when the rotor jitters at hundreds of hertz.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model.hpp"
#include "rt_core/state.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// The lead window's length for a record: 6 ms and at least 40 samples.
double TriggerStateLeadSeconds(const MeasuredRecord& record);

/// The fit of the lead window: the correction (modal positions then velocities, 2n) to add to
/// the model's state at the window's start, the measured currents' correction, and how
/// uncertain the resulting state at the trigger is. Zero and none when the record gives
/// nothing to fit.
struct LeadStateFit {
  Eigen::VectorXd correction;
  /// The measured currents' correction over the window (null: none): their noise, driving an
  /// unstable plant open loop for milliseconds, moves the state at the trigger by more than the
  /// displacement samples' noise does; the window's samples say how.
  std::shared_ptr<const LeadCurrentCorrection> current_correction;
  /// One standard deviation of the state at the trigger (2n) along each of the (at most three)
  /// principal axes of its covariance where the sensors see it: the start sensitivity's.
  std::vector<Eigen::VectorXd> uncertainty;
  /// ... and along every principal axis of its covariance scaled to unit variances: together
  /// they span all of it (the start's shift within it, start_state_shift.hpp).
  std::vector<Eigen::VectorXd> uncertainty_all;
  /// What was fitted ("N samples of M displacement channels over L ms, K directions"), or why
  /// nothing was and the model's own state was kept ("not fitted: ..."): the fit reports it,
  /// since a start left unfitted changes what the residual means.
  std::string note;
  bool fitted = false;
  /// The RMS of the window's displacement samples left by the fit, in units of their noise: 1
  /// where the model driven by the record's currents meets the window at its noise; far above,
  /// where it cannot (a force the model lacks, which the currents held the rotor against).
  double misfit = std::numeric_limits<double>::quiet_NaN();
};

/// The fit for `at_lead_start`, the model's state at `trigger_s - lead_s`.
/// `options.start_position_shift_m` and `start_velocity_shift_m_s` shift the window's samples
/// by a constant and by a ramp through the trigger.
LeadStateFit FitLeadState(const ModelParams& declared, const MeasurementParams& m,
                          const MeasuredRecord& r, const RecordRunOptions& options,
                          const Model& model, const State& at_lead_start, double trigger_s,
                          double lead_s);

}  // namespace ambdrop
