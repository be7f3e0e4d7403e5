#pragma once
// measurement.trigger_state = "record": where the rotor really was when the power failed.
// The record's noise moves a levitated rotor by more than any model predicts sample by sample
// (its controller answers that noise), and a rotor that the power loss leaves unstable (a
// magnet's bias keeps its negative stiffness) goes where that motion sends it. So over a lead
// window before the trigger the model is driven open loop by the record's measured currents,
// from its own closed-loop state at the window's start, and the part of that state the
// displacement channels see (the row space of their shapes: positions and velocities) is moved
// to the least-squares fit of the window's displacement samples (one Gauss-Newton step on
// finite-difference sensitivities: the levitated motion is micrometres, where the plant is
// linear). A window through the model pins the velocity far better than a local polynomial
// when the rotor jitters at hundreds of hertz.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/config_measurement.hpp"
#include "io/measured_csv.hpp"
#include "rt_core/model.hpp"
#include "rt_core/state.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// The lead window's length for a record: 6 ms and at least 40 samples.
double TriggerStateLeadSeconds(const MeasuredRecord& record);

/// The fit of the lead window: the correction (modal positions then velocities, 2n) to add to
/// the model's state at the window's start, and how uncertain it is: the principal axes of its
/// covariance (the samples' residual variance times (J^T J)^-1, mapped to the state), each
/// scaled to one standard deviation, largest first (at most three). Zero and none when the
/// record gives nothing to fit.
struct LeadStateFit {
  Eigen::VectorXd correction;
  std::vector<Eigen::VectorXd> uncertainty;
  /// What was fitted ("N samples of M displacement channels over L ms, K directions"), or why
  /// nothing was and the model's own state was kept ("not fitted: ..."): the fit reports it,
  /// since a start left unfitted changes what the residual means.
  std::string note;
  bool fitted = false;
};

/// The fit for `at_lead_start`, the model's state at `trigger_s - lead_s`.
/// `options.start_position_shift_m` and `start_velocity_shift_m_s` shift the window's samples
/// by a constant and by a ramp through the trigger.
LeadStateFit FitLeadState(const ModelParams& declared, const MeasurementParams& m,
                          const MeasuredRecord& r, const RecordRunOptions& options,
                          const Model& model, const State& at_lead_start, double trigger_s,
                          double lead_s);

}  // namespace ambdrop
