// Config keys of issue 24 items 1-2: amb.NAME.bias_source and the power-loss current laws of
// amb.NAME.flux_decay. Values land where they should, --set reaches them, and each rule's error
// names file, line, key and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_power_loss_test {
namespace {

using ::testing::HasSubstr;

// Lines 1-10; an AMB table appended after it starts at line 11.
const std::string& kRigid = testing::kSmallRigidRotorWithSensor;

// [amb.a] at line 11; a line appended to it is line 16.
const std::string kLinearised = kRigid + R"([amb.a]
position_m = 0.1
law = "linearised_currents"
current_gain_N_per_A = 100.0
position_gain_N_per_m = 2e5
)";

const std::string kElectromagnet = kRigid + R"([amb.a]
position_m = 0.1
law = "electromagnet"
[amb.a.electromagnet]
pole_area_m2 = 1.96e-4
turns = 130
nominal_gap_m = 0.25e-3
bias_current_A = 2.0
)";

ModelParams Load(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return LoadConfigFromString(text, "test.toml", overrides).params;
}

using testing::ConfigErrorOf;

TEST(ConfigPowerLoss, DefaultsAreTheElectromagnetBiasAndTheExponential) {
  const AmbParams a = Load(kLinearised).ambs.at(0);
  EXPECT_EQ(a.bias_source, AmbBiasSource::kElectromagnet);
  EXPECT_FALSE(a.flux_decay.enabled);
  EXPECT_EQ(a.flux_decay.current_law, PowerLossCurrentLaw::kExponential);
}

TEST(ConfigPowerLoss, KeysLandAndSetReachesThem) {
  const AmbParams pm = Load(kLinearised + R"(bias_source = "permanent_magnet"
[amb.a.flux_decay]
enabled = true
current_law = "slew_limited_ramp"
slew_rate_A_per_s = 250.0
)")
                           .ambs.at(0);
  EXPECT_EQ(pm.bias_source, AmbBiasSource::kPermanentMagnet);
  EXPECT_EQ(pm.flux_decay.current_law, PowerLossCurrentLaw::kSlewLimitedRamp);
  EXPECT_EQ(pm.flux_decay.slew_rate_A_per_s, 250.0);

  const AmbParams hold =
      Load(kElectromagnet,
           {"amb.a.bias_source=\"permanent_magnet\"", "amb.a.flux_decay.enabled=true",
            "amb.a.flux_decay.current_law=\"hold_then_exponential\"",
            "amb.a.flux_decay.hold_time_s=2e-3", "amb.a.flux_decay.time_constant_s=1e-3"})
          .ambs.at(0);
  EXPECT_EQ(hold.bias_source, AmbBiasSource::kPermanentMagnet);
  EXPECT_EQ(hold.flux_decay.current_law, PowerLossCurrentLaw::kHoldThenExponential);
  EXPECT_EQ(hold.flux_decay.hold_time_s, 2e-3);
  EXPECT_EQ(hold.flux_decay.time_constant_s, 1e-3);

  const AmbParams ramp =
      Load(kLinearised,
           {"amb.a.flux_decay.enabled=true", "amb.a.flux_decay.current_law=\"slew_limited_ramp\"",
            "amb.a.flux_decay.slew_rate_A_per_s=100", "amb.a.flux_decay.bias_current_A=3"})
          .ambs.at(0);
  EXPECT_EQ(ramp.flux_decay.bias_current_A, 3.0);
  EXPECT_EQ(ramp.flux_decay.slew_rate_A_per_s, 100.0);
}

TEST(ConfigPowerLoss, ADisabledTableDoesNotDemandItsNumbers) {
  for (const std::string law : {"exponential", "slew_limited_ramp", "hold_then_exponential"}) {
    EXPECT_NO_THROW(
        Load(kLinearised + "[amb.a.flux_decay]\nenabled = false\ncurrent_law = \"" + law + "\"\n"))
        << law;
  }
  // ... but still checks the ones it is given.
  EXPECT_THAT(ConfigErrorOf(kLinearised + R"([amb.a.flux_decay]
enabled = false
time_constant_s = -1.0
)"),
              HasSubstr("test.toml:18: key 'amb.a.flux_decay.time_constant_s': expected a "
                        "positive number (s), found -1"));
}

TEST(ConfigPowerLoss, BiasSourceRules) {
  EXPECT_THAT(ConfigErrorOf(kLinearised + "bias_source = \"magnet\"\n"),
              HasSubstr("test.toml:16: key 'amb.a.bias_source': expected one of "
                        "\"electromagnet\", \"permanent_magnet\", found \"magnet\""));
  EXPECT_THAT(ConfigErrorOf(kRigid + R"([amb.a]
position_m = 0.1
stiffness_N_per_m = 1.0
damping_N_s_per_m = 1.0
bias_source = "permanent_magnet"
)"),
              HasSubstr("test.toml:15: key 'amb.a.bias_source': expected no bias_source with "
                        "law = \"equivalent\""));
}

TEST(ConfigPowerLoss, CurrentLawRules) {
  EXPECT_THAT(
      ConfigErrorOf(kLinearised + "[amb.a.flux_decay]\nenabled = true\ncurrent_law = \"ramp\"\n"),
      HasSubstr("test.toml:18: key 'amb.a.flux_decay.current_law': expected one of "
                "\"exponential\", \"slew_limited_ramp\", \"hold_then_exponential\", found "
                "\"ramp\""));
  EXPECT_THAT(ConfigErrorOf(kRigid + R"([amb.a]
position_m = 0.1
stiffness_N_per_m = 1.0
damping_N_s_per_m = 1.0
[amb.a.flux_decay]
enabled = true
current_law = "slew_limited_ramp"
slew_rate_A_per_s = 10.0
)"),
              HasSubstr("test.toml:17: key 'amb.a.flux_decay.current_law': expected "
                        "\"exponential\" or \"hold_then_exponential\" with law = \"equivalent\""));
}

TEST(ConfigPowerLoss, KeysOfAnotherCurrentLawAreRefused) {
  const std::string ramp = kLinearised +
                           "bias_source = \"permanent_magnet\"\n[amb.a.flux_decay]\nenabled = "
                           "true\ncurrent_law = \"slew_limited_ramp\"\nslew_rate_A_per_s = 10.0\n";
  EXPECT_THAT(ConfigErrorOf(ramp + "time_constant_s = 1e-3\n"),
              HasSubstr("test.toml:21: key 'amb.a.flux_decay.time_constant_s': expected no "
                        "time_constant_s with current_law = \"slew_limited_ramp\""));
  EXPECT_THAT(ConfigErrorOf(ramp + "hold_time_s = 1e-3\n"),
              HasSubstr("test.toml:21: key 'amb.a.flux_decay.hold_time_s': expected no "
                        "hold_time_s with current_law = \"slew_limited_ramp\""));
  const std::string exponential =
      kLinearised + "[amb.a.flux_decay]\nenabled = true\ntime_constant_s = 1e-3\n";
  EXPECT_THAT(ConfigErrorOf(exponential + "slew_rate_A_per_s = 10.0\n"),
              HasSubstr("test.toml:19: key 'amb.a.flux_decay.slew_rate_A_per_s': expected no "
                        "slew_rate_A_per_s with current_law = \"exponential\""));
  EXPECT_THAT(ConfigErrorOf(exponential + "hold_time_s = 1e-3\n"),
              HasSubstr("test.toml:19: key 'amb.a.flux_decay.hold_time_s': expected no "
                        "hold_time_s with current_law = \"exponential\""));
  EXPECT_THAT(ConfigErrorOf(exponential + "bias_current_A = 2.0\n"),
              HasSubstr("test.toml:19: key 'amb.a.flux_decay.bias_current_A': expected no "
                        "bias_current_A with current_law = \"exponential\""));
}

// Trying another law from the command line (a user's --set, a fit's candidate) must not need
// the file's numbers of the law it replaces deleted: they are left unused. Given by --set, or
// with the law the file's own, they are still refused.
TEST(ConfigPowerLoss, ALawSwitchedBySetLeavesTheFilesKeysOfTheOldLawUnused) {
  const std::string ramp = kLinearised +
                           "bias_source = \"permanent_magnet\"\n[amb.a.flux_decay]\nenabled = "
                           "true\ncurrent_law = \"slew_limited_ramp\"\nslew_rate_A_per_s = 10.0\n";
  const AmbParams exponential = Load(ramp, {"amb.a.flux_decay.current_law=\"exponential\"",
                                            "amb.a.flux_decay.time_constant_s=4e-3"})
                                    .ambs.at(0);
  EXPECT_EQ(exponential.flux_decay.current_law, PowerLossCurrentLaw::kExponential);
  EXPECT_EQ(exponential.flux_decay.time_constant_s, 4e-3);
  const AmbParams hold =
      Load(ramp, {"amb.a.flux_decay.current_law=\"hold_then_exponential\"",
                  "amb.a.flux_decay.hold_time_s=1e-3", "amb.a.flux_decay.time_constant_s=4e-3"})
          .ambs.at(0);
  EXPECT_EQ(hold.flux_decay.current_law, PowerLossCurrentLaw::kHoldThenExponential);
  EXPECT_EQ(hold.flux_decay.hold_time_s, 1e-3);
  // The old law's key given on the command line too: refused, pointing at it.
  EXPECT_THAT(ConfigErrorOf(ramp, {"amb.a.flux_decay.current_law=\"exponential\"",
                                   "amb.a.flux_decay.time_constant_s=4e-3",
                                   "amb.a.flux_decay.slew_rate_A_per_s=20"}),
              HasSubstr("--set amb.a.flux_decay.slew_rate_A_per_s=20: key "
                        "'amb.a.flux_decay.slew_rate_A_per_s': expected no slew_rate_A_per_s "
                        "with current_law = \"exponential\""));
  // A key of another law set on a file whose law stays: refused.
  EXPECT_THAT(ConfigErrorOf(ramp, {"amb.a.flux_decay.time_constant_s=4e-3"}),
              HasSubstr("key 'amb.a.flux_decay.time_constant_s': expected no time_constant_s "
                        "with current_law = \"slew_limited_ramp\""));
}

TEST(ConfigPowerLoss, NumbersAreRequiredWhenEnabledAndInRange) {
  const std::string ramp = kLinearised +
                           "bias_source = \"permanent_magnet\"\n[amb.a.flux_decay]\n"
                           "enabled = true\ncurrent_law = \"slew_limited_ramp\"\n";
  EXPECT_THAT(ConfigErrorOf(ramp), HasSubstr("missing key 'amb.a.flux_decay.slew_rate_A_per_s'"));
  EXPECT_THAT(ConfigErrorOf(ramp + "slew_rate_A_per_s = 0.0\n"),
              HasSubstr("test.toml:20: key 'amb.a.flux_decay.slew_rate_A_per_s': expected a "
                        "positive number (A/s), found 0"));
  EXPECT_THAT(ConfigErrorOf(ramp + "slew_rate_A_per_s = inf\n"),
              HasSubstr("test.toml:20: key 'amb.a.flux_decay.slew_rate_A_per_s': expected a "
                        "positive number (A/s), found inf"));
  const std::string hold = kLinearised +
                           "[amb.a.flux_decay]\nenabled = true\ncurrent_law = "
                           "\"hold_then_exponential\"\ntime_constant_s = 1e-3\n";
  EXPECT_THAT(ConfigErrorOf(hold), HasSubstr("missing key 'amb.a.flux_decay.hold_time_s'"));
  EXPECT_THAT(ConfigErrorOf(hold + "hold_time_s = -1e-3\n"),
              HasSubstr("test.toml:20: key 'amb.a.flux_decay.hold_time_s': expected a "
                        "non-negative number (s), found -0.001"));
  EXPECT_THAT(ConfigErrorOf(kLinearised + "[amb.a.flux_decay]\nenabled = true\ncurrent_law = "
                                          "\"hold_then_exponential\"\nhold_time_s = 1e-3\n"),
              HasSubstr("missing key 'amb.a.flux_decay.time_constant_s'"));
}

TEST(ConfigPowerLoss, TheRampsBiasCurrentOnlyWhereTheLawLacksOne) {
  const std::string ramp =
      "[amb.a.flux_decay]\nenabled = true\ncurrent_law = \"slew_limited_ramp\"\n"
      "slew_rate_A_per_s = 10.0\n";
  // Linearised law, electromagnet bias: the coils' I0 is needed and must be positive.
  EXPECT_THAT(ConfigErrorOf(kLinearised + ramp),
              HasSubstr("missing key 'amb.a.flux_decay.bias_current_A'"));
  EXPECT_THAT(ConfigErrorOf(kLinearised + ramp + "bias_current_A = -2.0\n"),
              HasSubstr("test.toml:20: key 'amb.a.flux_decay.bias_current_A': expected a "
                        "positive number (A), found -2"));
  // The electromagnet law has its own; a permanent magnet does not ramp.
  EXPECT_THAT(ConfigErrorOf(kElectromagnet + ramp + "bias_current_A = 2.0\n"),
              HasSubstr("key 'amb.a.flux_decay.bias_current_A': expected no bias_current_A "
                        "with law = \"electromagnet\""));
  EXPECT_THAT(ConfigErrorOf(kLinearised + "bias_source = \"permanent_magnet\"\n" + ramp +
                            "bias_current_A = 2.0\n"),
              HasSubstr("test.toml:21: key 'amb.a.flux_decay.bias_current_A': expected no "
                        "bias_current_A with bias_source = \"permanent_magnet\""));
}

}  // namespace
}  // namespace ambdrop::config_power_loss_test
