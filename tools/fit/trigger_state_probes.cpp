#include "tools/fit/trigger_state_probes.hpp"

#include <cstddef>

namespace ambdrop {

std::vector<RecordRunOptions> TriggerStateProbes(const RecordCost& cost,
                                                 const SimulatedRecord& base,
                                                 TriggerStateAxes axes) {
  std::vector<RecordRunOptions> probes;
  if (!cost.measurement().trigger_state_from_record) return probes;
  for (const Eigen::VectorXd& axis :
       axes == TriggerStateAxes::kAll ? base.lead_uncertainty_all : base.lead_uncertainty) {
    for (const double sign : {1.0, -1.0}) {
      RecordRunOptions o = cost.run_options();
      o.trigger_state_shift = sign * axis;
      probes.push_back(o);
    }
  }
  // The currents the coils held, as uncertain as the law's fit to their samples: on a
  // magnet-biased rotor 1 mA more at one AMB moved the drop's first 8 ms by 1.5 um.
  for (std::size_t a = 0; a < kMaxAmbs; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const double sd = base.held_current_sd_A[a][axis];
      if (!(sd > 0.0)) continue;
      for (const double sign : {1.0, -1.0}) {
        RecordRunOptions o = cost.run_options();
        o.held_current_shift_A[a][axis] = sign * sd;
        probes.push_back(o);
      }
    }
  }
  return probes;
}

RecordRunOptions ShiftedAlong(const RecordCost& cost, const std::vector<RecordRunOptions>& probes,
                              const Eigen::VectorXd& z) {
  RecordRunOptions o = cost.run_options();
  for (Eigen::Index k = 0; k < z.size(); ++k) {
    const RecordRunOptions& plus = probes[static_cast<std::size_t>(2 * k)];
    if (plus.trigger_state_shift.size() > 0) {
      if (o.trigger_state_shift.size() == 0) {
        o.trigger_state_shift = Eigen::VectorXd::Zero(plus.trigger_state_shift.size());
      }
      o.trigger_state_shift += z(k) * plus.trigger_state_shift;
    }
    for (std::size_t a = 0; a < kMaxAmbs; ++a) {
      for (std::size_t axis = 0; axis < 2; ++axis) {
        o.held_current_shift_A[a][axis] += z(k) * plus.held_current_shift_A[a][axis];
      }
    }
  }
  return o;
}

}  // namespace ambdrop
