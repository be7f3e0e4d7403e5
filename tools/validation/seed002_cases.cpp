// Seed 002: Chen, Liu, Yuliane, Kuan (ITRI), "Rotor dynamic analysis in power lost condition for
// maglev high-speed fluid machinery", Sec. IV: the 32 kg flexible rotor of
// configs/chen_itri_flexible.toml dropped at 18 000, 14 000 and 10 000 rpm onto its two
// discrete-ball TDBs, 0.2 s after the drop (the span of the paper's plots).
#include <fmt/format.h>

#include <algorithm>
#include <numbers>
#include <vector>

#include "tools/validation/offline_drop.hpp"
#include "tools/validation/unbalance_phases.hpp"
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

// Where the paper's peaks come from: not the fall (16 kg per TDB through 0.1 mm is 0.016 J;
// its 2.3e4 N on Eq. (5) alone stores ~0.2 J) but the spin. While the race spins up, the
// un-lubricated contact (mu 0.3) drags the journal backwards round the race and the whirl takes
// energy from the spin, as long as the race (1.05e-4 kg m^2: ring, balls and cage) lags behind.
// Medians over 8 unbalance phases, 0.2 s: 2.29e4 / 2.02e4 N at 18 000 rpm (paper 2.3 / 2.35e4),
// 1.79 / 1.51e4 at 14 000 (2.25 / 2.15e4), 1.15 / 0.92e4 at 10 000 (2.1 / 1.9e4); the journal
// reaches 1.77e-4 m. With the earlier lubricated mu 0.1 and 6e-5 kg m^2 the peaks were 2-4e3 N.
// What is left: the paper's peaks fall 9 % (front) and 19 % (rear) from 18 000 to 10 000 rpm,
// ambdrop's halve. The whirl is fed while the race spins up, which lasts in proportion to the
// speed. Over 96 sets of the unpublished values (mu 0.25-0.4, race inertia 1e-4 to 3e-4 kg m^2,
// Cb 1320 or 3300 N s/m, L 6.5 or 13 mm, the slip as in Eq. (9)-(10) or at the contact point;
// medians over 8 phases; tools/bench/seed002_grid.py) the 18 000 / 10 000 rpm ratio is 1.5-4.6
// (median 1.95; the paper's 1.10 and 1.24) and no set puts all six peaks within 25 % (the best, 5
// of 6 at mu 0.3 and 1.5e-4 kg m^2, takes the journal to 1.95e-4 m of the 2e-4 m bound). Taking the
// slip from the spins alone, as Eq. (9)-(10) print it (friction.slip_speeds = "spin_only"), moves
// the medians by 3 % (the median over the 48 pairs; up to 26 % where mu 0.25 leaves the whirl on
// the edge).
constexpr const char* kPeakKnownFailure =
    "issue 5: friction-fed backward whirl (un-lubricated mu 0.3, the race's spin inertia) gives "
    "the paper's peaks at 18 000 rpm, but they halve by 10 000 rpm where the paper's fall 9-19 %: "
    "the race's spin-up, which feeds the whirl, lasts in proportion to the speed; none of 96 sets "
    "of the unpublished mu, race inertia, Cb and L puts all six within 25 % (see "
    "seed002_cases.cpp)";

// The paper gives no unbalance phase at the drop, and the drop is chaotic: the peaks and the
// forces after 0.1 s are medians over the phases, the displacement the largest of them.
OfflineDrop Drop(const std::string& config, double rpm, bool support) {
  const std::string on = support ? "true" : "false";
  std::vector<OfflineDrop> runs;
  for (int k = 0; k < kUnbalancePhases; ++k) {
    // Contact forces are read after the trigger; the "after 0.1 s" ones from 0.1 s after it.
    runs.push_back(RunOfflineDrop(
        config,
        {fmt::format("simulation.spin_speed_rad_s={:.17g}", rpm * std::numbers::pi / 30.0),
         UnbalancePhaseOverride("rotor", k), "simulation.duration_s=0.21",
         "simulation.output_interval_s=2e-6",
         std::string("tdb.") + kTdbNames[0] + ".ball_bearing_tdb.support.enabled=" + on,
         std::string("tdb.") + kTdbNames[1] + ".ball_bearing_tdb.support.enabled=" + on},
        0.1));
  }
  OfflineDrop d = runs.front();
  for (const OfflineDrop& r : runs) d.ok = d.ok && r.ok;
  for (std::size_t t = 0; t < d.tdbs.size(); ++t) {
    std::vector<double> normal, late, support_N;
    for (const OfflineDrop& r : runs) {
      normal.push_back(r.tdbs[t].normal_N);
      late.push_back(r.tdbs[t].late_normal_N);
      support_N.push_back(r.tdbs[t].support_N);
      d.tdbs[t].journal_radius_m = std::max(d.tdbs[t].journal_radius_m, r.tdbs[t].journal_radius_m);
    }
    d.tdbs[t].normal_N = Median(normal);
    d.tdbs[t].late_normal_N = Median(late);
    d.tdbs[t].support_N = Median(support_N);
  }
  return d;
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
