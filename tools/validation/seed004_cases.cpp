// Seed 004: Zhu & Zhang, "Dynamic responses of rotor drops onto auxiliary bearing with the
// support of metal rubber ring", Fig. 5(a): rotor drop at 12 000 rpm onto auxiliary bearings
// whose house sits on a metal rubber ring (configs/metal_rubber_ring.toml) or is rigidly mounted
// (configs/rigid_mount.toml). The recommended ring, Krr = 1e6 N/m with Crr = 1e4 N s/m, gives
// the lowest peak impact force over 12 000-30 000 rpm; here: over the 0.2 s after the drop at
// 12 000 rpm, lower than the rigid mount and than its neighbours on the decade grid.
#include <fmt/format.h>

#include "io/config/config_loader.hpp"
#include "tools/validation/stepped_drop.hpp"
#include "tools/validation/tdb_peaks.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

struct Impact {
  double peak_N = 0.0;  ///< largest rotor / inner-race force at either TDB
  bool ok = false;
};

/// The drop of `config_path`; with krr > 0, every TDB's ring set to Krr = krr, Crr = crr.
Impact PeakImpact(const std::string& config_path, double krr_N_per_m = 0.0,
                  double crr_N_s_per_m = 0.0) {
  std::vector<std::string> overrides;
  if (krr_N_per_m > 0.0) {
    for (const TdbParams& t : LoadConfig(config_path).params.tdbs) {
      const std::string ring = "tdb." + t.name + ".catcher_bearing.metal_rubber_ring.";
      overrides.push_back(fmt::format("{}stiffness_N_per_m={:.17g}", ring, krr_N_per_m));
      overrides.push_back(fmt::format("{}damping_N_s_per_m={:.17g}", ring, crr_N_s_per_m));
    }
  }
  const Model model = BuildModel(LoadConfig(config_path, overrides).params);
  TdbPeakTracker peaks(model.params);
  const SteppedDrop run = RunSteppedDrop(model, 0.2, [&](const Observation& o) { peaks.Add(o); });
  return {peaks.MaxNormal_N(), run.status == StepStatus::kOk};
}

// Not closed (issue 5). The paper's quantity is "the maximum impact forces between rotor and
// inner race after rotor drop" (Sec. 2.3; Fig. 9's experimental values are the AB support force
// on the rotor, Eq. (4)), which is what the tracker takes. Its text says only that Krr = 1e6,
// Crr = 1e4 "are advisable to buffer the following impact forces", over the four speeds of
// Fig. 5; the ordering against Crr = 1e3 is read off the figure. In the paper's own model
// (Eq. (2): house m_o on Krr, Crr) the first impact sets the peak, and it rises with Crr:
//   - Crr = 1e3 (zeta = 0.23 on the rotor's 4.55 kg share): spring-limited, weight share 45 N +
//     v0 sqrt(Krr m) = 0.0495 m/s x 2133 N s/m = 106 N, about 150 N; ambdrop 167 N;
//   - Crr = 1e4 (zeta = 2.3): damper-limited, below Crr v0 = 495 N; ambdrop 362 N.
// The force into the foundation (Krr x + Crr v) orders the same way (122 vs 367 N). Later
// impacts stay below 65 N over 0.5 s at either damping, friction 0.1-0.3 changes the peak by
// under 25 N, and 30 000 rpm gives the same order (146 vs 356 N). What Crr = 1e3 does cost is
// travel: the journal reaches 250 um from the centre (the ring gives ~100 um), the AMB air gap
// (twice the 0.125 mm protective gap), against 182 um at Crr = 1e4; rotor / stator contact is
// not modelled. A stop on the house's travel would turn the order: tried (a stiff 5e8 N/m
// contact of the house with the foundation's bore beyond 50, 75 or 100 um), Crr = 1e3 peaks at
// 702 / 551 / 349 N while the recommended ring stays at 362 N (its house moves less than 50 um),
// so a stop at 50-75 um passes every check (100 um does not). A real ring would need such a stop
// to keep the journal out of the AMB's gap, but the paper's Eq. (2) ring has none and gives no
// travel; choosing one inside that window to pass the check would be fitting, so it is not done.
constexpr const char* kLowDampingKnownFailure =
    "issue 5: Crr = 1e3 N s/m gives a lower peak impact (167 N) than the recommended 1e4 "
    "(362 N): the first impact sets the peak and, in the paper's Eq. (2) model, rises with Crr "
    "(spring-limited ~150 N by hand vs damper-limited < Crr v0 = 495 N); the foundation force "
    "orders the same way (122 vs 367 N); Crr = 1e3 instead lets the journal reach 250 um, the "
    "AMB air gap (rotor / stator contact is not modelled)";

}  // namespace

std::vector<ValidationCheck> Seed004MetalRubberRing(const std::string& configs_dir) {
  const char* kCase = "seed004 Fig. 5(a) (12 000 rpm)";
  const std::string ring = configs_dir + "/metal_rubber_ring.toml";
  constexpr double kKrr_N_per_m = 1e6, kCrr_N_s_per_m = 1e4;  // the paper's recommendation
  const Impact recommended = PeakImpact(ring, kKrr_N_per_m, kCrr_N_s_per_m);

  std::vector<ValidationCheck> checks;
  bool ok = recommended.ok;
  const auto lower_than = [&](const std::string& other, const Impact& impact) {
    ok = ok && impact.ok;
    return TrendCheck(kCase, "peak impact, recommended ring vs " + other, "lower",
                      fmt::format("{:.0f} vs {:.0f} N", recommended.peak_N, impact.peak_N),
                      recommended.peak_N > 0.0 && recommended.peak_N < impact.peak_N);
  };
  checks.push_back(lower_than("rigid mount", PeakImpact(configs_dir + "/rigid_mount.toml")));
  // The decade grid's neighbours.
  for (const double krr : {kKrr_N_per_m / 10.0, kKrr_N_per_m * 10.0}) {
    checks.push_back(
        lower_than(fmt::format("Krr {:.0e} N/m", krr), PeakImpact(ring, krr, kCrr_N_s_per_m)));
  }
  for (const double crr : {kCrr_N_s_per_m / 10.0, kCrr_N_s_per_m * 10.0}) {
    ValidationCheck c =
        lower_than(fmt::format("Crr {:.0e} N s/m", crr), PeakImpact(ring, kKrr_N_per_m, crr));
    if (!c.pass && crr < kCrr_N_s_per_m) c.known_failure = kLowDampingKnownFailure;
    checks.push_back(c);
  }
  if (!ok) {
    checks.push_back(TrendCheck(kCase, "all drops run to the end", "yes", "a run diverged", false));
  }
  return checks;
}

}  // namespace ambdrop
