// Seed 001: Jarroux et al., "Parametric analysis of a rigid rotor drop onto touchdown bearings",
// Sec. 3: trends of a rigid rotor dropped at speed onto 4-DOF TDBs with the cross-coupled
// ribbon (Eq. (1)) and the quadratic bearing law (configs/jarroux2016_rigid.toml).
#include <fmt/format.h>

#include "io/config_loader.hpp"
#include "tools/validation/offline_drop.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

std::string Describe(const WhirlClassification& w) {
  return fmt::format("{}, {:+.3f} x spin", WhirlName(w.kind), w.frequency_ratio);
}

// ambdrop, rig config, 0.95 s after the drop, mu 0.35 and ccrd cut 10x to 700 N s/m: both TDBs
// rock (swinging at about a third of the spin frequency), as they do at mu 0.2..0.5 with ccrd
// 0..7e3 N s/m; a 10x larger unbalance gives forward (often synchronous) whirl, backward whirl
// only at one TDB in isolated cases. Our view of the cause: the inner race (seed 000's Ieq
// 2.2e-3 kg m^2) spins up to the journal's surface speed within 0.06-0.12 s, after which the
// contact no longer slips and friction stops feeding a backward whirl; seed 001 gives neither its
// Ieq nor its drag torques, nor the unbalance, that decide this.
constexpr const char* kWhirlKnownFailure =
    "issue 5: with the assumed rig (seed 000's TDB inertia, G2.5 unbalance) the raised friction "
    "and cut ribbon damping still rock; the inner race spins up within ~0.1 s and friction stops "
    "driving the whirl";

}  // namespace

std::vector<ValidationCheck> Seed001Trends(const std::string& configs_dir) {
  const char* kCase = "seed001 Sec. 3 (drop at speed)";
  const std::string config = configs_dir + "/jarroux2016_rigid.toml";
  const ModelParams rig = LoadConfig(config).params;
  // Friction feeds spin energy into a backward whirl, support damping takes it out: the whirl
  // case raises mu to 0.35 and cuts the ribbon's damping (ccrd, Eq. (1)) 10x.
  constexpr double kWhirlMu = 0.35;
  constexpr double kWhirlDampingCut = 10.0;
  std::vector<std::string> wide_overrides, whirl_overrides;
  for (const TdbParams& t : rig.tdbs) {
    const std::string key = "tdb." + t.name + ".";
    wide_overrides.push_back(fmt::format("{}clearance_m={:.17g}", key, 2.0 * t.clearance_m));
    whirl_overrides.push_back(fmt::format("{}friction.coefficient={:.17g}", key, kWhirlMu));
    whirl_overrides.push_back(
        fmt::format("{}four_dof.cross_coupled.damping_N_s_per_m={:.17g}", key,
                    t.four_dof.cross_coupled.damping_N_s_per_m / kWhirlDampingCut));
  }
  const OfflineDrop base = RunOfflineDrop(config, {});
  const OfflineDrop wide = RunOfflineDrop(config, wide_overrides);
  const OfflineDrop bwm = RunOfflineDrop(config, whirl_overrides);

  std::vector<ValidationCheck> checks;
  // "Increasing rotor to inner race clearance ... increase the TDB load".
  for (std::size_t i = 0; i < base.tdbs.size() && i < wide.tdbs.size(); ++i) {
    const double narrow_N = base.tdbs[i].normal_N;
    const double wide_N = wide.tdbs[i].normal_N;
    checks.push_back(
        TrendCheck(kCase, base.tdbs[i].name + ": peak load, clearance doubled", "higher (>= +10 %)",
                   fmt::format("{:+.0f} % ({:.3g} N)", (wide_N / narrow_N - 1.0) * 100.0, wide_N),
                   narrow_N > 0.0 && wide_N > 1.1 * narrow_N));
  }
  // After the transient the rotor rocks (RM) or whirls backward (BWM): the rig's friction and
  // ribbon damping rock, mu >= 0.3 with low support damping whirls backward.
  for (std::size_t i = 0; i < rig.tdbs.size() && i < base.whirl.size() && i < bwm.whirl.size();
       ++i) {
    const TdbParams& t = rig.tdbs[i];
    const double mu = t.friction.coefficient;
    const double ccrd_N_s_per_m = t.four_dof.cross_coupled.damping_N_s_per_m;
    checks.push_back(TrendCheck(
        kCase, fmt::format("{}: motion, mu {:.2g}, ccrd {:.2g} N s/m", t.name, mu, ccrd_N_s_per_m),
        "rocking", Describe(base.whirl[i]), base.whirl[i].kind == WhirlKind::kRocking));
    ValidationCheck whirl = TrendCheck(
        kCase,
        fmt::format("{}: motion, mu {:.2g}, ccrd {:.2g} N s/m", t.name, kWhirlMu,
                    ccrd_N_s_per_m / kWhirlDampingCut),
        "backward whirl", Describe(bwm.whirl[i]),
        bwm.whirl[i].kind == WhirlKind::kBackwardWhirl && bwm.whirl[i].frequency_ratio < 0.0);
    if (!whirl.pass) whirl.known_failure = kWhirlKnownFailure;
    checks.push_back(whirl);
  }
  if (!base.ok || !wide.ok || !bwm.ok) {
    checks.push_back(TrendCheck(kCase, "all drops run to the end", "yes", "a run diverged", false));
  }
  return checks;
}

}  // namespace ambdrop
