// The contact-law TDB met by Hunt-Crossley's law (Jarroux 2019 Eq. (10) in place of Eq. (12)):
// a rigid race's static penetration, Hertz's impact duration, Hunt and Crossley's restitution,
// the law in series with a ribbon, and its config keys.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/config/config_keys.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/contact_law_tdb.hpp"
#include "test_configs.hpp"

namespace ambdrop::contact_law_hunt_crossley_test {
namespace {

constexpr double kClearance_m = 0.2e-3;

TdbParams Tdb(double stiffness_N_per_m_n, double exponent, double damping_s_per_m) {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.journal_radius_m = 0.03;
  p.clearance_m = kClearance_m;
  ContactLawParams c;
  c.normal_law = ContactLawNormal::kHuntCrossley;
  c.hunt_crossley = {stiffness_N_per_m_n, exponent, damping_s_per_m};
  p.model_params = c;
  p.friction.law = FrictionLaw::kNone;
  p.spin.enabled = false;
  return p;
}

// A point mass falling at v0 onto the TDB's bottom, integrated by RK4 at a step far below the
// contact's time: its rebound speed over v0 and how long it touched.
struct Impact {
  double restitution = 0.0;
  double contact_s = 0.0;
};

Impact DropOnto(const ContactLawTdb& tdb, double mass_kg, double v0_m_s) {
  double race = 0.0, race_rate = 0.0;
  TdbForce f;
  const auto acceleration = [&](double y, double v) {
    tdb.Evaluate({0.0, y, 0.0, v, 0.0}, &race, &race_rate, &f);
    return f.fy_N / mass_kg;
  };
  const double dt = 1e-8;
  double y = -kClearance_m, v = -v0_m_s, touching_s = 0.0;
  for (int i = 0; i < 10'000'000; ++i) {
    const double a1 = acceleration(y, v);
    const double a2 = acceleration(y + 0.5 * dt * v, v + 0.5 * dt * a1);
    const double a3 = acceleration(y + 0.5 * dt * (v + 0.5 * dt * a1), v + 0.5 * dt * a2);
    const double a4 = acceleration(y + dt * (v + 0.5 * dt * a2), v + dt * a3);
    y += dt * (v + dt * (a1 + a2 + a3) / 6.0);
    v += dt * (a1 + 2.0 * a2 + 2.0 * a3 + a4) / 6.0;
    if (y < -kClearance_m) touching_s += dt;
    if (y > -kClearance_m && v > 0.0 && touching_s > 0.0) break;
  }
  return {v / v0_m_s, touching_s};
}

TEST(ContactLawHuntCrossley, ARigidRaceCarriesTheWeightAtHertzsPenetration) {
  // kn delta^n = W at rest: delta = (W / kn)^(1/n) for a point (3/2) and a line-like (10/9) law.
  for (const double n : {1.5, 10.0 / 9.0, 1.0}) {
    const double kn = 2e10, weight_N = 700.0;
    const ContactLawTdb tdb(Tdb(kn, n, 0.3));
    const double delta = std::pow(weight_N / kn, 1.0 / n);
    double race = 0.0, rate = 0.0;
    TdbForce f;
    tdb.Evaluate({0.0, -(kClearance_m + delta), 0.0, 0.0, 0.0}, &race, &rate, &f);
    EXPECT_NEAR(f.fy_N, weight_N, 1e-9 * weight_N) << "n = " << n;
    EXPECT_NEAR(f.normal_force_N, weight_N, 1e-9 * weight_N);
    EXPECT_NEAR(f.support_y_N, -weight_N, 1e-9 * weight_N);  // the housing is pushed down
    EXPECT_NEAR(f.penetration_m, delta, 1e-15);
    EXPECT_EQ(f.fx_N, 0.0);
  }
}

TEST(ContactLawHuntCrossley, AnUndampedPointImpactLastsHertzsTime) {
  // Hertz (Johnson, Contact Mechanics, Sec. 11.4): an elastic impact at v on F = kn delta^(3/2)
  // lasts 2.9432 delta_max / v, delta_max = (5 m v^2 / (4 kn))^(2/5), and gives back v.
  const double mass_kg = 5.0, kn = 1e10, v0 = 0.1;
  const Impact impact = DropOnto(ContactLawTdb(Tdb(kn, 1.5, 0.0)), mass_kg, v0);
  const double delta_max = std::pow(5.0 * mass_kg * v0 * v0 / (4.0 * kn), 0.4);
  EXPECT_NEAR(impact.contact_s, 2.9432 * delta_max / v0, 2e-4 * 2.9432 * delta_max / v0);
  EXPECT_NEAR(impact.restitution, 1.0, 1e-9);
}

TEST(ContactLawHuntCrossley, ItsDampingGivesHuntAndCrossleysRestitution) {
  // Hunt & Crossley (1975): with lambda = 3/2 alpha kn, e = 1 - alpha v to first order in alpha v.
  for (const double alpha_v : {0.01, 0.02}) {
    const double v0 = 0.1;
    const Impact impact = DropOnto(ContactLawTdb(Tdb(1e10, 1.5, alpha_v / v0)), 5.0, v0);
    EXPECT_NEAR((1.0 - impact.restitution) / alpha_v, 1.0, 2.5 * alpha_v) << alpha_v;
  }
}

TEST(ContactLawHuntCrossley, InSeriesWithARibbonTheRaceRestsWhereBothCarryTheLoad) {
  // A massless race on a cross-coupled ribbon with no cross-coupling (a linear spring kr): at
  // rest kr u = kn delta^n along the contact's normal, and then nothing moves.
  TdbParams p = Tdb(3e9, 1.5, 0.5);
  ContactLawParams& c = p.contact_law();
  c.ribbon = ContactLawRibbon::kCrossCoupled;
  c.cross_coupled = {2e6, 0.0, 400.0, 100.0};
  const ContactLawTdb tdb(p);
  const double load_N = 300.0;
  const double u = load_N / c.cross_coupled.stiffness_N_per_m;
  const double delta = std::pow(load_N / 3e9, 1.0 / 1.5);
  double state[ContactLawTdb::kStatesCrossCoupled] = {0.0, 0.0, -u};
  double rate[ContactLawTdb::kStatesCrossCoupled] = {};
  TdbForce f;
  tdb.Evaluate({0.0, -(u + kClearance_m + delta), 0.0, 0.0, 0.0}, state, rate, &f);
  EXPECT_NEAR(f.normal_force_N, load_N, 1e-9 * load_N);
  EXPECT_NEAR(rate[ContactLawTdb::kRibbonY], 0.0, 1e-12);
  EXPECT_NEAR(f.support_y_N, -load_N, 1e-9 * load_N);
  // Pressed in faster than the race can follow, the contact's damping shares the push with the
  // ribbon's: (c + 3/2 alpha E) u' = E (1 + 3/2 alpha v) - R with E = kn delta^n.
  const double v = -0.05;  // the journal moving down, into the race
  tdb.Evaluate({0.0, -(u + kClearance_m + delta), 0.0, v, 0.0}, state, rate, &f);
  const double viscous = 1.5 * 0.5 * load_N;
  const double expected_rate = -(viscous * -v) / (400.0 + viscous);  // along -y, the normal
  EXPECT_NEAR(rate[ContactLawTdb::kRibbonY], expected_rate, 1e-12);
  EXPECT_NEAR(f.normal_force_N, load_N + viscous * (-v + expected_rate), 1e-9 * load_N);
}

TEST(ContactLawHuntCrossley, ConfigSelectsItAndNeedsOnlyItsOwnNumbers) {
  // Eq. (10) replaces Eq. (12): neither the bearing's nor the ribbon's numbers are asked for.
  const std::string rig = testing::kSmallRigidRotor + R"([tdb.a]
position_m = 0.1
journal_radius_m = 0.02
clearance_m = 2e-4
[tdb.a.contact_law]
normal_law = "hunt_crossley"
[tdb.a.contact_law.hunt_crossley]
stiffness_N_per_m_n = 4e10
exponent = 1.5
damping_s_per_m = 0.3
)";
  const LoadedConfig read = LoadConfigFromString(rig, "rig.toml");
  const ContactLawParams& c = read.params.tdbs.at(0).contact_law();
  EXPECT_EQ(c.normal_law, ContactLawNormal::kHuntCrossley);
  EXPECT_EQ(c.hunt_crossley.stiffness_N_per_m_n, 4e10);
  EXPECT_EQ(c.hunt_crossley.exponent, 1.5);
  EXPECT_EQ(c.hunt_crossley.damping_s_per_m, 0.3);
  // Its numbers are the registry's, as a fit's "declared value is off" candidates.
  const ConfigKey* k = FindKey(read.keys, "tdb.a.contact_law.hunt_crossley.stiffness_N_per_m_n");
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->key_class, KeyClass::kPhysical);
  EXPECT_EQ(FindKey(read.keys, "tdb.a.contact_law.bearing_stiffness_N_per_m"), nullptr);

  // Selected without its table: the error names the table.
  const std::string without = rig.substr(0, rig.find("[tdb.a.contact_law.hunt_crossley]"));
  EXPECT_NE(testing::ConfigErrorOf(without).find("hunt_crossley"), std::string::npos)
      << testing::ConfigErrorOf(without);
  // An exponent outside Hunt and Crossley's [1, 2] is refused with its key.
  const std::string error =
      testing::ConfigErrorOf(rig, {"tdb.a.contact_law.hunt_crossley.exponent=2.5"});
  EXPECT_NE(error.find("exponent"), std::string::npos) << error;
  // Switched back by --set, the bilinear law asks for its numbers again.
  EXPECT_NE(testing::ConfigErrorOf(rig, {"tdb.a.contact_law.normal_law=\"bilinear\""})
                .find("bearing_stiffness_N_per_m"),
            std::string::npos);
}

}  // namespace
}  // namespace ambdrop::contact_law_hunt_crossley_test
