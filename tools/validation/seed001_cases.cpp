// Seed 001: Jarroux et al., "Parametric analysis of a rigid rotor drop onto touchdown bearings",
// Sec. 3: trends of a rigid rotor dropped at speed onto 4-DOF TDBs with the cross-coupled
// ribbon (Eq. (1)) and the quadratic bearing law (configs/jarroux2016_rigid.toml).
#include <fmt/format.h>

#include "io/config/config_loader.hpp"
#include "tools/validation/offline_drop.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

std::string Describe(const WhirlClassification& w) {
  return fmt::format("{}, {:+.3f} x spin", WhirlName(w.kind), w.frequency_ratio);
}

// ambdrop, rig config, 0.95 s after the drop, mu 0.35 and ccrd cut 10x to 700 N s/m: both TDBs
// rock. Seed 001 gives no numbers for this: Sec. 3 only names the settled motions (RM, BWM) and
// says friction moves spin energy into the BWM; the mu / ccrd pair is ours (seed 000's intro
// lists high friction and low support damping among BWM causes). Eq. (1) (the cross-coupling
// opposes the outer race's whirl), the friction on journal and race, the race spin (seed 000
// Eq. (9)) and the classifier were checked: no sign error. What decides it (issue 5 study):
//  - once the inner race rolls on the journal, only its resisting torque T (drag + M1 + Phi w,
//    seed 000 Eq. (9)) pushes the journal backward, with T / Rir; a rolling BWM lasts if
//    T / Rir * c >= the ribbon's loss per radian of whirl, (eta kcrd + ccrd |w|) r_or^2 (seed 001
//    Eq. (1), outer race on its 0.15 mm clearance): T >= ~10 N m at ccrd 700 N s/m, ~31 N m at
//    7e3 (w ~ 600 rad/s, c 0.25 mm, Rir 60.25 mm);
//  - with seed 000's Ieq 2.2e-3 kg m^2 (its measured spin-up, 0.11-0.13 s, Table 3) no drag
//    0..3 N m, f1 0.001..0.002, eta 0.03..0.3, ribbon clearance 0.15 or 0.3 mm, unbalance G2.5..
//    G16 at 4 phases whirls backward at both TDBs, bar 3 of 144 slow drifts (-0.02..-0.11 x spin,
//    G16 only, phase-dependent, 2 change kind at a 1 us step); a sustained BWM (-0.82 x spin,
//    same at 1 us) needs a 10 N m drag plus a 0.1 mm TDB offset, which delays the base spin-up
//    to 0.8 s; Ieq 1e-2 gives only the tail of a decaying BWM, with a 0.55 s spin-up. Both leave
//    seed 000's rig (dry TDBs: M1 ~ 0.14 N m at rest), so the config keeps it;
//  - no support damping at all does not change it: ccrd 0 and eta 0 with mu 0.35 or 0.5 rock
//    (peaks 2.6-3.8e4 N), and so do a grease drag Phi 0.005-0.015 N m s (3.4-10 N m at full
//    speed) with or without a 0.1 mm TDB offset, and the slip taken from the spins alone: the
//    race (Ieq 2.2e-3) catches up with the journal within 0.06-0.1 s, and from then on rolls;
//  - at 5 us the arctan friction (vref 200 s/m) on the 0.4 kg inner race is past RK4's limit for
//    normal loads above ~5 kN (mu 0.35): its sign flips between RK stages (t = 0.25 s, Ieq 1e-2:
//    +5.4 kN at the step, -5.7 kN at the half step); the rig's, the 10 N m and the Ieq 1e-2
//    cases classify alike at 1 us.
constexpr const char* kWhirlKnownFailure =
    "issue 5: with seed 000's dry TDBs (Ieq 2.2e-3 kg m^2, spin-up 0.12 s) the raised friction and "
    "cut ribbon damping still rock; a rolling backward whirl needs a race drag of ~10 N m, which "
    "would delay the spin-up to ~0.8 s";

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
                    t.four_dof().cross_coupled.damping_N_s_per_m / kWhirlDampingCut));
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
    const double ccrd_N_s_per_m = t.four_dof().cross_coupled.damping_N_s_per_m;
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
