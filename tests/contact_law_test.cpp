// Contact-law TDB (Jarroux 2019 Eq. (9), (11), (12)) against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rt_core/contact_law_tdb.hpp"

namespace ambdrop::contact_law_test {
namespace {

TdbParams Tdb() {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.journal_radius_m = 0.05;
  p.clearance_m = 0.2e-3;
  p.contact_law() = {2e8, 2e3, 5e6, 7e3, 0.1e-3, ContactLawRibbon::kBilinear, {}, {}};
  p.friction = {FrictionLaw::kRegularisedCoulomb, 0.2, 200.0, 500.0};
  p.spin = {true, 2.2e-3, 1e-4, 0.0, 0.0, 0.0};
  return p;
}

TEST(ContactLaw, FreeJournalFeelsNothing) {
  const ContactLawTdb tdb(Tdb());
  double race = 10.0, rate = 0.0;
  TdbForce f;
  tdb.Evaluate({0.0, -0.19e-3, 0.0, -0.1, 500.0}, &race, &rate, &f);
  EXPECT_EQ(f.fx_N, 0.0);
  EXPECT_EQ(f.fy_N, 0.0);
  EXPECT_EQ(f.normal_force_N, 0.0);
  EXPECT_NEAR(f.penetration_m, -0.01e-3, 1e-15);
  EXPECT_DOUBLE_EQ(rate, -1e-4 * 10.0 / 2.2e-3);  // only Phi slows the free race
}

TEST(ContactLaw, RibbonBranchAtTheBottom) {
  const ContactLawTdb tdb(Tdb());
  double race = 0.0, rate = 0.0;
  TdbForce f;
  // 0.05 mm into the ribbon, moving down at 0.01 m/s, no spin.
  tdb.Evaluate({0.0, -0.25e-3, 0.0, -0.01, 0.0}, &race, &rate, &f);
  const double fn = 5e6 * 0.05e-3 + 7e3 * 0.01;  // keq urs + ceq urs'
  EXPECT_NEAR(f.normal_force_N, fn, 1e-9);
  EXPECT_NEAR(f.fy_N, fn, 1e-9);  // pushes the journal up
  EXPECT_NEAR(f.fx_N, 0.0, 1e-12);
  EXPECT_EQ(f.torque_on_rotor_N_m, 0.0);
  // and the housing down: the support force is the force passed to it, as on every TDB kind
  EXPECT_NEAR(f.support_y_N, -fn, 1e-9);
  EXPECT_EQ(f.support_x_N, -f.fx_N);
}

TEST(ContactLaw, CrushedRibbonBranchOnTheSide) {
  const ContactLawTdb tdb(Tdb());
  double race = 0.0, rate = 0.0;
  TdbForce f;
  // 0.15 mm beyond the clearance along +x, receding at 0.02 m/s, no spin or whirl.
  tdb.Evaluate({0.35e-3, 0.0, -0.02, 0.0, 0.0}, &race, &rate, &f);
  const double fn = 2e8 * (0.15e-3 - 0.1e-3) + 2e3 * (-0.02) + 5e6 * 0.1e-3;
  EXPECT_NEAR(f.normal_force_N, fn, 1e-6);
  EXPECT_NEAR(f.fx_N, -fn, 1e-6);
}

TEST(ContactLaw, FrictionBrakesTheRotorAndSpinsUpTheRace) {
  const ContactLawTdb tdb(Tdb());
  double race = 0.0, rate = 0.0;
  TdbForce f;
  const double spin = 600.0;
  tdb.Evaluate({0.0, -0.25e-3, 0.0, 0.0, spin}, &race, &rate, &f);
  const double fn = 5e6 * 0.05e-3;
  const double slip = spin * 0.05;  // journal surface speed, race at rest
  const double ft = 0.2 * fn * 2.0 / std::numbers::pi * std::atan(200.0 * slip);
  EXPECT_NEAR(f.tangential_force_N, ft, 1e-9);
  // At the bottom the journal surface moves along +x: friction on the rotor points along -x.
  EXPECT_NEAR(f.fx_N, -ft, 1e-9);
  EXPECT_NEAR(f.torque_on_rotor_N_m, -ft * 0.05, 1e-12);
  EXPECT_NEAR(rate, ft * (0.05 + 0.2e-3) / 2.2e-3, 1e-6);  // Eq. (9) with Omega_tdb = 0
}

TEST(ContactLaw, MisalignmentMovesTheContactCircle) {
  TdbParams p = Tdb();
  p.misalignment = {true, 0.0, -0.1e-3};  // TDB centre 0.1 mm low
  const ContactLawTdb tdb(p);
  double race = 0.0, rate = 0.0;
  TdbForce f;
  tdb.Evaluate({0.0, -0.25e-3, 0.0, 0.0, 0.0}, &race, &rate, &f);
  EXPECT_EQ(f.normal_force_N, 0.0);  // 0.15 mm from the moved centre: inside the clearance
  tdb.Evaluate({0.0, 0.15e-3, 0.0, 0.0, 0.0}, &race, &rate, &f);
  EXPECT_NEAR(f.penetration_m, 0.05e-3, 1e-15);  // 0.25 mm above the moved centre
  EXPECT_LT(f.fy_N, 0.0);
}

TEST(ContactLaw, DissipativeContactNeverAddsEnergy) {
  // Fixed-seed randomised impacts of a point mass on the contact law: the rebound speed never
  // exceeds the impact speed.
  TdbParams p = Tdb();
  p.friction.law = FrictionLaw::kNone;
  const ContactLawTdb tdb(p);
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  auto uniform = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  for (int trial = 0; trial < 50; ++trial) {
    const double mass = 10.0 + 200.0 * uniform();
    const double v0 = 0.01 + 0.5 * uniform();
    const double dt = 1e-7;
    double y = -p.clearance_m, v = -v0, race = 0.0, rate = 0.0;
    TdbForce f;
    for (int i = 0; i < 2000000 && !(y > -p.clearance_m && v > 0.0); ++i) {
      tdb.Evaluate({0.0, y, 0.0, v, 0.0}, &race, &rate, &f);
      v += dt * f.fy_N / mass;  // symplectic Euler
      y += dt * v;
    }
    EXPECT_GT(v, 0.0) << "trial " << trial;
    EXPECT_LE(v, v0 * (1 + 1e-3)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace ambdrop::contact_law_test
