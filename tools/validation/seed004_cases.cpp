// Seed 004: Zhu & Zhang, "Dynamic responses of rotor drops onto auxiliary bearing with the
// support of metal rubber ring", Fig. 5(a): rotor drop at 12 000 rpm onto auxiliary bearings
// whose house sits on a metal rubber ring (configs/metal_rubber_ring.toml) or is rigidly mounted
// (configs/rigid_mount.toml). The recommended ring, Krr = 1e6 N/m with Crr = 1e4 N s/m, gives
// the lowest peak impact force over 12 000-30 000 rpm; here: over the 0.2 s after the drop at
// 12 000 rpm, lower than the rigid mount and than its neighbours on the decade grid.
#include <fmt/format.h>

#include "io/config_loader.hpp"
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

// Crr = 1e3 N s/m gives a lower peak than the recommended 1e4. In the impact the ring's damper,
// not its spring, carries the house (Crr / Krr = 10 ms, far longer than the impact), so the force
// it passes grows with Crr; the paper's optimum at 1e4 must come from effects not modelled here
// (ring hysteresis, later impacts over its longer run, its bearing damping Cb).
constexpr const char* kLowDampingKnownFailure =
    "issue 5: Crr = 1e3 N s/m gives a lower peak impact than the recommended 1e4 (the impact "
    "loads the ring's damper, so the force it passes grows with Crr)";

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
