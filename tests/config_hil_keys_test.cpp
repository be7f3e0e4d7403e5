// Config keys of the HIL issue (AMB force laws, flux decay, sensor errors, the controller) and
// config inheritance through `base`: values land where they should, and each rule's error names
// file, line, key and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_hil_keys_test {
namespace {

using ::testing::HasSubstr;

const std::string& kRigid = testing::kSmallRigidRotorWithSensor;

using testing::ConfigErrorOf;

TEST(ConfigHil, ElectromagnetAmbLoads) {
  const ModelParams p = LoadConfigFromString(kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
current_limit_A = 4.0
[amb.a.electromagnet]
pole_area_m2 = 1.96e-4
turns = 130
nominal_gap_m = 0.25e-3
bias_current_A = 2.0
[amb.a.flux_decay]
enabled = true
time_constant_s = 1e-3
)",
                                             "test.toml")
                            .params;
  ASSERT_EQ(p.ambs.size(), 1u);
  EXPECT_EQ(p.ambs[0].law, AmbForceLaw::kElectromagnet);
  EXPECT_EQ(p.ambs[0].electromagnet.turns, 130.0);
  EXPECT_EQ(p.ambs[0].current_limit_A, 4.0);
  EXPECT_TRUE(p.ambs[0].flux_decay.enabled);
  EXPECT_EQ(p.ambs[0].sensor, "a");  // defaults to the AMB's own name
}

TEST(ConfigHil, ElectromagnetRules) {
  EXPECT_THAT(ConfigErrorOf(kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
current_gain_N_per_A = 3.0
)"),
              HasSubstr("test.toml:15: key 'amb.a.current_gain_N_per_A': expected no "
                        "current_gain_N_per_A with law = \"electromagnet\""));
  EXPECT_THAT(ConfigErrorOf(kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
)"),
              HasSubstr("missing key 'amb.a.electromagnet'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
[amb.a.electromagnet]
pole_area_m2 = 1.96e-4
turns = 130
nominal_gap_m = -0.25e-3
bias_current_A = 2.0
)"),
              HasSubstr("test.toml:18: key 'amb.a.electromagnet.nominal_gap_m': expected a "
                        "positive number (m), found -0.00025"));
  EXPECT_THAT(ConfigErrorOf(kRigid + R"(
[amb.a]
position_m = 0.1
stiffness_N_per_m = 1.0
damping_N_s_per_m = 1.0
[amb.a.flux_decay]
enabled = true
tau = 1e-3
)"),
              HasSubstr("test.toml:18: unknown key 'amb.a.flux_decay.tau' (allowed here: enabled, "
                        "current_law, time_constant_s, slew_rate_A_per_s, hold_time_s, "
                        "bias_current_A)"));
}

TEST(ConfigHil, SensorErrorModels) {
  const ModelParams p = LoadConfigFromString(R"(
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 10.0
polar_inertia_kg_m2 = 0.01
transverse_inertia_kg_m2 = 0.1
centre_of_mass_m = 0.2
[sensor.a]
position_m = 0.1
gain = 0.98
offset_m = 2e-6
quantisation_m = 1e-7
output = "counts"
counts_per_m = 1e7
[sensor.a.noise]
enabled = true
std_dev_m = 1e-7
seed = 5
[sensor.a.lag]
enabled = true
delay_s = 1e-4
cutoff_Hz = 2000.0
)",
                                             "test.toml")
                            .params;
  const SensorParams& s = p.sensors[0];
  EXPECT_EQ(s.gain, 0.98);
  EXPECT_EQ(s.output, SensorOutput::kCounts);
  EXPECT_EQ(s.noise.seed, 5u);
  EXPECT_EQ(s.lag.cutoff_Hz, 2000.0);
  EXPECT_THAT(ConfigErrorOf(kRigid + "output = \"counts\"\n"),
              HasSubstr("missing key 'sensor.a.counts_per_m'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "counts_per_m = 1e7\n"),
              HasSubstr("test.toml:11: key 'sensor.a.counts_per_m': expected no counts_per_m "
                        "with output = \"metres\""));
}

TEST(ConfigHil, ControllerTable) {
  EXPECT_THAT(ConfigErrorOf(kRigid + "[controller]\nkind = \"internal_pid\"\n"),
              HasSubstr("missing key 'controller.pid'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[controller]\nkind = \"external\"\n"),
              HasSubstr("test.toml:12: key 'controller.kind': expected one of \"none\", "
                        "\"internal_pid\", \"internal_linear\", found \"external\""));
  const ModelParams p = LoadConfigFromString(kRigid + R"(
[controller]
kind = "internal_pid"
rate_Hz = 10000.0
[controller.pid]
kp = 2.3
ki_per_s = 10.0
kd_s = 1.4e-3
derivative_filter_s = 7e-5
)",
                                             "test.toml")
                            .params;
  EXPECT_EQ(p.controller.kind, ControllerKind::kInternalPid);
  EXPECT_EQ(p.controller.pid.kd_s, 1.4e-3);
  EXPECT_EQ(p.controller.pid.sensor_gain_V_per_m, 20000.0);  // seed 003's default
}

TEST(ConfigHil, TriggerPartialAndRestore) {
  const ModelParams p =
      LoadConfigFromString(
          kRigid + "[trigger]\ntime_s = 0.1\nrestore_time_s = 0.2\nambs = [\"a\"]\naxes = \"y\"\n",
          "test.toml")
          .params;
  EXPECT_EQ(p.trigger.restore_time_s, 0.2);
  ASSERT_EQ(p.trigger.ambs.size(), 1u);
  EXPECT_FALSE(p.trigger.axis_x);
  EXPECT_TRUE(p.trigger.axis_y);
  EXPECT_THAT(ConfigErrorOf(kRigid + "[trigger]\ntime_s = 0.3\nrestore_time_s = 0.2\n"),
              HasSubstr("test.toml:13: key 'trigger.restore_time_s': expected a number > "
                        "trigger.time_s = 0.3 (s), found 0.2"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[trigger]\naxes = \"z\"\n"),
              HasSubstr("test.toml:12: key 'trigger.axes': expected one of \"xy\", \"x\", \"y\""));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[trigger]\nambs = [1]\n"),
              HasSubstr("test.toml:12: key 'trigger.ambs': expected an array of AMB names"));
}

TEST(ConfigBase, DerivedComponentsReplaceAndSectionsMerge) {
  const std::string dir = std::string(AMBDROP_SOURCE_DIR) + "/tests/data/";
  const ModelParams p = LoadConfigFromString(R"(
base = "base_rig.toml"
[rotor.rigid]
mass_kg = 12.0
[amb.a]
position_m = 0.1
law = "linearised_currents"
current_gain_N_per_A = 100.0
position_gain_N_per_m = 1e5
)",
                                             dir + "derived.toml")
                            .params;
  EXPECT_EQ(p.rotor.rigid.mass_kg, 12.0);          // merged key by key
  EXPECT_EQ(p.rotor.rigid.centre_of_mass_m, 0.2);  // kept from the base
  ASSERT_EQ(p.ambs.size(), 1u);
  EXPECT_EQ(p.ambs[0].law, AmbForceLaw::kLinearisedCurrents);  // replaced whole
  ASSERT_EQ(p.sensors.size(), 2u);
  EXPECT_EQ(p.sensors[1].gain, 1.1);
}

TEST(ConfigBase, ErrorsNameTheFileTheyAreIn) {
  const std::string dir = std::string(AMBDROP_SOURCE_DIR) + "/tests/data/";
  // A config given as text resolves its base from its name's folder: here, none.
  EXPECT_THAT(ConfigErrorOf("base = \"base_rig_bad.toml\"\n" + kRigid),
              HasSubstr("test.toml:1: key 'base': expected a readable config file"));
  try {
    LoadConfigFromString("base = \"base_rig_bad.toml\"\n" + kRigid, dir + "derived.toml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("tests/data/base_rig_bad.toml:3: key 'simulation.step_s': expected a "
                          "positive number (s), found -1"));
  }
  try {
    LoadConfigFromString("base = \"missing.toml\"\n" + kRigid, dir + "derived.toml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("derived.toml:1: key 'base': expected a readable "
                                                 "config file"));
  }
}

}  // namespace
}  // namespace ambdrop::config_hil_keys_test
