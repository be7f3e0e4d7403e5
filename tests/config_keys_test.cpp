// The key registry (io/config_keys.hpp): every number of every rig in configs/ is recorded with
// a `--set` path that reaches exactly that number, a class that keeps solver and measurement keys
// out of a fit, and a default fit range inside what the readers accept.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "io/config_keys.hpp"
#include "io/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

std::map<std::string, ConfigKey> ByPath(const std::vector<ConfigKey>& keys) {
  std::map<std::string, ConfigKey> out;
  for (const ConfigKey& k : keys) out[k.path] = k;
  return out;
}

bool Accepted(const ConfigKey& k, double v) {
  return (k.lower_inclusive ? v >= k.lower : v > k.lower) &&
         (k.upper_inclusive ? v <= k.upper : v < k.upper);
}

TEST(ConfigKeys, ClassesFollowWhatAKeyDescribes) {
  EXPECT_EQ(ClassOfKey("simulation.step_s"), KeyClass::kSolver);
  EXPECT_EQ(ClassOfKey("simulation.output_interval_s"), KeyClass::kSolver);
  EXPECT_EQ(ClassOfKey("controller.rate_Hz"), KeyClass::kSolver);
  EXPECT_EQ(ClassOfKey("sensor.de.noise.std_dev_m"), KeyClass::kMeasurement);
  EXPECT_EQ(ClassOfKey("sensor.de.noise.seed"), KeyClass::kMeasurement);
  EXPECT_EQ(ClassOfKey("measurement.sample_rate_Hz"), KeyClass::kMeasurement);
  EXPECT_EQ(ClassOfKey("trigger.time_s"), KeyClass::kRun);
  EXPECT_EQ(ClassOfKey("simulation.spin_speed_rad_s"), KeyClass::kRun);
  EXPECT_EQ(ClassOfKey("tdb.de.clearance_m"), KeyClass::kPhysical);
  EXPECT_EQ(ClassOfKey("tdb.de.friction.regularisation_s_per_m"), KeyClass::kPhysical);
  EXPECT_EQ(ClassOfKey("sensor.de.lag.delay_s"), KeyClass::kPhysical);
  // A segment, not a substring: a rig may name a sensor "noisemaker".
  EXPECT_EQ(ClassOfKey("sensor.noisemaker.gain"), KeyClass::kPhysical);
  // How finely the ADC reads is the acquisition's, not the machine's.
  EXPECT_EQ(ClassOfKey("sensor.de.quantisation_m"), KeyClass::kMeasurement);
}

// A number of a table switched off is read (and checked) but not used: the fit must not offer
// it as "the declared value is off", as moving it changes nothing.
TEST(ConfigKeys, KeysOfASwitchedOffTableAreNotInForce) {
  const LoadedConfig loaded = LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"));
  const auto keys = ByPath(loaded.keys);
  // [amb.de.flux_decay] enabled = false; [amb.de.electromagnet.saturation] enabled = true.
  ASSERT_TRUE(keys.count("amb.de.flux_decay.time_constant_s"));
  EXPECT_FALSE(keys.at("amb.de.flux_decay.time_constant_s").in_force);
  ASSERT_TRUE(keys.count("amb.de.electromagnet.saturation.flux_density_T"));
  EXPECT_TRUE(keys.at("amb.de.electromagnet.saturation.flux_density_T").in_force);
  EXPECT_TRUE(keys.at("amb.de.electromagnet.bias_current_A").in_force);
  // Switched on from the command line, it is in force.
  const LoadedConfig on = LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"),
                                     {"amb.de.flux_decay.enabled=true"});
  EXPECT_TRUE(ByPath(on.keys).at("amb.de.flux_decay.time_constant_s").in_force);
}

TEST(ConfigKeys, EveryRigRecordsItsNumbersWithUnitsAndClasses) {
  for (const std::string& rig : testing::RigConfigFiles()) {
    SCOPED_TRACE(rig);
    const LoadedConfig loaded = LoadConfig(testing::ConfigPath(rig));
    ASSERT_GT(loaded.keys.size(), 10u);
    std::size_t physical = 0;
    for (const ConfigKey& k : loaded.keys) {
      EXPECT_TRUE(std::isfinite(k.value)) << k.path;
      EXPECT_TRUE(Accepted(k, k.value)) << k.path << " = " << k.value;
      EXPECT_EQ(k.declared, !k.location.empty()) << k.path;
      if (k.path.starts_with("simulation.") && k.path != "simulation.spin_speed_rad_s") {
        EXPECT_EQ(k.key_class, KeyClass::kSolver) << k.path;
      }
      if (k.key_class == KeyClass::kPhysical) ++physical;
    }
    EXPECT_GT(physical, 5u);
    // Keys every rig has, read where the readers read them.
    const auto keys = ByPath(loaded.keys);
    EXPECT_TRUE(keys.count("simulation.step_s")) << "no simulation.step_s";
    EXPECT_EQ(keys.at("simulation.step_s").unit, "s");
  }
}

TEST(ConfigKeys, DefaultFitRangesHoldTheValueInsideTheAcceptedRange) {
  for (const std::string& rig : testing::RigConfigFiles()) {
    SCOPED_TRACE(rig);
    for (const ConfigKey& k : LoadConfig(testing::ConfigPath(rig)).keys) {
      if (k.key_class != KeyClass::kPhysical) continue;
      const FitRange r = DefaultFitRange(k);
      EXPECT_LT(r.lower, r.upper) << k.path;
      EXPECT_TRUE(Accepted(k, r.lower) && Accepted(k, r.upper))
          << k.path << " [" << r.lower << ", " << r.upper << "]";
      EXPECT_TRUE(r.lower <= k.value && k.value <= r.upper) << k.path << " = " << k.value;
    }
  }
}

// The registry's paths are exactly what --set accepts: setting a declared physical key to a
// new value inside its fit range moves that key, and only that key, of everything declared.
TEST(ConfigKeys, EveryDeclaredPhysicalKeyIsReachedByItsSetPath) {
  std::size_t checked = 0;
  for (const std::string& rig : testing::RigConfigFiles()) {
    SCOPED_TRACE(rig);
    const std::string path = testing::ConfigPath(rig);
    const std::vector<ConfigKey> declared = LoadConfig(path).keys;
    for (const ConfigKey& k : declared) {
      if (k.key_class != KeyClass::kPhysical || !k.declared) continue;
      const FitRange r = DefaultFitRange(k);
      double w = 0.5 * (r.lower + r.upper);
      if (w == k.value) w = r.lower + 0.25 * (r.upper - r.lower);
      const std::string set = fmt::format("{}={:.17g}", k.path, w);
      LoadedConfig moved;
      try {
        moved = LoadConfig(path, {set});
      } catch (const ConfigError& e) {
        // Other keys may bound this one (a bore inside its shaft): that is a refusal with a
        // reason, not a lost key. It must name the key it was given.
        EXPECT_NE(std::string(e.what()).find(k.path), std::string::npos) << set << ": " << e.what();
        continue;
      }
      const auto after = ByPath(moved.keys);
      ASSERT_TRUE(after.count(k.path)) << set << ": the key is no longer read";
      EXPECT_EQ(after.at(k.path).value, w) << set;
      for (const ConfigKey& other : declared) {
        if (other.path == k.path || !other.declared) continue;
        ASSERT_TRUE(after.count(other.path)) << set << " lost " << other.path;
        EXPECT_EQ(after.at(other.path).value, other.value) << set << " moved " << other.path;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
}

}  // namespace
}  // namespace ambdrop
