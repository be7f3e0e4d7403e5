#pragma once
// What every HIL run is checked against, whatever the controller: a test bench's run that did
// not levitate, or whose controller never answered, is no passed test, and `hil` says so in its
// status and exit code (issue 17: it exited 0 with status ok when each AMB was fed the other
// end's sensor and the rotor sat on its TDBs before the trigger, and when no controller message
// came at all). The bounds are the command line's (`--check-*`); the defaults catch a run that
// did not levitate or a link that lost half the answers, and leave the drop's own figures free.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "rt_core/simulator.hpp"

namespace ambdrop {

struct HilCheckBounds {
  /// Before the first power event every journal stays within this fraction of its TDB's
  /// radial clearance (the excursion towards contact, clearance + penetration).
  double levitated_fraction = 0.5;
  /// An outside controller answers at least this fraction of the sensor samples sent (currents
  /// messages received, a scenario's swallowed ones included, per sample).
  double answered_fraction = 0.5;
  double max_tdb_load_N = std::numeric_limits<double>::infinity();        ///< peak normal force
  double max_penetration_m = std::numeric_limits<double>::infinity();     ///< beyond the clearance
  double max_race_speed_rad_s = std::numeric_limits<double>::infinity();  ///< inner race spin-up
};

/// What the session counted (the real-time side) that the checks judge.
struct HilRunFacts {
  std::optional<double> first_power_event_s;  ///< empty: no power event came
  /// Largest journal excursion before the first power event as a fraction of its clearance;
  /// NaN when no state came before it.
  double levitated_fraction = 0.0;
  std::int64_t answers = 0;       ///< currents messages received (swallowed ones included)
  std::int64_t samples_sent = 0;  ///< sensor samples sent to the controller
  bool external = false;          ///< an outside controller (LCM, CAN)
};

class HilChecks {
 public:
  /// Called for each observation, in time order (the writer thread's).
  void Add(const Observation& o) noexcept;

  /// The first observation with a TDB in contact; empty if none.
  std::optional<double> first_contact_s() const noexcept { return contact_s_; }
  double peak_tdb_load_N() const noexcept { return peak_load_N_; }
  double max_penetration_m() const noexcept { return max_penetration_m_; }
  double max_race_speed_rad_s() const noexcept { return max_race_speed_rad_s_; }

  /// One sentence per failed check, "; "-separated ("" if all passed):
  ///  - a TDB touched before the first power event: the controller did not levitate the rotor;
  ///  - a journal went beyond bounds.levitated_fraction of its clearance before it;
  ///  - an outside controller sent no currents message, or answered fewer than
  ///    bounds.answered_fraction of the samples;
  ///  - the peak TDB load, penetration or race speed beyond its bound.
  std::string Failures(const HilRunFacts& facts, const HilCheckBounds& bounds) const;

 private:
  std::optional<double> contact_s_;
  double peak_load_N_ = 0.0;
  double max_penetration_m_ = -std::numeric_limits<double>::infinity();
  double max_race_speed_rad_s_ = 0.0;
};

}  // namespace ambdrop
