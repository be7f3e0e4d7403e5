// The [scenario] table: read as written, and every mistake a clear ConfigError naming the file,
// line and key.
#include <gtest/gtest.h>

#include <string>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_scenario_test {
namespace {

std::string Rig() {
  return "base = \"" + testing::ConfigPath("jarroux2019_industrial_pid.toml") +
         "\"\n[trigger]\nenabled = false\n";
}

std::string ErrorOf(const std::string& text) {
  try {
    LoadConfigFromString(text, "scenario.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigScenario, ReadsEventsAndExpectations) {
  const LoadedConfig c = LoadConfigFromString(Rig() + R"(
[scenario]
description = "dip"
silence_action = "zero"
[[scenario.event]]
kind = "power_fail"
time_s = 0.05
amb = "de"
axis = "y"
[[scenario.event]]
kind = "sensor_dropout"
time_s = 0.1
duration_s = 0.01
sensor = "nde"
value_m = -1e-4
[scenario.expect]
contact_at = ["de"]
relevitated = true
)",
                                              "scenario.toml");
  ASSERT_TRUE(c.scenario.has_value());
  const ScenarioParams& s = *c.scenario;
  EXPECT_EQ(s.silence_action, "zero");
  ASSERT_EQ(s.events.size(), 2U);
  EXPECT_EQ(s.events[0].kind, ScenarioEventKind::kPowerFail);
  EXPECT_EQ(c.params.ambs[s.events[0].amb].name, "de");
  EXPECT_EQ(s.events[0].axis, 1);
  EXPECT_EQ(s.events[1].kind, ScenarioEventKind::kSensorDropout);
  EXPECT_EQ(c.params.sensors[s.events[1].sensor].name, "nde");
  EXPECT_EQ(s.events[1].value_m, -1e-4);
  EXPECT_EQ(s.events[1].axis, -1);
  EXPECT_EQ(s.expect.contact_at, std::vector<std::string>{"de"});
  EXPECT_EQ(s.expect.relevitated, true);
  EXPECT_FALSE(s.expect.status.has_value());
}

TEST(ConfigScenario, MistakesNameFileLineAndKey) {
  struct Case {
    const char* text;
    const char* expected;  // a piece of the message
  };
  const Case cases[] = {
      {"[scenario]\n[[scenario.event]]\nkind = \"meteor\"\ntime_s = 1.0\n",
       "scenario.toml:6: key 'scenario.event[0].kind'"},
      {"[scenario]\n[[scenario.event]]\nkind = \"power_fail\"\ntime_s = 0.1\namb = \"middle\"\n",
       "the name of one of the rig's AMBs (\"de\", \"nde\")"},
      {"[scenario]\n[[scenario.event]]\nkind = \"stuck_current\"\ntime_s = 0.1\n",
       "scenario.event[0].duration_s"},
      {"[scenario]\n[[scenario.event]]\nkind = \"power_fail\"\ntime_s = 0.1\nduration_s = 1.0\n",
       "no duration for power_fail"},
      {"[scenario]\n[scenario.expect]\ncontact_at = [\"middle\"]\n", "the rig's TDB names"},
      {"[scenario]\n[scenario.expect]\nlevitated = true\n", "scenario.expect.levitated"},
      {"[scenario]\n[[scenario.event]]\nkind = \"sensor_dropout\"\ntime_s = 0.1\n"
       "duration_s = 0.1\namb = \"de\"\n",
       "no AMB for sensor_dropout"},
  };
  for (const Case& c : cases) {
    const std::string message = ErrorOf(Rig() + c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "for:\n"
                                                           << c.text << "\ngot: " << message;
  }
}

TEST(ConfigScenario, PowerEventsNeedTheRigsTriggerOff) {
  const std::string text = "base = \"" + testing::ConfigPath("jarroux2019_industrial_pid.toml") +
                           "\"\n[scenario]\n[[scenario.event]]\nkind = \"power_fail\"\n"
                           "time_s = 0.1\n";
  EXPECT_NE(ErrorOf(text).find("trigger.enabled = false"), std::string::npos) << ErrorOf(text);
}

}  // namespace
}  // namespace ambdrop::config_scenario_test
