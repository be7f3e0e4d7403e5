#pragma once
// What every HIL run is checked against, whatever the controller: a test bench's run that did
// not levitate, or whose controller never answered, is no passed test, and `hil` says so in its
// status and exit code (issue 17: it exited 0 with status ok when each AMB was fed the other
// end's sensor and the rotor sat on its TDBs before the trigger, and when no controller message
// came at all).
#include <cstdint>
#include <optional>
#include <string>

#include "rt_core/simulator.hpp"

namespace ambdrop {

class HilChecks {
 public:
  /// Called for each observation, in time order (the writer thread's).
  void Add(const Observation& o) noexcept;

  /// The first observation with a TDB in contact; empty if none.
  std::optional<double> first_contact_s() const noexcept { return contact_s_; }

  /// One sentence per failed check, "; "-separated ("" if all passed):
  ///  - a TDB touched before the first power event (`first_power_event_s`, empty if none came):
  ///    the controller did not levitate the rotor;
  ///  - an outside controller (`external`) sent no currents message (`currents_received`).
  std::string Failures(std::optional<double> first_power_event_s, std::int64_t currents_received,
                       bool external) const;

 private:
  std::optional<double> contact_s_;
};

}  // namespace ambdrop
