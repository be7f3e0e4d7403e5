#include "tools/cli/hil_checks.hpp"

#include <fmt/format.h>

namespace ambdrop {

void HilChecks::Add(const Observation& o) noexcept {
  if (contact_s_) return;
  for (const TdbForce& t : o.tdb) {
    if (t.normal_force_N > 0.0) {
      contact_s_ = o.time_s;
      return;
    }
  }
}

std::string HilChecks::Failures(std::optional<double> first_power_event_s,
                                std::int64_t currents_received, bool external) const {
  std::string out;
  if (contact_s_ && (!first_power_event_s || *contact_s_ < *first_power_event_s)) {
    out += fmt::format(
        "a journal touched its TDB at {:.6g} s, before any power event: the controller did not "
        "levitate the rotor",
        *contact_s_);
  }
  if (external && currents_received == 0) {
    out += fmt::format("{}the controller sent no currents message", out.empty() ? "" : "; ");
  }
  return out;
}

}  // namespace ambdrop
