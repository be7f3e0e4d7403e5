// The inner-race radius Rir (tdb.NAME.inner_race_radius_m) on every TDB kind: read strictly,
// absent it is journal radius + clearance bit for bit, and every kind rolls, spins up and takes
// its race torque on it (Jarroux 2019 Eq. (9), (11); Chen 2019 (seed 002) Eq. (9)-(10); seed 004
// Eq. (3)).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/config/config_keys.hpp"
#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "rt_core/contact_law_tdb.hpp"
#include "rt_core/tdb_common.hpp"
#include "rt_core/tdb_factory.hpp"
#include "test_configs.hpp"

namespace ambdrop::inner_race_radius_test {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

struct Rig {
  const char* file;
  const char* tdb;
};
// One config per TDB kind: contact law, 4-DOF, ball bearing (seed 002), catcher bearing.
const std::vector<Rig> kRigs = {{"jarroux2019_industrial.toml", "nde"},
                                {"jarroux2019_industrial_model2.toml", "nde"},
                                {"chen_itri_flexible.toml", "front"},
                                {"sdcb_rigid.toml", "left"}};

const TdbParams& Named(const ModelParams& params, const std::string& name) {
  for (const TdbParams& t : params.tdbs) {
    if (t.name == name) return t;
  }
  throw std::out_of_range("no TDB " + name);
}

std::string ErrorOf(const std::string& file, const std::vector<std::string>& overrides) {
  try {
    LoadConfig(testing::ConfigPath(file), overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(InnerRaceRadius, AbsentIsJournalRadiusPlusClearanceBitForBit) {
  for (const Rig& rig : kRigs) {
    const TdbParams p = testing::LoadTestConfig(rig.file).tdbs[0];
    EXPECT_EQ(p.inner_race_radius_m, 0.0) << rig.file;
    EXPECT_EQ(InnerRaceRadius(p), p.journal_radius_m + p.clearance_m) << rig.file;
  }
}

// Absent, the key is listed in the registry (ambdrop keys, the fit's candidates) as a default,
// at the derived value; and it still follows the journal radius and clearance whenever they move
// and it does not: given with --set (a fit moving the clearance alone) or changed in the
// parameters after loading. Declared, it stays where it is put.
TEST(InnerRaceRadius, AbsentIsListedAsADerivedDefaultThatFollowsTheClearance) {
  for (const Rig& rig : kRigs) {
    SCOPED_TRACE(rig.file);
    const std::string table = std::string("tdb.") + rig.tdb + ".";
    const std::string key = table + "inner_race_radius_m";
    const LoadedConfig loaded = LoadConfig(testing::ConfigPath(rig.file));
    const TdbParams& t = Named(loaded.params, rig.tdb);
    const ConfigKey* listed = FindKey(loaded.keys, key);
    ASSERT_NE(listed, nullptr) << key << " is not in the registry";
    EXPECT_FALSE(listed->declared);
    EXPECT_EQ(listed->value, t.journal_radius_m + t.clearance_m);
    EXPECT_EQ(listed->unit, "m");
    EXPECT_EQ(listed->key_class, KeyClass::kPhysical);
    EXPECT_EQ(listed->lower, t.journal_radius_m);
    EXPECT_EQ(t.inner_race_radius_m, 0.0) << "the parameters keep the 'derived' sentinel";

    const double clearance = 1.5 * t.clearance_m;
    const double journal = 0.9 * t.journal_radius_m;
    for (const std::vector<std::string>& moved :
         {std::vector<std::string>{table + "clearance_m=" + OverrideNumber(clearance)},
          std::vector<std::string>{table + "journal_radius_m=" + OverrideNumber(journal)}}) {
      const LoadedConfig m = LoadConfig(testing::ConfigPath(rig.file), moved);
      const TdbParams& mt = Named(m.params, rig.tdb);
      EXPECT_EQ(InnerRaceRadius(mt), mt.journal_radius_m + mt.clearance_m) << moved[0];
      EXPECT_EQ(FindKey(m.keys, key)->value, mt.journal_radius_m + mt.clearance_m) << moved[0];
      EXPECT_FALSE(FindKey(m.keys, key)->declared) << moved[0];
    }
    TdbParams copy = t;
    copy.clearance_m = clearance;
    EXPECT_EQ(InnerRaceRadius(copy), copy.journal_radius_m + clearance);

    // Written back at its listed value, it is declared and stays when the clearance moves.
    const LoadedConfig pinned = LoadConfig(
        testing::ConfigPath(rig.file),
        {OverrideFor(*listed, listed->value), table + "clearance_m=" + OverrideNumber(clearance)});
    EXPECT_EQ(InnerRaceRadius(Named(pinned.params, rig.tdb)), listed->value);
  }
}

TEST(InnerRaceRadius, ReadOnEveryKind) {
  for (const Rig& rig : kRigs) {
    const TdbParams base = Named(testing::LoadTestConfig(rig.file), rig.tdb);
    const std::string key = std::string("tdb.") + rig.tdb + ".inner_race_radius_m";
    const TdbParams p = Named(
        testing::LoadTestConfig(rig.file, {key + "=" + std::to_string(base.journal_radius_m)}),
        rig.tdb);
    EXPECT_EQ(InnerRaceRadius(p), base.journal_radius_m) << rig.file;
  }
}

TEST(InnerRaceRadius, ErrorsNameKeyAndWhy) {
  const std::string key = "tdb.nde.inner_race_radius_m";
  const std::string file = "jarroux2019_industrial.toml";  // journal radius 0.06 m
  EXPECT_THAT(ErrorOf(file, {key + "=0.059"}),
              AllOf(HasSubstr("key '" + key + "'"), HasSubstr("at least journal_radius_m"),
                    HasSubstr("the race bore surrounds the journal"), HasSubstr("found 0.059")));
  EXPECT_THAT(ErrorOf(file, {key + "=-0.06"}), HasSubstr("key '" + key + "'"));
  EXPECT_THAT(ErrorOf(file, {key + "=nan"}), HasSubstr("key '" + key + "'"));
  EXPECT_THAT(ErrorOf(file, {key + "=inf"}), HasSubstr("key '" + key + "'"));
  EXPECT_THAT(ErrorOf(file, {"tdb.nde.inner_race_radius=0.06"}),
              HasSubstr("unknown key 'tdb.nde.inner_race_radius'"));
  EXPECT_EQ(ErrorOf(file, {key + "=0.06"}), "no error");  // the bore may touch the journal
}

// The journal pressed into the race from above by `depth_m`, spinning at `spin_rad_s`, on the
// race's own position for kinds with race masses (state 2 is the race centre's y on each).
JournalMotion PressedJournal(const TdbParams& p, const double* state, double depth_m,
                             double spin_rad_s) {
  double race_y = 0.0;
  if (p.model() != TdbModelKind::kContactLaw) race_y = state[2];
  const double centre_y = p.misalignment.enabled ? p.misalignment.y_m : 0.0;
  const double centre_x = p.misalignment.enabled ? p.misalignment.x_m : 0.0;
  return {centre_x, centre_y + race_y - (p.clearance_m + depth_m), 0.0, 0.0, spin_rad_s};
}

// Pure rolling (Jarroux 2019 Eq. (11): zero slip) is at Omega Rir = omega Rj on every kind: no
// friction there, friction spinning the race up below it; and the race torque is ft Rir, so at
// rest the spin-up rate scales with Rir.
TEST(InnerRaceRadius, EveryKindRollsAndSpinsUpOnIt) {
  for (const Rig& rig : kRigs) {
    SCOPED_TRACE(rig.file);
    const TdbParams base = testing::LoadTestConfig(rig.file).tdbs[0];
    const double rj = base.journal_radius_m;
    const double spin = 500.0;
    double start_rate[2] = {0.0, 0.0};
    const double radii[2] = {rj, rj * 1.1};
    for (int k = 0; k < 2; ++k) {
      TdbParams p = base;
      p.inner_race_radius_m = radii[k];
      const auto tdb = MakeTouchdownBearing(p);
      std::vector<double> state(tdb->StateSize()), rate(tdb->StateSize());
      tdb->InitialState(state.data());
      const JournalMotion j = PressedJournal(p, state.data(), 2e-6, spin);
      TdbForce f;
      tdb->Evaluate(j, state.data(), rate.data(), &f);
      ASSERT_GT(f.normal_force_N, 0.0);
      EXPECT_GT(f.tangential_force_N, 0.0);
      start_rate[k] = rate[0];
      state[0] = spin * rj / radii[k];  // pure rolling on Rir
      tdb->Evaluate(j, state.data(), rate.data(), &f);
      EXPECT_NEAR(f.tangential_force_N, 0.0, 1e-9 * f.normal_force_N);
    }
    // At rest the resisting torques vanish with their smooth sign; what is left is ft Rir / I.
    EXPECT_NEAR(start_rate[1] / start_rate[0], radii[1] / radii[0], 1e-9);
  }
}

// Spin-up of the contact-law race under a journal held in contact at constant spin, no drag:
// the race ends at omega Rj / Rir, so a larger Rir ends proportionally slower (the 0.83 % of an
// independent simulator whose race radius is the journal radius).
TEST(InnerRaceRadius, SpinUpEndsAtJournalRadiusOverRaceRadius) {
  TdbParams p = testing::LoadTestConfig("jarroux2019_industrial.toml").tdbs[0];
  p.spin.rotational_damping_N_m_s = 0.0;
  p.spin.palmgren_f1 = 0.0;
  p.spin.drag_torque_N_m = 0.0;
  const double rj = p.journal_radius_m;
  const double spin = 680.0;
  const std::vector<double> radii = {rj, rj + p.clearance_m, 1.2 * rj};
  std::vector<double> final_speed;
  for (double radius : radii) {
    p.inner_race_radius_m = radius;
    const ContactLawTdb tdb(p);
    const JournalMotion j = PressedJournal(p, nullptr, 100e-6, spin);
    double race = 0.0, rate = 0.0;
    TdbForce f;
    const double dt = 1e-5;
    for (int i = 0; i < 200000; ++i) {  // 2 s, many slip time constants
      tdb.Evaluate(j, &race, &rate, &f);
      race += dt * rate;
    }
    EXPECT_NEAR(race, spin * rj / radius, 1e-6 * spin) << radius;
    final_speed.push_back(race);
  }
  EXPECT_NEAR(final_speed[0] / final_speed[1], radii[1] / radii[0], 1e-8);
  EXPECT_NEAR(final_speed[0] / final_speed[2], 1.2, 1e-8);
}

}  // namespace
}  // namespace ambdrop::inner_race_radius_test
