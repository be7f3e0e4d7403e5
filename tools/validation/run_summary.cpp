#include "tools/validation/run_summary.hpp"

#include <cmath>
#include <vector>

#include "rt_core/tdb_common.hpp"

namespace ambdrop {

RunSummary::RunSummary(const ModelParams& params)
    // Without a scheduled shutdown any contact comes from the configured currents, and the
    // only meaningful origin left is the start of the run.
    : trigger_time_s_(params.trigger.enabled ? params.trigger.time_s : 0.0) {
  for (const TdbParams& tdb : params.tdbs) {
    TdbGeometry geometry;
    if (tdb.misalignment.enabled) {
      geometry.centre_x_m = tdb.misalignment.x_m;
      geometry.centre_y_m = tdb.misalignment.y_m;
    }
    geometry.clearance_m = tdb.clearance_m;
    geometry.journal_radius_m = tdb.journal_radius_m;
    geometry.race_radius_m = InnerRaceRadius(tdb);
    geometry_.push_back(geometry);
    TdbSummary summary;
    summary.name = tdb.name;
    tdbs_.push_back(summary);
    orbits_.emplace_back(kOrbitCapacity);
  }
}

void RunSummary::Add(const Observation& observation) {
  const double t = observation.time_s;
  const double spin = observation.spin_speed_rad_s;
  const bool after_trigger = t >= trigger_time_s_;
  for (std::size_t i = 0; i < tdbs_.size(); ++i) {
    const TdbGeometry& geometry = geometry_[i];
    const TdbForce& force = observation.tdb[i];
    TdbSummary& summary = tdbs_[i];

    // Comparisons written so that a NaN never replaces a finite maximum.
    if (force.normal_force_N > summary.peak_normal_force_N) {
      summary.peak_normal_force_N = force.normal_force_N;
    }
    const double dx = observation.tdb_journal_xy_m[i][0] - geometry.centre_x_m;
    const double dy = observation.tdb_journal_xy_m[i][1] - geometry.centre_y_m;
    const double excursion = std::hypot(dx, dy) / geometry.clearance_m;
    if (excursion > summary.max_excursion_over_clearance) {
      summary.max_excursion_over_clearance = excursion;
    }
    if (!summary.first_contact_time_s && force.normal_force_N > 0.0) {
      summary.first_contact_time_s = t;
    }
    // Before the trigger the motor holds the rotor and the race is (normally) at rest; the
    // metric is about how fast the race catches up after the drop. A non-spinning rotor gives
    // a 0 >= 0 comparison that would count as spun up at once, hence the spin > 0 guard.
    if (!summary.spinup_time_s && after_trigger && spin > 0.0 &&
        force.tdb_spin_rad_s * geometry.race_radius_m >=
            kSpinupFraction * spin * geometry.journal_radius_m) {
      summary.spinup_time_s = t - trigger_time_s_;
    }
  }
  // The journal orbit after the trigger, for the whirl classification.
  if (after_trigger && !tdbs_.empty()) {
    for (std::size_t i = 0; i < tdbs_.size(); ++i) {
      orbits_[i][orbit_next_] = {t, observation.tdb_journal_xy_m[i][0] - geometry_[i].centre_x_m,
                                 observation.tdb_journal_xy_m[i][1] - geometry_[i].centre_y_m,
                                 spin};
    }
    orbit_next_ = (orbit_next_ + 1) % kOrbitCapacity;
    if (orbit_count_ < kOrbitCapacity) ++orbit_count_;
  }
  ++observations_;
  last_time_s_ = t;
  last_spin_speed_rad_s_ = spin;
}

WhirlClassification RunSummary::Whirl(std::size_t index) const {
  if (orbit_count_ == 0 || !last_time_s_) return {};
  // After the transient: the second half of the time since the trigger.
  const double from_s = trigger_time_s_ + 0.5 * (*last_time_s_ - trigger_time_s_);
  std::vector<OrbitSample> window;
  window.reserve(orbit_count_);
  const std::size_t oldest = (orbit_next_ + kOrbitCapacity - orbit_count_) % kOrbitCapacity;
  for (std::size_t k = 0; k < orbit_count_; ++k) {
    const OrbitSample& sample = orbits_[index][(oldest + k) % kOrbitCapacity];
    if (sample.time_s >= from_s) window.push_back(sample);
  }
  return ClassifyWhirl(window, geometry_[index].clearance_m);
}

}  // namespace ambdrop
