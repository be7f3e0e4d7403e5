// [controller.linear], controller.delay_samples and [controller.amplifier]: values load, and
// each rule's error names file, line, key and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_controller_forms_test {
namespace {

using ::testing::HasSubstr;

const std::string kRigid = testing::kSmallRigidRotor +
                           "[controller]\nkind = \"internal_linear\"\n";  // [controller] on line 9

const std::string kSection = "[[controller.linear.sections]]\n";

using testing::ConfigErrorOf;

TEST(ConfigControllerForms, ValuesLoad) {
  const ControllerParams c = LoadConfigFromString(kRigid + R"(delay_samples = 2
[controller.linear]
discretisation = "zoh"
anti_windup = "back_calculation"
back_calculation_time_s = 0.01
[[controller.linear.sections]]
kind = "pid"
kp = 2.0
ki_per_s = 10.0
[[controller.linear.sections]]
kind = "notch"
frequency_Hz = 900.0
pole_damping = 0.2
discretisation = "tustin"
prewarp_Hz = 900.0
[controller.amplifier]
enabled = true
bandwidth_Hz = 1500.0
slew_rate_A_per_s = 2e4
)",
                                                  "test.toml")
                                 .params.controller;
  EXPECT_EQ(c.form, ControllerForm::kLinear);
  EXPECT_EQ(c.kind, ControllerKind::kInternalPid);
  EXPECT_EQ(c.delay_samples, 2);
  ASSERT_EQ(c.linear.sections.size(), 2u);
  EXPECT_EQ(c.linear.sections[0].discretisation, Discretisation::kZeroOrderHold);
  EXPECT_EQ(c.linear.sections[1].discretisation, Discretisation::kTustin);
  EXPECT_EQ(c.linear.sections[1].prewarp_Hz, 900.0);
  EXPECT_EQ(c.linear.anti_windup, AntiWindup::kBackCalculation);
  EXPECT_TRUE(c.amplifier.enabled);
  EXPECT_EQ(c.amplifier.slew_rate_A_per_s, 2e4);
}

TEST(ConfigControllerForms, DefaultsAreOff) {
  const ControllerParams c =
      LoadConfigFromString(
          kRigid + "[controller.linear]\n" + kSection + "kind = \"gain\"\ngain = 1\n", "test.toml")
          .params.controller;
  EXPECT_EQ(c.delay_samples, 0);
  EXPECT_FALSE(c.amplifier.enabled);
  EXPECT_EQ(c.linear.anti_windup, AntiWindup::kConditional);
  // A disabled amplifier does not ask for its bandwidth.
  EXPECT_EQ(ConfigErrorOf(kRigid + "[controller.linear]\n" + kSection +
                          "kind = \"gain\"\ngain = 1\n[controller.amplifier]\nenabled = false\n"),
            "no error");
}

TEST(ConfigControllerForms, Rules) {
  const std::string linear = kRigid + "[controller.linear]\n";  // on line 11
  EXPECT_THAT(ConfigErrorOf(kRigid), HasSubstr("missing key 'controller.linear'"));
  EXPECT_THAT(ConfigErrorOf(linear),
              HasSubstr("test.toml:11: missing key 'controller.linear.sections'"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"pi\"\n"),
              HasSubstr("test.toml:13: key 'controller.linear.sections[0].kind': expected one of"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"notch\"\nfrequency_Hz = 100\n"),
              HasSubstr("missing key 'controller.linear.sections[0].pole_damping'"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"notch\"\nfrequency_Hz = -1\n"),
              HasSubstr("test.toml:14: key 'controller.linear.sections[0].frequency_Hz': "
                        "expected a positive number"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"gain\"\ngain = 1\nkp = 2\n"),
              HasSubstr("unknown key 'controller.linear.sections[0].kp'"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"pid\"\nkd_s = 1e-3\n"),
              HasSubstr("missing key 'controller.linear.sections[0].derivative_filter_s'"));
  EXPECT_THAT(
      ConfigErrorOf(linear + kSection + "kind = \"pid\"\nkd_s = 1e-3\nderivative_filter_s = 0\n"),
      HasSubstr("test.toml:15: key 'controller.linear.sections[0].derivative_filter_s': "
                "expected a derivative filter > 0 s"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection + "kind = \"gain\"\ngain = 1\nprewarp_Hz = 10000\n"),
              HasSubstr("test.toml:15: key 'controller.linear.sections[0].prewarp_Hz': expected "
                        "a frequency in [0, 10000)"));
  EXPECT_THAT(
      ConfigErrorOf(linear + kSection +
                    "kind = \"s_biquad\"\nnumerator = [1, 0, 0]\ndenominator = [0, 1, 1]\n"),
      HasSubstr("test.toml:14: key 'controller.linear.sections[0].numerator': expected a "
                "numerator of degree <= the denominator's"));
  EXPECT_THAT(ConfigErrorOf(linear + kSection +
                            "kind = \"z_biquad\"\nnumerator = [1, 0]\ndenominator = [1, 0, 0]\n"),
              HasSubstr("test.toml:14: key 'controller.linear.sections[0].numerator': expected 3 "
                        "finite numbers"));
  EXPECT_THAT(
      ConfigErrorOf(linear + kSection +
                    "kind = \"z_biquad\"\nnumerator = [1, 0, 0]\ndenominator = [0, 1, 0]\n"),
      HasSubstr("test.toml:15: key 'controller.linear.sections[0].denominator'"));
  EXPECT_THAT(
      ConfigErrorOf(linear + "anti_windup = \"back_calculation\"\nback_calculation_time_s = 1\n" +
                    kSection + "kind = \"gain\"\ngain = 1\n"),
      HasSubstr("test.toml:12: key 'controller.linear.anti_windup': expected "
                "\"back_calculation\" only with a section that integrates"));
  EXPECT_THAT(ConfigErrorOf(linear + "anti_windup = \"back_calculation\"\n" + kSection +
                            "kind = \"pid\"\nki_per_s = 1\n"),
              HasSubstr("missing key 'controller.linear.back_calculation_time_s'"));
  EXPECT_THAT(ConfigErrorOf(linear + "back_calculation_time_s = 1\n" + kSection +
                            "kind = \"pid\"\nki_per_s = 1\n"),
              HasSubstr("test.toml:12: key 'controller.linear.back_calculation_time_s'"));
  std::string nine = linear;
  for (int i = 0; i < 9; ++i) nine += kSection + "kind = \"gain\"\ngain = 1\n";
  EXPECT_THAT(ConfigErrorOf(nine),
              HasSubstr("key 'controller.linear.sections': expected at most 8"));
  const std::string gain = kSection + "kind = \"gain\"\ngain = 1\n";
  EXPECT_THAT(ConfigErrorOf(kRigid + "delay_samples = 17\n[controller.linear]\n" + gain),
              HasSubstr("test.toml:11: key 'controller.delay_samples': expected an integer in "
                        "[0, 16]"));
  EXPECT_THAT(ConfigErrorOf(linear + gain + "[controller.amplifier]\nenabled = true\n"),
              HasSubstr("missing key 'controller.amplifier.bandwidth_Hz'"));
  EXPECT_THAT(ConfigErrorOf(linear + gain +
                            "[controller.amplifier]\nenabled = true\nbandwidth_Hz = 1500\n"
                            "slew_rate_A_per_s = 0\n"),
              HasSubstr("test.toml:18: key 'controller.amplifier.slew_rate_A_per_s': expected a "
                        "positive number"));
  EXPECT_THAT(
      ConfigErrorOf(linear + gain +
                    "[controller.amplifier]\nenabled = true\nbandwidth_Hz = 1500\norder = 3\n"),
      HasSubstr("test.toml:18: key 'controller.amplifier.order': expected an integer in "
                "[1, 2]"));
  EXPECT_THAT(ConfigErrorOf(linear + gain + "[controller.amplifier]\nbandwith_Hz = 1500\n"),
              HasSubstr("unknown key 'controller.amplifier.bandwith_Hz'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[controller.linear]\nkp = 1\n"),
              HasSubstr("unknown key 'controller.linear.kp'"));
}

TEST(ConfigControllerForms, KindPicksTheForm) {
  // The PID form keeps its own table; a [controller.linear] from a base file is checked, unused.
  const ControllerParams c =
      LoadConfigFromString(
          kRigid + "[controller.linear]\n" + kSection + "kind = \"gain\"\ngain = 1\n", "test.toml",
          {"controller.kind=internal_pid", "controller.pid.kp=1", "controller.pid.ki_per_s=0",
           "controller.pid.kd_s=0", "controller.pid.derivative_filter_s=0"})
          .params.controller;
  EXPECT_EQ(c.form, ControllerForm::kPid);
  EXPECT_EQ(c.pid.kp, 1.0);
}

}  // namespace
}  // namespace ambdrop::config_controller_forms_test
