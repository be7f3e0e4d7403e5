// Seed 002: Chen, Liu, Yuliane, Kuan (ITRI), "Rotor dynamic analysis in power lost condition for
// maglev high-speed fluid machinery", Sec. IV: the 32 kg flexible rotor of
// configs/chen_itri_flexible.toml dropped at 18 000, 14 000 and 10 000 rpm onto its two
// discrete-ball TDBs, 0.2 s after the drop (the span of the paper's plots).
#include <fmt/format.h>

#include <algorithm>
#include <numbers>

#include "tools/validation/offline_drop.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

// The paper's Figs. 12-14 (text of Sec. IV). Its text gives the 14 000 rpm peaks "at 15000
// RPM" once; the figures and the rest of the text say 14 000.
constexpr const char* kTdbNames[2] = {"front", "rear"};
struct SpeedCase {
  double rpm;
  double published_peak_N[2];  ///< per kTdbNames
};
constexpr SpeedCase kSpeeds[3] = {
    {18000.0, {2.3e4, 2.35e4}}, {14000.0, {2.25e4, 2.15e4}}, {10000.0, {2.1e4, 1.9e4}}};

// "The orbit and the rotor responses are less than critical clearance of 2e-4 m" (the paper's
// maxima are 1.0-1.2e-4 m), beyond the TDB air gap of 1e-4 m that the rotor falls through.
constexpr double kCriticalClearance_m = 2e-4;
constexpr double kTdbAirGap_m = 1e-4;

// ambdrop, 0.2 s after the drop, peaks about an order of magnitude below the paper's with no
// trend on the speed. A 0.1 mm fall of 16 kg per TDB brings 0.016 J; stored in the ~1e8-1e9 N/m
// of balls and line contact that is ~2-3e3 N, and the 1.25 um eccentricity adds only 142 N at
// 18 000 rpm. The paper's 2.3e4 N needs a violent whirl (or a stiffer/heavier set-up) that its
// text does not specify; we do not tune unpublished parameters to reach it.
// Why the paper's peaks are out of reach (worked out with the paper's own numbers): they equal
// its Eq. (5) at its maximum journal displacement from the race centre (1.2e-4 m, so
// delta = 1.9e-5 m with L = 13 mm). Storing that force takes 0.18 J per TDB in the line contact
// (0.64 J with the balls in series, which would also put the journal at 1.7e-4 m), where the
// drop supplies 0.02-0.03 J; a rigid race would still give only 5.7-8.7e3 N on first impact.
// Only a friction-driven backward whirl adds energy: with the unpublished friction coefficient
// and ball damping in physical ranges (mu 0.2-0.4, Cb 0) it reaches ~1e4 N, with the orbit
// beyond 1.2e-4 m and no monotonic speed trend.
constexpr const char* kPeakKnownFailure =
    "issue 5: the paper's ~2.3e4 N peaks need ~0.2-0.6 J per TDB, the drop supplies 0.02-0.03 J; "
    "the race/ball chain carries at most 3.6e3 N within the paper's 1.2e-4 m, and a backward "
    "whirl with unpublished friction reaches ~1e4 N (see seed002_cases.cpp)";

OfflineDrop Drop(const std::string& config, double rpm, bool support) {
  const std::string on = support ? "true" : "false";
  // Contact forces are read after the trigger; the "after 0.1 s" ones from 0.1 s after it.
  return RunOfflineDrop(
      config,
      {fmt::format("simulation.spin_speed_rad_s={:.17g}", rpm * std::numbers::pi / 30.0),
       "simulation.duration_s=0.21", "simulation.output_interval_s=2e-6",
       std::string("tdb.") + kTdbNames[0] + ".ball_bearing_tdb.support.enabled=" + on,
       std::string("tdb.") + kTdbNames[1] + ".ball_bearing_tdb.support.enabled=" + on},
      0.1);
}

/// The peaks of TDB `name`; zeros when the rig has no such TDB, which fails the checks.
TdbPeaks Find(const OfflineDrop& d, const std::string& name) {
  for (const TdbPeaks& t : d.tdbs) {
    if (t.name == name) return t;
  }
  return TdbPeaks{name};
}

double MaxRadius_m(const OfflineDrop& d) {
  double r = 0.0;
  for (const TdbPeaks& t : d.tdbs) r = std::max(r, t.journal_radius_m);
  return r;
}

double MaxLateNormal_N(const OfflineDrop& d) {
  double f = 0.0;
  for (const TdbPeaks& t : d.tdbs) f = std::max(f, t.late_normal_N);
  return f;
}

}  // namespace

std::vector<ValidationCheck> Seed002DropSpeeds(const std::string& configs_dir) {
  const char* kCase = "seed002 Sec. IV (drop, 0.2 s)";
  const std::string config = configs_dir + "/chen_itri_flexible.toml";
  OfflineDrop drops[3];
  for (int s = 0; s < 3; ++s) drops[s] = Drop(config, kSpeeds[s].rpm, false);
  // Fig. 19: the 18 000 rpm drop with the support Ks = 5e8 N/m, Cs = 27 900 N s/m.
  const OfflineDrop supported = Drop(config, kSpeeds[0].rpm, true);

  std::vector<ValidationCheck> checks;
  // Peak contact forces, each within 25 % of the paper's.
  for (int s = 0; s < 3; ++s) {
    for (int t = 0; t < 2; ++t) {
      ValidationCheck c = NumberCheck(
          kCase, fmt::format("{:.0f} rpm {}: peak contact force", kSpeeds[s].rpm, kTdbNames[t]),
          kSpeeds[s].published_peak_N[t], Find(drops[s], kTdbNames[t]).normal_N, 0.25, "N");
      if (!c.pass) c.known_failure = kPeakKnownFailure;
      checks.push_back(c);
    }
  }
  // "The highest contact force is occurred when the rotor speed is 18000 RPM", and the paper's
  // peaks fall with the speed at both TDBs.
  for (const char* tdb : kTdbNames) {
    const double f18 = Find(drops[0], tdb).normal_N;
    const double f14 = Find(drops[1], tdb).normal_N;
    const double f10 = Find(drops[2], tdb).normal_N;
    ValidationCheck c = TrendCheck(
        kCase, std::string(tdb) + ": peak contact force falls with speed", "18k > 14k > 10k rpm",
        fmt::format("{:.0f}, {:.0f}, {:.0f} N", f18, f14, f10), f18 > f14 && f14 > f10);
    if (!c.pass) c.known_failure = kPeakKnownFailure;
    checks.push_back(c);
  }
  // Displacements: the journal falls onto the race, and stays inside the critical clearance.
  const auto displacement = [&](const std::string& label, const OfflineDrop& d, bool reaches) {
    const double r = MaxRadius_m(d);
    ValidationCheck c = TrendCheck(
        kCase, label + ": max displacement",
        reaches ? fmt::format("{:.0e} .. {:.0e} m", kTdbAirGap_m, kCriticalClearance_m)
                : fmt::format("< {:.0e} m", kCriticalClearance_m),
        fmt::format("{:.3g} m", r), (!reaches || r > kTdbAirGap_m) && r < kCriticalClearance_m);
    c.criterion = "bound";
    return c;
  };
  for (int s = 0; s < 3; ++s) {
    checks.push_back(displacement(fmt::format("{:.0f} rpm", kSpeeds[s].rpm), drops[s], true));
  }
  checks.push_back(
      displacement(fmt::format("{:.0f} rpm + Ks, Cs", kSpeeds[0].rpm), supported, false));
  // Fig. 19 vs Fig. 12: "after 0.1 sec contact forces decrease", while the rotor still runs on
  // its TDBs.
  const double without_N = MaxLateNormal_N(drops[0]);
  const double with_N = MaxLateNormal_N(supported);
  checks.push_back(TrendCheck(kCase, "Ks, Cs: contact force after 0.1 s", "lower",
                              fmt::format("{:.0f} vs {:.0f} N", with_N, without_N),
                              with_N > 0.0 && with_N < without_N));

  bool ok = supported.ok;
  for (const OfflineDrop& d : drops) ok = ok && d.ok;
  if (!ok) {
    checks.push_back(TrendCheck(kCase, "all drops run to the end", "yes", "a run diverged", false));
  }
  return checks;
}

}  // namespace ambdrop
