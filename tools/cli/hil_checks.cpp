#include "tools/cli/hil_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ambdrop {

void HilChecks::Add(const Observation& o) noexcept {
  for (const TdbForce& t : o.tdb) {
    if (t.normal_force_N > 0.0 && !contact_s_) contact_s_ = o.time_s;
    peak_load_N_ = std::max(peak_load_N_, t.normal_force_N);
    max_race_speed_rad_s_ = std::max(max_race_speed_rad_s_, std::abs(t.tdb_spin_rad_s));
  }
  for (const TdbForce& t : o.tdb)
    max_penetration_m_ = std::max(max_penetration_m_, t.penetration_m);
}

std::string HilChecks::Failures(const HilRunFacts& facts, const HilCheckBounds& bounds) const {
  std::string out;
  const auto add = [&out](const std::string& sentence) {
    out += (out.empty() ? "" : "; ") + sentence;
  };
  const auto& first_power_event_s = facts.first_power_event_s;
  if (contact_s_ && (!first_power_event_s || *contact_s_ < *first_power_event_s)) {
    add(fmt::format(
        "a journal touched its TDB at {:.6g} s, before any power event: the controller did not "
        "levitate the rotor",
        *contact_s_));
  } else if (facts.levitated_fraction > bounds.levitated_fraction) {
    add(fmt::format(
        "before the first power event a journal moved {:.3g} of its clearance off centre "
        "(--check-levitated-fraction {:.3g}): the rotor was not levitated",
        facts.levitated_fraction, bounds.levitated_fraction));
  }
  if (facts.external) {
    if (facts.answers == 0) {
      add("the controller sent no currents message");
    } else if (facts.samples_sent > 0) {
      const double answered =
          static_cast<double>(facts.answers) / static_cast<double>(facts.samples_sent);
      if (answered < bounds.answered_fraction) {
        add(fmt::format(
            "the controller answered {} of {} sensor samples ({:.3g}; --check-answered-fraction "
            "{:.3g})",
            facts.answers, facts.samples_sent, answered, bounds.answered_fraction));
      }
    }
  }
  if (peak_load_N_ > bounds.max_tdb_load_N) {
    add(fmt::format("a TDB's peak load was {:.6g} N (--check-max-tdb-load-N {:.6g})", peak_load_N_,
                    bounds.max_tdb_load_N));
  }
  if (max_penetration_m_ > bounds.max_penetration_m) {
    add(fmt::format(
        "a journal went {:.6g} m beyond its clearance (--check-max-penetration-m {:.6g})",
        max_penetration_m_, bounds.max_penetration_m));
  }
  if (max_race_speed_rad_s_ > bounds.max_race_speed_rad_s) {
    add(fmt::format("an inner race spun up to {:.6g} rad/s (--check-max-race-speed-rad-s {:.6g})",
                    max_race_speed_rad_s_, bounds.max_race_speed_rad_s));
  }
  return out;
}

}  // namespace ambdrop
