#pragma once
// The first impact of a rotor dropped at rest, per TDB: peak loads until the first rebound top,
// and the rebound height (the journal's rise from its first bottom to the apex of its first
// flight). Jarroux 2019 Sec. 6.1 compares its TDB models by these.
#include <string>
#include <vector>

#include "rt_core/model_params.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

struct FirstImpact {
  double peak_support_N = 0.0;  ///< largest housing force until the first rebound top
  double peak_normal_N = 0.0;   ///< largest rotor / inner-race force over the same span
  double bottom_m = 0.0;        ///< journal y at the first bottom
  double top_m = 0.0;           ///< journal y at the first rebound top
  double rebound_m() const { return top_m - bottom_m; }
  bool complete = false;  ///< the journal flew and landed again
};

/// Follows one TDB's journal: first contact, first bottom (deepest point of the first contact),
/// then the apex of the first flight: the highest point after the bottom until the journal
/// lands again after at least 0.5 ms without contact, having risen by 5 um (or until the end of
/// the run if it never leaves the race).
class ImpactTracker {
 public:
  void Add(double time_s, double y_m, const TdbForce& force);
  const FirstImpact& result() const { return r_; }

 private:
  enum Phase { kFalling, kFirstContact, kFlight, kDone } phase_ = kFalling;
  double last_contact_s_ = 0.0;
  FirstImpact r_;
};

struct DropAtRestResult {
  std::vector<std::string> names;  ///< per TDB
  std::vector<FirstImpact> impacts;
  bool ok = false;  ///< the simulation ran to the end
  std::string failure_message;
};

/// Drops the rotor of `config_path` at rest (spin 0, trigger at 0.02 s, 0.1 s after it) with
/// `overrides`, observing every step, and measures each TDB's first impact.
DropAtRestResult DropAtRest(const std::string& config_path, std::vector<std::string> overrides);

}  // namespace ambdrop
