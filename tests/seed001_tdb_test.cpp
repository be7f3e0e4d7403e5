// The seed-001 options of the 4-DOF TDB (Jarroux 2016, "Parametric analysis of a rigid rotor
// drop onto touchdown bearings"): the cross-coupled ribbon of its Eq. (1) and the quadratic
// bearing law against hand-computed values, the cross-coupling never feeding the outer race's
// whirl, the races' static equilibrium, the config keys (with negative tests), and the step with
// these options allocation-free and bit-identical on repeat.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "drop_step_checks.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/four_dof_tdb.hpp"
#include "rt_core/model.hpp"
#include "rt_core/ribbon_cross_coupled.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::seed001_tdb_test {
namespace {

using S = FourDofTdb;
using ::testing::HasSubstr;
using States = std::array<double, S::kStatesDahl>;
constexpr double kPi = std::numbers::pi;

TdbParams Tdb(BearingLaw bearing = BearingLaw::kHertzLinearised) {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.UseFourDof();
  p.journal_radius_m = 0.06;
  p.clearance_m = 0.25e-3;
  p.friction = {FrictionLaw::kRegularisedCoulomb, 0.2, 200.0, 0.0};
  p.spin = {true, 2.2e-3, 1e-4, 0.0, 0.0, 0.0};
  FourDofParams& f = p.four_dof();
  f.inner_race_mass_kg = 0.4;
  f.outer_race_mass_kg = 0.5;
  f.ribbon_clearance_m = 0.146e-3;
  f.inner_contact = {5e9, 1.0, 0.2};
  f.housing_contact = {4e9, 1.0, 0.3};
  f.bearing = {bearing, 40, 0.0, 8e9, 8e9, 1000.0, 1.0, 0.0};
  f.ribbon = RibbonLaw::kCrossCoupled;
  f.cross_coupled = {5e6, 0.3, 7e3, 100.0};
  return p;
}

// ---- Cross-coupled ribbon, Jarroux 2016 (seed 001) Eq. (1) ----

TEST(CrossCoupledRibbon, HandValuesAtTheBottomWhirlingForward) {
  // Outer race 0.1 mm below the centre moving along +x at 0.01 m/s: whirl speed +0.01 m/s
  // (anticlockwise, with the spin), sgn = (2/pi) atan(100 * 0.01) = 0.5, eta sgn = 0.15.
  const CrossCoupledRibbonParams p{5e6, 0.3, 7e3, 100.0};
  EXPECT_NEAR(WhirlSpeed(0.0, -1e-4, 0.01, 0.0), 0.01, 1e-15);
  double fx = 0.0, fy = 0.0;
  CrossCoupledRibbonForce(p, 0.0, -1e-4, 0.01, 0.0, &fx, &fy);
  // frd_x = kcrd (x - eta s y) + ccrd x' = 5e6 * 0.15e-4 + 7e3 * 0.01 = 75 + 70 N.
  EXPECT_NEAR(fx, 145.0, 1e-9);
  // frd_y = kcrd (eta s x + y) = -500 N.
  EXPECT_NEAR(fy, -500.0, 1e-9);
  // Whirling backward (x' = -0.01) the cross-coupled part turns round: -75 - 70 N.
  CrossCoupledRibbonForce(p, 0.0, -1e-4, -0.01, 0.0, &fx, &fy);
  EXPECT_NEAR(fx, -75.0 - 70.0, 1e-9);
  EXPECT_NEAR(fy, -500.0, 1e-9);
  // No whirl (radial motion only): no cross-coupling, Kelvin-Voigt per axis.
  CrossCoupledRibbonForce(p, 0.0, -1e-4, 0.0, -0.02, &fx, &fy);
  EXPECT_EQ(fx, 0.0);
  EXPECT_NEAR(fy, -500.0 - 140.0, 1e-9);
}

TEST(CrossCoupledRibbon, SignFollowsTheArctanLaw) {
  const CrossCoupledRibbonParams p{1e6, 1.0, 0.0, 50.0};
  // At (r, 0) moving along +y at v: frd_y = kcrd eta (2/pi) atan(vref v) r.
  for (const double v : {-0.1, -0.01, 0.001, 0.02, 1.0}) {
    double fx = 0.0, fy = 0.0;
    CrossCoupledRibbonForce(p, 1e-4, 0.0, 0.0, v, &fx, &fy);
    EXPECT_NEAR(fy, 1e6 * 1e-4 * 2.0 / kPi * std::atan(50.0 * v), 1e-12) << v;
    EXPECT_NEAR(fx, 1e6 * 1e-4, 1e-12);
  }
}

TEST(CrossCoupledRibbon, CrossCouplingNeverFeedsTheWhirl) {
  // Power of the cross-coupled part on the outer race (force -frd less its Kelvin-Voigt part)
  // is <= 0 at random states, and strictly negative when the race whirls.
  const CrossCoupledRibbonParams p{5e6, 0.4, 7e3, 100.0};
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  auto uniform = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  for (int trial = 0; trial < 1000; ++trial) {
    const double x = (2 * uniform() - 1) * 2e-4, y = (2 * uniform() - 1) * 2e-4;
    const double vx = (2 * uniform() - 1) * 0.1, vy = (2 * uniform() - 1) * 0.1;
    double fx = 0.0, fy = 0.0;
    CrossCoupledRibbonForce(p, x, y, vx, vy, &fx, &fy);
    const double cross_x = -(fx - 5e6 * x - 7e3 * vx);
    const double cross_y = -(fy - 5e6 * y - 7e3 * vy);
    const double power = cross_x * vx + cross_y * vy;
    EXPECT_LE(power, 0.0) << trial;
    if (std::abs(WhirlSpeed(x, y, vx, vy)) > 1e-3) {
      EXPECT_LT(power, 0.0) << trial;
    }
  }
}

TEST(FourDofCrossCoupled, OuterRaceFeelsMinusEq1AndTheHousingItsForce) {
  const FourDofTdb tdb(Tdb());
  EXPECT_EQ(tdb.StateSize(), S::kStatesKelvinVoigt);  // no internal ribbon state
  States s{}, rate{};
  s[S::kOuterY] = s[S::kInnerY] = -1e-4;  // races together: no bearing force
  s[S::kOuterVx] = s[S::kInnerVx] = 0.01;
  TdbForce f;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(rate[S::kOuterVx], -145.0 / 0.5, 1e-9);
  EXPECT_NEAR(rate[S::kOuterVy], 500.0 / 0.5, 1e-9);
  EXPECT_EQ(rate[S::kInnerVx], 0.0);
  EXPECT_NEAR(f.support_force_N(), std::hypot(145.0, 500.0), 1e-9);
}

TEST(FourDofCrossCoupled, HousingContactOnceTheRibbonClearanceIsUsed) {
  const FourDofTdb tdb(Tdb());
  States s{}, rate{};
  // 2 um beyond the 0.146 mm ribbon clearance, straight down, moving out at 0.01 m/s.
  s[S::kOuterY] = s[S::kInnerY] = -0.148e-3;
  s[S::kOuterVy] = s[S::kInnerVy] = -0.01;
  TdbForce f;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  const double fh = 4e9 * 2e-6 * (1.0 + 1.5 * 0.3 * 0.01);  // Hunt-Crossley, seed 000 Eq. (10)
  const double ribbon = 5e6 * -0.148e-3 + 7e3 * -0.01;      // Eq. (1), no whirl
  EXPECT_NEAR(rate[S::kOuterVy], (fh - ribbon) / 0.5, 1e-6);
  EXPECT_NEAR(f.support_force_N(), std::abs(ribbon) + fh, 1e-6);
  // 1 um inside the clearance: the ribbon alone.
  s[S::kOuterY] = s[S::kInnerY] = -0.145e-3;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(f.support_force_N(), 5e6 * 0.145e-3 + 70.0, 1e-6);
}

// ---- Quadratic bearing law, Jarroux 2016 (seed 001) Sec. 2 ----

TEST(QuadraticBearing, GivenStiffnessHandValues) {
  TdbParams p = Tdb(BearingLaw::kQuadratic);
  p.four_dof().bearing.quadratic_stiffness_N_per_m2 = 2e13;
  const FourDofTdb tdb(p);
  EXPECT_EQ(tdb.bearing().quadratic_constant_N_per_m2, 2e13);
  States s{}, rate{};
  // Inner race 3 um right of and 4 um below the outer race (5 um): Fr = 2e13 * 25e-12 = 500 N
  // towards the outer race's centre, i.e. (-300, +400) N on the inner race.
  s[S::kInnerX] = 3e-6;
  s[S::kInnerY] = -4e-6;
  TdbForce f;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(rate[S::kInnerVx], -300.0 / 0.4, 1e-9);
  EXPECT_NEAR(rate[S::kInnerVy], 400.0 / 0.4, 1e-9);
  // Doubling the deflection quadruples the force (a linear law would double it).
  s[S::kInnerX] = 6e-6;
  s[S::kInnerY] = -8e-6;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(rate[S::kInnerVx], -1200.0 / 0.4, 1e-9);
  // The damping is cbrg of seed 000 Eq. (8), as for the other laws.
  s[S::kInnerX] = 0.0;
  s[S::kInnerY] = 0.0;
  s[S::kInnerVy] = 0.1;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(rate[S::kInnerVy], -tdb.bearing().damping_N_s_per_m * 0.1 / 0.4, 1e-9);
}

TEST(QuadraticBearing, DefaultIsTheSecantThroughTheHertzOperatingPoint) {
  const FourDofTdb tdb(Tdb(BearingLaw::kQuadratic));
  const BallBearingCoefficients& c = tdb.bearing();
  // Hertz deflection under the 1000 N operating load, ur0 = (F0 / K)^(2/3).
  const double ur0 = std::pow(1000.0 / c.radial_constant_N_per_m1_5, 2.0 / 3.0);
  double fx = 0.0, fy = 0.0;
  BallBearingForce(BearingLaw::kQuadratic, c, 0.0, -ur0, 0.0, 0.0, &fx, &fy);
  EXPECT_NEAR(fy, 1000.0, 1e-9);
  BallBearingForce(BearingLaw::kHertz, c, 0.0, -ur0, 0.0, 0.0, &fx, &fy);
  EXPECT_NEAR(fy, 1000.0, 1e-9);
  // Below the operating point the quadratic law is softer than Hertz (u^2 < u^1.5 ur0^0.5).
  double quadratic = 0.0, hertz = 0.0;
  BallBearingForce(BearingLaw::kQuadratic, c, 0.0, -0.5 * ur0, 0.0, 0.0, &fx, &quadratic);
  BallBearingForce(BearingLaw::kHertz, c, 0.0, -0.5 * ur0, 0.0, 0.0, &fx, &hertz);
  EXPECT_NEAR(quadratic, 250.0, 1e-9);
  EXPECT_NEAR(hertz, 1000.0 * std::pow(0.5, 1.5), 1e-9);
}

TEST(FourDofSeed001, RacesStartInStaticEquilibriumUnderGravity) {
  for (const BearingLaw law : {BearingLaw::kQuadratic, BearingLaw::kHertzLinearised}) {
    TdbParams p = Tdb(law);
    p.four_dof().gravity_y_m_s2 = -9.81;
    const FourDofTdb tdb(p);
    States s{}, rate{};
    tdb.InitialState(s.data());
    TdbForce f;
    tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
    for (int i = 0; i < tdb.StateSize(); ++i) EXPECT_NEAR(rate[i], 0.0, 1e-9) << i;
    EXPECT_NEAR(s[S::kOuterY], -0.9 * 9.81 / 5e6, 1e-18);  // kcrd carries both races
    EXPECT_LT(s[S::kInnerY], s[S::kOuterY]);
    EXPECT_NEAR(f.support_force_N(), 0.9 * 9.81, 1e-9);
  }
  TdbParams bad = Tdb();
  bad.four_dof().cross_coupled.stiffness_N_per_m = 0.0;
  EXPECT_THROW(FourDofTdb{bad}, std::invalid_argument);
}

// ---- Config keys ----

std::string ErrorOf(const std::vector<std::string>& overrides) {
  try {
    LoadConfig(testing::ConfigPath("jarroux2016_rigid.toml"), overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ConfigSeed001, RigReadsAsWritten) {
  const ModelParams p = testing::LoadTestConfig("jarroux2016_rigid.toml");
  EXPECT_EQ(p.rotor.kind, RotorKind::kRigid);
  ASSERT_EQ(p.tdbs.size(), 2u);
  for (const TdbParams& t : p.tdbs) {
    EXPECT_EQ(t.model(), TdbModelKind::kFourDof);
    EXPECT_EQ(t.four_dof().ribbon, RibbonLaw::kCrossCoupled);
    EXPECT_EQ(t.four_dof().bearing.law, BearingLaw::kQuadratic);
    EXPECT_EQ(t.four_dof().bearing.quadratic_stiffness_N_per_m2, 0.0);  // derived
    EXPECT_DOUBLE_EQ(t.four_dof().cross_coupled.stiffness_N_per_m, 5.0e6);
    EXPECT_DOUBLE_EQ(t.four_dof().cross_coupled.cross_coupling, 0.3);
    EXPECT_DOUBLE_EQ(t.four_dof().cross_coupled.damping_N_s_per_m, 7.0e3);
    EXPECT_DOUBLE_EQ(t.four_dof().cross_coupled.sign_regularisation_s_per_m, 100.0);
  }
  const ModelParams q = testing::LoadTestConfig(
      "jarroux2016_rigid.toml", {"tdb.de.four_dof.bearing.quadratic_stiffness_N_per_m2=3e13"});
  const TdbParams& de = q.tdbs.at(0).name == "de" ? q.tdbs.at(0) : q.tdbs.at(1);
  EXPECT_DOUBLE_EQ(de.four_dof().bearing.quadratic_stiffness_N_per_m2, 3e13);
}

TEST(ConfigSeed001, ErrorsNameKeyAndExpectation) {
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.cross_coupled.eta=0.1"}),
              HasSubstr("unknown key 'tdb.de.four_dof.cross_coupled.eta'"));
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.cross_coupled.cross_coupling=-0.1"}),
              HasSubstr("key 'tdb.de.four_dof.cross_coupled.cross_coupling': expected a "
                        "non-negative number"));
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.cross_coupled.stiffness_N_per_m=0"}),
              HasSubstr("expected a positive number (N/m), found 0"));
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.bearing.quadratic_stiffness_N_per_m2=-1"}),
              HasSubstr("key 'tdb.de.four_dof.bearing.quadratic_stiffness_N_per_m2': expected "
                        "a positive number"));
  // Switching the ribbon needs the selected ribbon's table.
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.ribbon=\"kelvin_voigt\""}),
              HasSubstr("missing key 'tdb.de.four_dof.kelvin_voigt': expected a table"));
  EXPECT_THAT(ErrorOf({"tdb.de.four_dof.ribbon=\"crosscoupled\""}),
              HasSubstr("expected one of \"kelvin_voigt\", \"dahl\", \"cross_coupled\""));
}

// ---- The step with the seed-001 options ----

Model Rig(std::vector<std::string> extra) {
  std::vector<std::string> overrides = {"trigger.time_s=0.005", "tdb.de.friction.coefficient=0.4",
                                        "tdb.nde.friction.coefficient=0.4"};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return BuildModel(testing::LoadTestConfig("jarroux2016_rigid.toml", overrides));
}

std::vector<std::vector<std::string>> Variants() {
  return {{},
          {"tdb.de.four_dof.bearing_law=\"hertz\"", "tdb.de.misalignment.enabled=true",
           "tdb.de.misalignment.y_m=-2e-5"}};
}

TEST(Seed001Step, NoHeapAllocationThroughTheDrop) {
  for (const auto& v : Variants()) testing::ExpectDropAllocatesNothing(Rig(v));
}

TEST(Seed001Step, RepeatedRunsAreBitIdentical) {
  for (const auto& v : Variants()) testing::ExpectDropBitIdentical(Rig(v));
}

}  // namespace
}  // namespace ambdrop::seed001_tdb_test
