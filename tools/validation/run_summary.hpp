#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rt_core/model_params.hpp"
#include "rt_core/simulator.hpp"
#include "tools/fit/whirl_classifier.hpp"

namespace ambdrop {

/// Drop metrics of one touchdown bearing.
struct TdbSummary {
  std::string name;
  double peak_normal_force_N = 0.0;
  /// Max over time of the journal's radial distance from the TDB centre over the clearance
  /// (1 = touching; the centre is offset by the misalignment when that is enabled).
  double max_excursion_over_clearance = 0.0;
  /// First observation with a positive normal force.
  std::optional<double> first_contact_time_s;
  /// From the trigger until the inner-race surface speed first reaches 95 % of the journal's.
  std::optional<double> spinup_time_s;
};

/// Accumulates the drop metrics of a run from its observations (no I/O: the caller reports).
/// Metrics are only as fine as the observations fed in, i.e. the output interval.
class RunSummary {
 public:
  /// Fraction of the journal surface speed the TDB must reach to count as spun up.
  static constexpr double kSpinupFraction = 0.95;

  explicit RunSummary(const ModelParams& params);

  void Add(const Observation& observation);

  /// Journal samples kept per TDB for the whirl classification (the latest ones, a ring).
  static constexpr std::size_t kOrbitCapacity = std::size_t{1} << 15;
  /// Whirl classification of TDB `index` after the transient (Jarroux 2016, seed 001, Sec. 3):
  /// ClassifyWhirl over the second half of the time since the trigger, or over as much of it as
  /// the ring still holds.
  WhirlClassification Whirl(std::size_t index) const;

  const std::vector<TdbSummary>& tdbs() const noexcept { return tdbs_; }
  std::int64_t observations() const noexcept { return observations_; }
  /// Time from which spin-up is measured: the trigger, or 0 when no trigger is scheduled.
  double trigger_time_s() const noexcept { return trigger_time_s_; }
  /// Of the last observation; absent before the first.
  std::optional<double> last_time_s() const noexcept { return last_time_s_; }
  std::optional<double> last_spin_speed_rad_s() const noexcept { return last_spin_speed_rad_s_; }

 private:
  struct TdbGeometry {
    double centre_x_m = 0.0;
    double centre_y_m = 0.0;
    double clearance_m = 0.0;
    double journal_radius_m = 0.0;
    double race_radius_m = 0.0;  ///< inner-race surface radius, InnerRaceRadius
  };

  std::vector<TdbGeometry> geometry_;
  std::vector<std::vector<OrbitSample>> orbits_;  ///< per TDB, a ring of kOrbitCapacity
  std::size_t orbit_next_ = 0;                    ///< ring slot of the next sample
  std::size_t orbit_count_ = 0;                   ///< samples held (<= kOrbitCapacity)
  std::vector<TdbSummary> tdbs_;
  double trigger_time_s_ = 0.0;
  std::int64_t observations_ = 0;
  std::optional<double> last_time_s_;
  std::optional<double> last_spin_speed_rad_s_;
};

}  // namespace ambdrop
