#include "tools/validation/tdb_peaks.hpp"

#include <algorithm>
#include <cmath>

namespace ambdrop {

TdbPeakTracker::TdbPeakTracker(const ModelParams& params, double late_from_s)
    : late_from_s_(late_from_s) {
  for (const TdbParams& tdb : params.tdbs) tdbs_.push_back(TdbPeaks{tdb.name});
}

void TdbPeakTracker::Add(const Observation& o) {
  for (std::size_t i = 0; i < tdbs_.size(); ++i) {
    TdbPeaks& p = tdbs_[i];
    const TdbForce& f = o.tdb[i];
    p.normal_N = std::max(p.normal_N, f.normal_force_N);
    p.support_N = std::max(p.support_N, f.support_force_N());
    if (o.time_s >= late_from_s_) p.late_normal_N = std::max(p.late_normal_N, f.normal_force_N);
    p.journal_radius_m = std::max(p.journal_radius_m,
                                  std::hypot(o.tdb_journal_xy_m[i][0], o.tdb_journal_xy_m[i][1]));
  }
}

double TdbPeakTracker::MaxNormal_N() const noexcept {
  double peak = 0.0;
  for (const TdbPeaks& p : tdbs_) peak = std::max(peak, p.normal_N);
  return peak;
}

}  // namespace ambdrop
