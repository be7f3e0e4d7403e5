// AMB force laws of the HIL issue against hand-computed values: the differential-driving
// electromagnet (seed 003), its linearisation, amplifier limits and flux decay.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rt_core/amb_force.hpp"

namespace ambdrop::amb_force_law_test {
namespace {

ElectromagnetParams Seed003() {
  // Seed 003: pole area 1.96e-4 m^2, 130 turns, 0.25 mm gap, 2 A bias.
  return {1.96e-4, 130.0, 0.25e-3, 2.0, std::numbers::pi / 8.0};
}

TEST(Electromagnet, ForceMatchesTheLawByHand) {
  const ElectromagnetParams e = Seed003();
  const double k =
      4e-7 * std::numbers::pi * 130.0 * 130.0 * 1.96e-4 * std::cos(std::numbers::pi / 8) / 4;
  EXPECT_NEAR(ElectromagnetConstant(e) / k, 1.0, 1e-9);
  // i = 0.5 A, u = 0.05 mm towards the upper pole.
  const double expected = k * (2.5 * 2.5 / (0.2e-3 * 0.2e-3) - 1.5 * 1.5 / (0.3e-3 * 0.3e-3));
  EXPECT_NEAR(ElectromagnetForce(e, 0.5, 0.05e-3), expected, 1e-9 * std::abs(expected));
  // Centred with no control current the two magnets cancel.
  EXPECT_EQ(ElectromagnetForce(e, 0.0, 0.0), 0.0);
  // Antisymmetric in (i, u).
  EXPECT_NEAR(ElectromagnetForce(e, -0.5, -0.05e-3), -expected, 1e-9 * std::abs(expected));
}

TEST(Electromagnet, LinearisedGainsAreTheDerivativesAtTheCentre) {
  const ElectromagnetParams e = Seed003();
  const double di = 1e-6, du = 1e-10;
  const double ki = (ElectromagnetForce(e, di, 0) - ElectromagnetForce(e, -di, 0)) / (2 * di);
  const double ks = (ElectromagnetForce(e, 0, du) - ElectromagnetForce(e, 0, -du)) / (2 * du);
  EXPECT_NEAR(ElectromagnetCurrentGain(e) / ki, 1.0, 1e-6);
  EXPECT_NEAR(ElectromagnetPositionGain(e) / ks, 1.0, 1e-6);
  EXPECT_GT(ks, 0.0);  // open loop the bearing pulls the rotor off centre
}

TEST(Electromagnet, SaturationCapsEachCoilsPullAtTheSaturatedFluxDensity) {
  ElectromagnetParams e = Seed003();
  const double k = ElectromagnetConstant(e);
  e.saturation_enabled = true;
  e.saturation_flux_density_T = 1.2;
  // B = mu0 N I / (2 g): 130 turns, 2 A, 0.25 mm give 0.65 T, below 1.2 T: the law unchanged.
  const double b0 = 4e-7 * std::numbers::pi * 130.0 * 2.0 / (2 * 0.25e-3);
  ASSERT_LT(b0, 1.2);
  EXPECT_EQ(ElectromagnetForce(e, 0.5, 0.05e-3),
            ElectromagnetForce(k, e.nominal_gap_m, e.bias_current_A, 0.5, 0.05e-3));
  // F_sat = B_sat^2 A cos(alpha) / mu0, by hand.
  const double f_sat =
      1.2 * 1.2 * 1.96e-4 * std::cos(std::numbers::pi / 8) / (4e-7 * std::numbers::pi);
  EXPECT_NEAR(SaturatedCoilForce(e) / f_sat, 1.0, 1e-9);
  // Near the upper pole with the full control current, the upper coil saturates: the force is
  // F_sat minus the lower coil's unsaturated pull.
  const double i = 2.0, u = 0.2e-3;
  ASSERT_GT(4e-7 * std::numbers::pi * 130.0 * (2.0 + i) / (2 * (0.25e-3 - u)), 1.2);
  EXPECT_NEAR(ElectromagnetForce(e, i, u), f_sat - 0.0, 1e-9 * f_sat);  // lower coil: I0 - i = 0
  EXPECT_LT(ElectromagnetForce(e, i, u),
            ElectromagnetForce(k, e.nominal_gap_m, e.bias_current_A, i, u) / 10.0);
  // The cap is the saturation, nothing more: continuous where B crosses B_sat.
  const double i_sat = 1.2 * 2 * (0.25e-3 - u) / (4e-7 * std::numbers::pi * 130.0) - 2.0;
  EXPECT_NEAR(ElectromagnetForce(e, i_sat + 1e-9, u), ElectromagnetForce(e, i_sat - 1e-9, u),
              1e-4 * f_sat);
}

TEST(Electromagnet, AmplifierLimitsTheCurrent) {
  AmbParams a;
  a.law = AmbForceLaw::kElectromagnet;
  a.electromagnet = Seed003();
  a.current_limit_A = 3.0;
  // Both coils within [0, 3 A] around the 2 A bias: |i| <= 1 A.
  EXPECT_EQ(LimitedCurrent(a, 5.0), 1.0);
  EXPECT_EQ(LimitedCurrent(a, -5.0), -1.0);
  EXPECT_EQ(LimitedCurrent(a, 0.4), 0.4);
  a.current_limit_A = 10.0;  // then the bias bounds it: a coil current cannot go negative
  EXPECT_EQ(LimitedCurrent(a, -5.0), -2.0);
  a.law = AmbForceLaw::kLinearisedCurrents;
  EXPECT_EQ(LimitedCurrent(a, -15.0), -10.0);
}

TEST(FluxDecay, ForceFadesWithTheSquareOfTheCurrents) {
  AmbParams a;
  EXPECT_EQ(FluxDecayForceScale(a, 0.0), 0.0);  // switched off: the force vanishes at once
  a.flux_decay = {true, 2e-3};
  EXPECT_EQ(FluxDecayForceScale(a, 0.0), 1.0);
  EXPECT_NEAR(FluxDecayForceScale(a, 2e-3), std::exp(-2.0), 1e-15);
  EXPECT_LT(FluxDecayForceScale(a, 20e-3), 1e-8);
}

TEST(FeedForward, CurrentForTheStaticLoad) {
  AmbParams a;
  a.law = AmbForceLaw::kElectromagnet;
  a.electromagnet = Seed003();
  const double i = CurrentForStaticForce(a, 10.0);
  EXPECT_NEAR(ElectromagnetCurrentGain(a.electromagnet) * i, 10.0, 1e-12);
}

}  // namespace
}  // namespace ambdrop::amb_force_law_test
