#pragma once
// Per-TDB extremes of a drop, accumulated from its observations: the peak contact (impact)
// force, load-cell force and orbit size that seeds 001-004 report.
#include <limits>
#include <string>
#include <vector>

#include "rt_core/model_params.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

struct TdbPeaks {
  std::string name;
  double normal_N = 0.0;   ///< largest rotor / inner-race normal force
  double support_N = 0.0;  ///< largest force passed to the housing (the load cells)
  /// Largest normal force from the tracker's late_from_s on (seed 002's "after 0.1 s").
  double late_normal_N = 0.0;
  /// Largest distance of the journal from the nominal rotor axis (seed 002's displacement).
  double journal_radius_m = 0.0;
};

/// Keeps the running maxima of every observation it is given; the caller chooses the span.
class TdbPeakTracker {
 public:
  explicit TdbPeakTracker(const ModelParams& params,
                          double late_from_s = std::numeric_limits<double>::infinity());
  void Add(const Observation& observation);
  const std::vector<TdbPeaks>& tdbs() const noexcept { return tdbs_; }
  /// The largest normal force over every TDB.
  double MaxNormal_N() const noexcept;

 private:
  double late_from_s_;
  std::vector<TdbPeaks> tdbs_;
};

}  // namespace ambdrop
