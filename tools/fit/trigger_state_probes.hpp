#pragma once
// measurement.trigger_state = "record": the state at the trigger is an estimate (the lead
// window's fit, lead_state_estimate.hpp), and a rotor that the power loss leaves unstable goes
// where its error sends it. The start sensitivity runs the declared model along that estimate's
// uncertainty: these are its probes.
#include <vector>

#include "tools/fit/record_cost.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// How far each probe goes, in standard deviations: half of one. The moves it makes are scaled
/// back to one (the start is nearly linear there: on the flexible rig's clean seed 8 probes of
/// one standard deviation and of half of one predicted the same spread within 5 %).
inline constexpr double kTriggerStateProbeSigmas = 0.5;

/// The probes, in pairs (+ then - kTriggerStateProbeSigmas standard deviations): along each
/// principal axis of the lead window's estimate (SimulatedRecord::lead_uncertainty of `base`,
/// the declared model's run) and each held current's standard error. Empty unless
/// measurement.trigger_state = "record".
std::vector<RecordRunOptions> TriggerStateProbes(const RecordCost& cost,
                                                 const SimulatedRecord& base);

}  // namespace ambdrop
