// The seed 002-004 TDB models' config keys are read strictly: an unknown key, a value out of
// range and a missing table each say the file (or --set), the dotted key and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_seed_tdbs_test {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ErrorOf(const std::string& file, const std::vector<std::string>& overrides) {
  try {
    LoadConfig(testing::ConfigPath(file), overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ConfigSeedTdbs, SlipSpeedsDefaultToTheContactPoint) {
  const std::string rig = testing::ConfigPath("chen_itri_flexible.toml");
  EXPECT_EQ(LoadConfig(rig).params.tdbs[0].ball_bearing().friction.slip_speeds,
            SlipSpeeds::kContactPoint);
  const ModelParams literal =
      LoadConfig(rig, {"tdb.rear.ball_bearing_tdb.friction.slip_speeds=\"spin_only\""}).params;
  EXPECT_EQ(literal.tdbs[0].ball_bearing().friction.slip_speeds, SlipSpeeds::kContactPoint);
  EXPECT_EQ(literal.tdbs[1].ball_bearing().friction.slip_speeds, SlipSpeeds::kSpinOnly);
}

// The ball-bearing TDB's journal friction is its own table; of the common [friction] it reads
// only the regularisation its races' load torque shares, so the other keys are errors there,
// not values silently ignored.
TEST(ConfigSeedTdbs, BallBearingTdbRejectsTheFrictionKeysItDoesNotRead) {
  const std::string rig = "chen_itri_flexible.toml";
  for (const char* key : {"coefficient=0.9", "law=\"none\"", "whirl_damping_N_s_per_m=5.0"}) {
    EXPECT_THAT(
        ErrorOf(rig, {std::string("tdb.front.friction.") + key}),
        AllOf(HasSubstr("key 'tdb.front.friction."), HasSubstr("[ball_bearing_tdb.friction]")))
        << key;
  }
  const ModelParams p =
      LoadConfig(testing::ConfigPath(rig), {"tdb.front.friction.regularisation_s_per_m=500"})
          .params;
  EXPECT_EQ(p.tdbs[0].name, "front");
  EXPECT_EQ(p.tdbs[0].friction.regularisation_s_per_m, 500.0);
  // The catcher bearing reads the whole [friction] table (its journal contact is the common one).
  EXPECT_EQ(ErrorOf("ddcb_rigid.toml", {"tdb.left.friction.coefficient=0.2"}), "no error");
}

TEST(ConfigSeedTdbs, BallBearingTdbErrorsNameKeyAndExpectation) {
  const std::string rig = "chen_itri_flexible.toml";
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.line_contact.lenght_m=0.01"}),
              HasSubstr("unknown key 'tdb.front.ball_bearing_tdb.line_contact.lenght_m'"));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.line_contact.length_m=0"}),
              AllOf(HasSubstr("key 'tdb.front.ball_bearing_tdb.line_contact.length_m'"),
                    HasSubstr("expected a positive number (m), found 0")));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.bearing.balls=0"}),
              AllOf(HasSubstr("key 'tdb.front.ball_bearing_tdb.bearing.balls'"),
                    HasSubstr("expected an integer")));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.bearing.inner_groove_conformity=0.5"}),
              HasSubstr("a groove conformity above 0.5"));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.bearing.race_poisson_ratio=0.5"}),
              HasSubstr("key 'tdb.front.ball_bearing_tdb.bearing.race_poisson_ratio'"));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.friction.law=\"coulomb\""}),
              AllOf(HasSubstr("key 'tdb.front.ball_bearing_tdb.friction.law'"),
                    HasSubstr("\"static_kinetic\""), HasSubstr("found \"coulomb\"")));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.friction.slip_speeds=\"spin\""}),
              AllOf(HasSubstr("key 'tdb.front.ball_bearing_tdb.friction.slip_speeds'"),
                    HasSubstr("\"contact_point\""), HasSubstr("\"spin_only\""),
                    HasSubstr("found \"spin\"")));
  EXPECT_THAT(ErrorOf(rig, {"tdb.front.ball_bearing_tdb.support.stiffness_N_per_m=-5e8"}),
              AllOf(HasSubstr("--set tdb.front.ball_bearing_tdb.support.stiffness_N_per_m=-5e8: "),
                    HasSubstr("expected a positive number (N/m), found -500000000")));
}

TEST(ConfigSeedTdbs, CatcherBearingErrorsNameKeyAndExpectation) {
  const std::string ddcb = "ddcb_rigid.toml";
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.decks=3"}),
              AllOf(HasSubstr("key 'tdb.left.catcher_bearing.decks'"),
                    HasSubstr("expected an integer"), HasSubstr("found 3")));
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.impact.exponent=2.5"}),
              AllOf(HasSubstr("key 'tdb.left.catcher_bearing.impact.exponent'"),
                    HasSubstr("expected a number in [1, 2], found 2.5")));
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.inner_race.mass_kg=0"}),
              HasSubstr("key 'tdb.left.catcher_bearing.inner_race.mass_kg': expected a positive "
                        "number (kg), found 0"));
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.mount=\"rubber\""}),
              AllOf(HasSubstr("key 'tdb.left.catcher_bearing.mount'"),
                    HasSubstr("\"metal_rubber_ring\""), HasSubstr("found \"rubber\"")));
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.inner_bearing.ballz=8"}),
              HasSubstr("unknown key 'tdb.left.catcher_bearing.inner_bearing.ballz'"));
  // A metal-rubber mount needs its ring.
  EXPECT_THAT(ErrorOf(ddcb, {"tdb.left.catcher_bearing.mount=\"metal_rubber_ring\""}),
              AllOf(HasSubstr("ddcb_rigid.toml:81: missing key "
                              "'tdb.left.catcher_bearing.metal_rubber_ring'"),
                    HasSubstr("expected a table")));
  EXPECT_THAT(ErrorOf("metal_rubber_ring.toml", {}), HasSubstr("no error"));
}

}  // namespace
}  // namespace ambdrop::config_seed_tdbs_test
