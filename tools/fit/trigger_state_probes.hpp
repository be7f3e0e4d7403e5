#pragma once
// measurement.trigger_state = "record": the state at the trigger is an estimate (the lead
// window's fit, lead_state_estimate.hpp), and a rotor that the power loss leaves unstable goes
// where its error sends it. The start sensitivity (effect_selection.hpp) and the state shift
// (start_state_shift.hpp) run the declared model along that estimate's uncertainty: these are
// their probes.
#include <vector>

#include "tools/fit/record_cost.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// Which axes of the estimate's covariance the probes take.
enum class TriggerStateAxes {
  kSeen,  ///< the (at most three) largest where the sensors see them: the bulk's spread
  kAll,   ///< every one: what a shift of the state may use
};

/// The probes, in pairs (+ then - one standard deviation): along the lead window's estimate's
/// axes (SimulatedRecord::lead_uncertainty or lead_uncertainty_all of `base`, the declared
/// model's run) and each held current's standard error. Empty unless measurement.trigger_state
/// = "record".
std::vector<RecordRunOptions> TriggerStateProbes(const RecordCost& cost,
                                                 const SimulatedRecord& base,
                                                 TriggerStateAxes axes);

/// The run options of the shift `z` (standard deviations along each probe pair's axis, in the
/// probes' order): `cost`'s own, its state at the trigger and held currents moved by
/// sum z_k times the k-th pair's + probe.
RecordRunOptions ShiftedAlong(const RecordCost& cost, const std::vector<RecordRunOptions>& probes,
                              const Eigen::VectorXd& z);

}  // namespace ambdrop
