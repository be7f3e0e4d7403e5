// The 4-DOF TDB's force laws against hand-computed values: Hunt-Crossley (Jarroux 2019
// Eq. (10)), Hertz ball bearing (Eq. (5)-(8)), Kelvin-Voigt ribbon (Eq. (4)), generalized Dahl
// envelopes and rate (Eq. (1)-(3)).
#include <gtest/gtest.h>

#include <cmath>

#include "rt_core/ball_bearing.hpp"
#include "rt_core/hunt_crossley.hpp"
#include "rt_core/ribbon_dahl.hpp"
#include "rt_core/ribbon_kelvin_voigt.hpp"

namespace ambdrop::tdb_force_laws_test {
namespace {

TEST(HuntCrossley, LinearExponentAsPrinted) {
  const HuntCrossleyParams p{5e9, 1.0, 0.2};
  // 10 um in, approaching at 0.1 m/s: 5e9 * 1e-5 * (1 + 1.5 * 0.2 * 0.1) = 51 500 N.
  EXPECT_NEAR(HuntCrossleyForce(p, 1e-5, 0.1), 51500.0, 1e-9);
  // Receding at 0.1 m/s: 5e4 * (1 - 0.03) = 48 500 N.
  EXPECT_NEAR(HuntCrossleyForce(p, 1e-5, -0.1), 48500.0, 1e-9);
  // At rest: the spring alone.
  EXPECT_NEAR(HuntCrossleyForce(p, 2e-6, 0.0), 1e4, 1e-9);
}

TEST(HuntCrossley, HertzianAndGeneralExponents) {
  // n = 3/2: 1e10 * (4e-6)^1.5 = 1e10 * 8e-9 = 80 N, times (1 + 1.5 * 0.5 * 0.2) = 1.15.
  EXPECT_NEAR(HuntCrossleyForce({1e10, 1.5, 0.5}, 4e-6, 0.2), 92.0, 1e-9);
  // n = 10/9 (line contact): 1e9 * (1e-6)^(10/9) = 1e9 * 1e-6 * 10^(-2/3) = 215.443... N.
  EXPECT_NEAR(HuntCrossleyForce({1e9, 10.0 / 9.0, 0.0}, 1e-6, 0.0),
              1e3 * std::pow(10.0, -2.0 / 3.0), 1e-9);
}

TEST(HuntCrossley, NoForceOutsideContactAndNeverPulls) {
  const HuntCrossleyParams p{5e9, 1.0, 0.2};
  EXPECT_EQ(HuntCrossleyForce(p, 0.0, 1.0), 0.0);
  EXPECT_EQ(HuntCrossleyForce(p, -1e-6, 1.0), 0.0);
  // Receding faster than 1 / (1.5 alpha) = 3.33 m/s: the factor turns negative, the force is 0.
  EXPECT_EQ(HuntCrossleyForce(p, 1e-5, -4.0), 0.0);
}

TEST(BallBearing, CoupledStiffnessEq6) {
  // Equal contacts: kn = (2 k^(-2/3))^(-3/2) = k / 2^(3/2).
  EXPECT_NEAR(CoupledBallStiffness(8e9, 8e9), 8e9 / std::sqrt(8.0), 1e-3);
  // k_ir = 1e9, k_or = 8e9: (1e-6 + 0.25e-6)^(-3/2) = (1.25e-6)^(-1.5) = 7.155e8.
  EXPECT_NEAR(CoupledBallStiffness(1e9, 8e9), std::pow(1.25e-6, -1.5), 1e-3);
}

TEST(BallBearing, RadialIntegralIsHarrisJr) {
  // Harris, Jr(epsilon = 0.5) = 0.2288; and a midpoint-rule integral of Eq. (5)'s integrand.
  EXPECT_NEAR(RadialLoadIntegral(), 0.2288, 5e-5);
  const int n = 200000;
  const double pi = 3.14159265358979323846;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double theta = -pi / 2 + (i + 0.5) * pi / n;
    sum += std::pow(std::cos(theta), 2.5) * pi / n;
  }
  EXPECT_NEAR(RadialLoadIntegral(), sum / (2 * pi), 1e-9);
}

TEST(BallBearing, LinearisedStiffnessAndKramerDamping) {
  BallBearingParams p;
  p.balls = 40;
  p.contact_angle_rad = 0.0;  // cos = 1
  p.inner_contact_stiffness_N_per_m1_5 = 8e9;
  p.outer_contact_stiffness_N_per_m1_5 = 8e9;
  p.operating_load_N = 1000.0;
  p.damping_factor = 1.0;
  const BallBearingCoefficients c = BallBearingFromHertz(p);
  // K = Z kn Jr = 40 * 8e9 / 2.828427 * 0.228828 = 2.58794e10 N/m^1.5.
  const double k = 40.0 * 8e9 / std::sqrt(8.0) * 0.2288279290505;
  EXPECT_NEAR(c.radial_constant_N_per_m1_5 / k, 1.0, 1e-12);
  // kbrg = dFr/dur at Fr = 1000 N, by a central difference of K ur^1.5.
  const double ur0 = std::pow(1000.0 / k, 2.0 / 3.0);
  const double h = 1e-4 * ur0;
  const double slope = (k * std::pow(ur0 + h, 1.5) - k * std::pow(ur0 - h, 1.5)) / (2 * h);
  EXPECT_NEAR(c.stiffness_N_per_m / slope, 1.0, 1e-7);
  // Eq. (8): cbrg = 1e-5 kbrg for a factor of 1.
  EXPECT_NEAR(c.damping_N_s_per_m, 1e-5 * c.stiffness_N_per_m, 1e-9);
  // A contact angle shrinks K by cos^(5/2).
  p.contact_angle_rad = 0.5;
  EXPECT_NEAR(BallBearingFromHertz(p).radial_constant_N_per_m1_5 / k, std::pow(std::cos(0.5), 2.5),
              1e-12);
}

TEST(BallBearing, ForcesOnTheInnerRace) {
  const BallBearingCoefficients c{1e10, 2e8, 2e3};
  double fx = 0.0, fy = 0.0;
  // Linearised: inner race 3 um right and 4 um down of the outer race, moving up at 0.01 m/s.
  BallBearingForce(BearingLaw::kHertzLinearised, c, 3e-6, -4e-6, 0.0, 0.01, &fx, &fy);
  EXPECT_NEAR(fx, -600.0, 1e-9);        // -2e8 * 3e-6
  EXPECT_NEAR(fy, 800.0 - 20.0, 1e-9);  // -2e8 * -4e-6 - 2e3 * 0.01
  // Hertz: |d| = 5 um, K |d|^1.5 = 1e10 * 1.118034e-8 = 111.8034 N along -d.
  BallBearingForce(BearingLaw::kHertz, c, 3e-6, -4e-6, 0.0, 0.0, &fx, &fy);
  const double magnitude = 1e10 * std::pow(5e-6, 1.5);
  EXPECT_NEAR(fx, -magnitude * 0.6, 1e-9);
  EXPECT_NEAR(fy, magnitude * 0.8, 1e-9);
  BallBearingForce(BearingLaw::kHertz, c, 0.0, 0.0, 0.0, 0.0, &fx, &fy);
  EXPECT_EQ(fx, 0.0);
  EXPECT_EQ(fy, 0.0);
}

TEST(KelvinVoigtRibbon, Eq4) {
  const KelvinVoigtRibbonParams p{5e6, 7e3};
  EXPECT_NEAR(KelvinVoigtRibbonForce(p, 1e-4, 0.02), 500.0 + 140.0, 1e-9);
  EXPECT_NEAR(KelvinVoigtRibbonForce(p, -1e-4, 0.0), -500.0, 1e-9);
}

DahlRibbonParams Dahl() {
  DahlRibbonParams p;
  p.slipping_threshold_N = 400.0;
  p.threshold_scale = 0.5;
  p.slipping_stiffness_N_per_m = 5e6;
  p.beta_per_m = 6e4;
  p.upper_hardening_N = 20.0;
  p.upper_hardening_rate_per_m = 2.5e4;
  p.lower_hardening_N = 10.0;
  p.lower_hardening_rate_per_m = 1e4;
  return p;
}

TEST(DahlRibbon, EnvelopesEq3) {
  const DahlRibbonParams p = Dahl();
  EXPECT_DOUBLE_EQ(DahlSlippingThreshold(p), 200.0);
  // u = 1e-4: hu = 200 + 500 + 20 e^2.5 = 943.6499 N; hl = -200 + 500 - 10 e^-1 = 296.3212 N.
  EXPECT_NEAR(DahlUpperEnvelope(p, 1e-4), 700.0 + 20.0 * 12.182493960703473, 1e-9);
  EXPECT_NEAR(DahlLowerEnvelope(p, 1e-4), 300.0 - 10.0 * 0.36787944117144233, 1e-9);
  // u = 0: hu = 220, hl = -210.
  EXPECT_NEAR(DahlUpperEnvelope(p, 0.0), 220.0, 1e-12);
  EXPECT_NEAR(DahlLowerEnvelope(p, 0.0), -210.0, 1e-12);
}

TEST(DahlRibbon, RateEq1RelaxesTowardsTheEnvelopeTheMotionSelects) {
  const DahlRibbonParams p = Dahl();
  // Loading at 0.01 m/s from 0 N at u = 0: 6e4 * 0.01 * (220 - 0) = 132 000 N/s.
  EXPECT_NEAR(DahlRibbonForceRate(p, 0.0, 0.01, 0.0), 132000.0, 1e-6);
  // Unloading at 0.01 m/s from 100 N: 6e4 * 0.01 * (-210 - 100) = -186 000 N/s.
  EXPECT_NEAR(DahlRibbonForceRate(p, 0.0, -0.01, 100.0), -186000.0, 1e-6);
  // On the envelope it follows: no relaxation left.
  EXPECT_NEAR(DahlRibbonForceRate(p, 1e-4, 0.01, DahlUpperEnvelope(p, 1e-4)), 0.0, 1e-9);
  // At rest the force holds.
  EXPECT_EQ(DahlRibbonForceRate(p, 1e-4, 0.0, 123.0), 0.0);
}

}  // namespace
}  // namespace ambdrop::tdb_force_laws_test
