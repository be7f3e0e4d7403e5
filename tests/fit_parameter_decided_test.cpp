// Which fitted values a record decides (ParameterDecided, tools/fit/effect_fit.hpp), on the
// figures the independent truth rigs gave (docs/fit.md): a Dahl ribbon's slipping stiffness that
// the 4-DOF rig's drop leaves open by decades beside the threshold it fixes to 2 %, and the
// numbers a relative rule would get wrong (an offset near zero, fixed to a micrometre).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "tools/fit/effect_fit.hpp"

namespace ambdrop::fit_parameter_decided_test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// As tools/fit/effect_library.cpp makes them for the truth rigs (the 4-DOF rig's Kelvin-Voigt
// ribbon of 3e7 N/m, a 0.2 mm clearance, an NDE TDB's share of the weight 250 N).
EffectParameter SlippingStiffness() {
  EffectParameter p{"slipping_stiffness_N_per_m", 3e3, 3e7, {6.5e4, 1.4e6}};
  p.log_scale = true;
  return p;
}
EffectParameter SlippingThreshold() {
  return {"slipping_threshold_N", 12.5, 5000.0, {250, 750}};
}
EffectParameter OffsetY() {
  return {"y_m", -2e-4, 2e-4, {0.0}};
}
EffectParameter Phase() {
  EffectParameter p{"phase_rad", -std::numbers::pi, std::numbers::pi, {0.0}};
  p.periodic = true;
  return p;
}
EffectParameter Eccentricity() {
  EffectParameter p{"mass_eccentricity_kg_m", 0.0, 1e-4, {1e-5}};
  p.magnitude = true;
  return p;
}
EffectParameter Delay() {
  EffectParameter p{"delay_s", 0.0, 1e-3, {1e-4}};
  p.quantum = 1e-4;
  return p;
}

TEST(FitParameterDecided, TheDahlRecordsStiffnessIsOpenWhereItsThresholdIsFixed) {
  // The 4-DOF rig's Dahl records (batteries of session 30): the threshold to 2 %, the slipping
  // stiffness with a sigma of 1.6 and 550 times its value; the rigid rig's with its housing
  // declared: 3.5e5 +- 2.6e4 N/m, within 17 % of the truth.
  EXPECT_TRUE(ParameterDecided(SlippingThreshold(), 462.3, 9.4, false));
  EXPECT_FALSE(ParameterDecided(SlippingStiffness(), 3327.0, 1.8e6, false));
  EXPECT_FALSE(ParameterDecided(SlippingStiffness(), 5.06e4, 8.0e4, false));
  EXPECT_TRUE(ParameterDecided(SlippingStiffness(), 3.5e5, 2.6e4, false));
}

TEST(FitParameterDecided, ANumberNearZeroIsDecidedByItsRangeNotItsValue) {
  // An offset of 1.2 +- 1 um in a 0.2 mm clearance is a measured "about zero"; the same sigma
  // on an unbalance, a size from 0 known only to its decade, is not.
  EXPECT_TRUE(ParameterDecided(OffsetY(), 1.2e-6, 1e-6, false));
  EXPECT_FALSE(ParameterDecided(OffsetY(), 1.2e-6, 1.2e-4, false));
  EXPECT_TRUE(ParameterDecided(Eccentricity(), 4.9e-6, 1e-8, false));
  EXPECT_FALSE(ParameterDecided(Eccentricity(), 4.9e-6, 3e-6, false));
  // A phase within +-0.05 rad is known; one whose sigma is a quarter turn or more is not.
  EXPECT_TRUE(ParameterDecided(Phase(), 0.37, 0.045, false));
  EXPECT_FALSE(ParameterDecided(Phase(), 0.37, 0.5 * std::numbers::pi, false));
}

TEST(FitParameterDecided, NoSigmaLeavesAValueOpenUnlessABoundOrTheSamplesHoldIt) {
  EXPECT_FALSE(ParameterDecided(SlippingThreshold(), 462.3, kNaN, false));
  EXPECT_TRUE(ParameterDecided(SlippingThreshold(), 5000.0, kNaN, true));
  // A delay between two samples moves nothing: flat there by construction, not undecided.
  EXPECT_TRUE(ParameterDecided(Delay(), 3e-4, kNaN, false));
}

TEST(FitParameterDecided, AWiderSigmaNeverDecidesAValueANarrowerOneLeftOpen) {
  for (const EffectParameter& p :
       {SlippingStiffness(), SlippingThreshold(), OffsetY(), Phase(), Eccentricity()}) {
    const double value = p.starts.front() != 0.0 ? p.starts.front() : 1e-6;
    bool open = false;
    for (double sigma = 1e-12; sigma < 1e8; sigma *= 1.5) {
      const bool decided = ParameterDecided(p, value, sigma, false);
      if (open) {
        EXPECT_FALSE(decided) << p.name << " sigma " << sigma;
      }
      open = open || !decided;
    }
    EXPECT_TRUE(open) << p.name << ": some sigma must leave it open";
  }
}

}  // namespace
}  // namespace ambdrop::fit_parameter_decided_test
