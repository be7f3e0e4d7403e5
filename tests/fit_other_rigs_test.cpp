// `ambdrop fit` beyond the seed-000 rigs it was built on: the flexible rotor on ball-bearing TDBs
// with discrete balls (seed 002) and the single-decker catcher bearing rig (seed 003). Both
// levitate on equivalent-law AMBs (closed loop from t = 0, the coil currents carry only their
// noise) and bounce so that, after the first impacts, a change of a fraction of a micrometre
// moves the whole prediction: the fit must still find the effect, from the drop's deterministic
// start, and judge what is left against the drop's own sensitivity.
//
// To stay quick, each case offers the fit a few competing effects of the library rather than all
// of it (the competition is what is tested: misalignment of either TDB against the other effects
// that also move the rest position or the fall; each rig's friction coefficient, which each TDB
// model takes in its own friction law).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "test_configs.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/measured_record_maker.hpp"

namespace ambdrop::fit_other_rigs_test {
namespace {

struct Rig {
  const char* config;
  const char* finer_step;  ///< the truth's step: half the rig's
};

constexpr Rig kFlexible{"chen_itri_flexible.toml", "simulation.step_s=1e-6"};
constexpr Rig kCatcher{"sdcb_rigid.toml", "simulation.step_s=5e-7"};

// 30 ms levitated, 40 ms after the power failure: the fall, the first impacts and some bouncing.
std::vector<std::string> Timing() {
  return {"simulation.duration_s=0.07", "trigger.time_s=0.03"};
}

struct Fitted {
  Selection selection;
  double noise_floor = 0.0;
};

Fitted Fit(const Rig& rig, const std::vector<std::string>& effect,
           const std::vector<std::string>& offered,
           const std::vector<std::string>& timing = Timing()) {
  std::vector<std::string> truth = timing;
  truth.push_back(rig.finer_step);
  truth.insert(truth.end(), effect.begin(), effect.end());
  MeasureOptions noise;
  noise.current_noise_A = 0.005;
  noise.force_noise_N = 2.0;
  noise.speed_noise_rad_s = 0.01;
  noise.seed = 11;
  const SyntheticMeasurement made =
      MakeMeasuredRecord(testing::LoadTestConfig(rig.config, truth), noise);
  const ConfigVariants variants = testing::LoadTestVariants(rig.config, timing);
  const ModelParams& declared = variants.declared().params;
  const RecordCost cost(declared, made.measurement, made.record, RecordRunOptions{});
  std::vector<Effect> library;
  for (Effect& e : EffectLibrary(variants)) {
    if (std::find(offered.begin(), offered.end(), e.name) != offered.end()) {
      library.push_back(std::move(e));
    }
  }
  EXPECT_EQ(library.size(), offered.size()) << "an offered effect is not in the library";
  SelectionRules rules;
  rules.threads = 2;
  Fitted f;
  f.noise_floor = cost.NoiseFloor();
  f.selection = SelectEffects(variants, cost, library, f.noise_floor, rules);
  const Selection& s = f.selection;
  std::printf("verdict %s: %s (model floor %.3g, after %.3g)\n", s.verdict.c_str(),
              s.reason.c_str(), s.model_floor, s.model_floor_after);
  for (const ParameterEstimate& p : s.chosen_fit.parameters) {
    std::printf("  %s %s = %.6g\n", p.effect.c_str(), p.name.c_str(), p.value);
  }
  return f;
}

double Chosen(const Selection& s, const std::string& effect, const std::string& name) {
  for (const ParameterEstimate& p : s.chosen_fit.parameters) {
    if (p.effect == effect && p.name == name) return p.value;
  }
  ADD_FAILURE() << effect << " " << name << " not chosen";
  return std::nan("");
}

void ExpectNamedAndCut(const Fitted& f, const std::string& effect) {
  const Selection& s = f.selection;
  EXPECT_TRUE(s.verdict == "explained" || s.verdict == "partly_explained") << s.reason;
  // The fitted model's own sensitivity widens the limit, but never past a third of the
  // declared model's residual (SelectionRules::explained_cut).
  EXPECT_LE(s.limit_after, std::max(s.limit, s.rms_before / SelectionRules{}.explained_cut));
  EXPECT_GE(s.limit_after, s.limit);
  ASSERT_FALSE(s.chosen.empty()) << s.reason;
  EXPECT_EQ(s.chosen.front(), effect);
  const double before = AboveNoise(s.rms_before, s.noise_floor);
  const double after = AboveNoise(s.rms_after, s.noise_floor);
  EXPECT_GE(before, 3.0 * after) << "overall model error " << before << " -> " << after;
}

TEST(FitOtherRigs, FlexibleRotorOnBallBearingTdbsFindsTheMisalignedTdb) {
  const Fitted f = Fit(kFlexible,
                       {"tdb.front.misalignment.enabled=true", "tdb.front.misalignment.x_m=2e-5",
                        "tdb.front.misalignment.y_m=-3e-5"},
                       {"tdb_misalignment:front", "tdb_misalignment:rear", "amb_flux_decay",
                        "sensor_gain_offset:front"});
  ExpectNamedAndCut(f, "tdb_misalignment:front");
  EXPECT_NEAR(Chosen(f.selection, "tdb_misalignment:front", "x_m"), 2e-5, 4e-6);
  EXPECT_NEAR(Chosen(f.selection, "tdb_misalignment:front", "y_m"), -3e-5, 6e-6);
}

// An effect outside the library, in a drop that turns chaotic: a 30 % wider front TDB. A
// misalignment 30 um down comes close (the same fall), and the model it makes is chaotic
// enough to widen its own limit past the residual it leaves; the cap on that widening
// (SelectionRules::explained_cut) keeps it from calling itself explained, and no second effect
// may join it for an improvement within that chaos (a 0.1 ms flux decay, all but the declared
// instant loss, once did: 0.0192 -> 0.0153, the misaligned model's own sensitivity 0.0168).
TEST(FitOtherRigs, ChaoticDropDoesNotExplainAnEffectOutsideTheLibrary) {
  const std::vector<std::string> timing = {"simulation.duration_s=0.2", "trigger.time_s=0.05"};
  const Fitted f =
      Fit(kFlexible, {"tdb.front.clearance_m=1.3e-4"},
          {"tdb_misalignment:front", "tdb_misalignment:rear", "amb_flux_decay"}, timing);
  EXPECT_NE(f.selection.verdict, "explained") << f.selection.reason;
}

TEST(FitOtherRigs, FlexibleRotorCleanRecordNeedsNoEffect) {
  const Fitted f = Fit(kFlexible, {}, {"tdb_misalignment:front", "amb_flux_decay"});
  EXPECT_EQ(f.selection.verdict, "no_effect_needed") << f.selection.reason;
  EXPECT_TRUE(f.selection.chosen.empty());
  for (const CandidateScore& c : f.selection.candidates) EXPECT_FALSE(c.tried) << c.name;
}

TEST(FitOtherRigs, CatcherBearingRigFindsTheMisalignedTdb) {
  const Fitted f = Fit(kCatcher,
                       {"tdb.left.misalignment.enabled=true", "tdb.left.misalignment.x_m=2e-5",
                        "tdb.left.misalignment.y_m=-3e-5"},
                       {"tdb_misalignment:left", "tdb_misalignment:right", "amb_flux_decay",
                        "sensor_gain_offset:left"});
  ExpectNamedAndCut(f, "tdb_misalignment:left");
  EXPECT_NEAR(Chosen(f.selection, "tdb_misalignment:left", "x_m"), 2e-5, 4e-6);
  EXPECT_NEAR(Chosen(f.selection, "tdb_misalignment:left", "y_m"), -3e-5, 6e-6);
}

// Each TDB model's own friction law takes the coefficient; the catcher bearing's races turn on
// its bearings' moments alone, so a drag torque (a [spin] key) is not offered there.
TEST(FitOtherRigs, TheLibraryOffersWhatEachTdbModelUses) {
  const auto names = [](const ConfigVariants& p) {
    std::vector<std::string> n;
    for (const Effect& e : EffectLibrary(p)) n.push_back(e.name);
    return n;
  };
  const auto has = [](const std::vector<std::string>& n, const char* name) {
    return std::find(n.begin(), n.end(), name) != n.end();
  };
  const ConfigVariants variants = testing::LoadTestVariants(kFlexible.config);
  const ModelParams& flexible = variants.declared().params;
  const std::vector<std::string> on_balls = names(variants);
  EXPECT_TRUE(has(on_balls, "friction_coefficient"));
  EXPECT_TRUE(has(on_balls, "tdb_drag_torque:front"));
  for (const Effect& e : EffectLibrary(variants)) {
    if (e.name != "friction_coefficient") continue;
    const ModelParams p = WithEffects(variants, {&e}, {{0.2}});
    for (std::size_t i = 0; i < p.tdbs.size(); ++i) {
      const SlipFrictionParams& declared = flexible.tdbs[i].ball_bearing().friction;
      const SlipFrictionParams& fitted = p.tdbs[i].ball_bearing().friction;
      EXPECT_EQ(fitted.kinetic_coefficient, 0.2);
      EXPECT_NEAR(fitted.static_coefficient / fitted.kinetic_coefficient,
                  declared.static_coefficient / declared.kinetic_coefficient, 1e-12);
    }
    const std::vector<std::string> set = e.overrides({0.2});
    EXPECT_NE(std::find(set.begin(), set.end(),
                        "tdb.front.ball_bearing_tdb.friction.kinetic_coefficient=0.2"),
              set.end());
  }

  const std::vector<std::string> catcher = names(testing::LoadTestVariants(kCatcher.config));
  EXPECT_TRUE(has(catcher, "friction_coefficient"));
  EXPECT_FALSE(has(catcher, "tdb_drag_torque:left"));
  EXPECT_FALSE(has(catcher, "tdb_drag_torque:right"));

  // A frictionless law takes no coefficient.
  const std::vector<std::string> frictionless = names(testing::LoadTestVariants(
      kFlexible.config, {"tdb.front.ball_bearing_tdb.friction.law=\"none\"",
                         "tdb.rear.ball_bearing_tdb.friction.law=\"none\""}));
  EXPECT_FALSE(has(frictionless, "friction_coefficient"));
}

TEST(FitOtherRigs, CatcherBearingRigFindsItsFrictionCoefficient) {
  const Fitted f =
      Fit(kCatcher, {"tdb.left.friction.coefficient=0.2", "tdb.right.friction.coefficient=0.2"},
          {"friction_coefficient", "tdb_misalignment:left", "amb_flux_decay"});
  ExpectNamedAndCut(f, "friction_coefficient");
  EXPECT_NEAR(Chosen(f.selection, "friction_coefficient", "coefficient"), 0.2, 0.04);
}

TEST(FitOtherRigs, FlexibleRotorFindsItsKineticFrictionCoefficient) {
  const Fitted f = Fit(kFlexible,
                       {"tdb.front.ball_bearing_tdb.friction.kinetic_coefficient=0.2",
                        "tdb.front.ball_bearing_tdb.friction.static_coefficient=0.3",
                        "tdb.rear.ball_bearing_tdb.friction.kinetic_coefficient=0.2",
                        "tdb.rear.ball_bearing_tdb.friction.static_coefficient=0.3"},
                       {"friction_coefficient", "amb_flux_decay"});
  ExpectNamedAndCut(f, "friction_coefficient");
  EXPECT_NEAR(Chosen(f.selection, "friction_coefficient", "coefficient"), 0.2, 0.04);
}

}  // namespace
}  // namespace ambdrop::fit_other_rigs_test
