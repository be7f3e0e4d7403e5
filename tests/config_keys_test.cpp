// The key registry (io/config/config_keys.hpp): every number of every rig in configs/ is recorded
// with a `--set` path that reaches exactly that number, a class that keeps solver and measurement
// keys out of a fit, and a default fit range inside what the readers accept.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "io/config/config_keys.hpp"
#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "io/config/toml_reader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_keys_test {
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

// The unit comes from the key's name: a compound X_per_Y is X/Y ("1/Y" when the name carries no
// numerator unit), and the house's compounds without "per" keep their spelling (rad/s, m/s^2,
// kg/m^3, N m s). One row per unit suffix the readers use.
TEST(ConfigKeys, UnitsFollowTheKeysNamesIncludingCompoundsWithPer) {
  const std::vector<std::pair<std::string, std::string>> kCases = {
      // X_per_Y
      {"sensor_gain_V_per_m", "V/m"},
      {"amplifier_gain_A_per_V", "A/V"},
      {"ki_per_s", "1/s"},
      {"beta_per_m", "1/m"},
      {"lower_hardening_rate_per_m", "1/m"},
      {"stiffness_N_per_m", "N/m"},
      {"quadratic_stiffness_N_per_m2", "N/m^2"},
      {"inner_contact_stiffness_N_per_m1_5", "N/m^1.5"},
      {"stiffness_N_per_m_n", "N/m^n"},
      {"stiffness_N_per_m_e", "N/m^e"},
      {"damping_N_s_per_m", "N s/m"},
      {"damping_x_N_s_per_m", "N s/m"},
      {"damping_s_per_m", "s/m"},
      {"regularisation_s_per_m", "s/m"},
      {"drag_regularisation_s_per_rad", "s/rad"},
      {"current_gain_N_per_A", "N/A"},
      {"slew_rate_A_per_s", "A/s"},
      {"constant_N_m2_per_A2", "N m^2/A^2"},
      {"scale_A_per_count", "A/count"},
      {"scale_m_per_count", "m/count"},
      {"scale_rad_s_per_count", "(rad/s)/count"},
      {"counts_per_m", "count/m"},
      // compounds without "per", and single units
      {"spin_speed_rad_s", "rad/s"},
      {"offset_rad_s", "rad/s"},
      {"stick_speed_m_s", "m/s"},
      {"acceleration_m_s2", "m/s^2"},
      {"density_kg_m3", "kg/m^3"},
      {"inertia_kg_m2", "kg m^2"},
      {"pole_area_m2", "m^2"},
      {"eccentricity_kg_m", "kg m"},
      {"drag_torque_N_m", "N m"},
      {"rotational_damping_N_m_s", "N m s"},
      {"windage_N_m_s2", "N m s^2"},
      {"bitrate_bps", "bit/s"},
      {"youngs_modulus_Pa", "Pa"},
      {"cutoff_Hz", "Hz"},
      {"flux_density_T", "T"},
      {"bias_current_A", "A"},
      {"slipping_threshold_N", "N"},
      {"mass_kg", "kg"},
      {"phase_rad", "rad"},
      {"clearance_m", "m"},
      {"kd_s", "s"},
      // dimensionless
      {"gain", ""},
      {"kp", ""},
      {"palmgren_f1", ""},
      {"exponent", ""},
  };
  for (const auto& [key, unit] : kCases) {
    EXPECT_EQ(KeyUnit(key), unit) << key;
    EXPECT_EQ(config_detail::UnitOfKey(key), unit) << key;
  }
}

// Error messages print the same unit, once.
TEST(ConfigKeys, ErrorsPrintTheCompoundUnitOnce) {
  // The CAN rig: the PID rig with a [can] table.
  const std::string pid = testing::ConfigPath("jarroux2019_industrial_pid_can.toml");
  const auto error_of = [&](const std::string& set) {
    try {
      LoadConfig(pid, {set});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of("controller.pid.sensor_gain_V_per_m=-1"),
              ::testing::HasSubstr("(V/m), found -1"));
  EXPECT_THAT(error_of("controller.pid.amplifier_gain_A_per_V=-1"),
              ::testing::HasSubstr("(A/V), found -1"));
  EXPECT_THAT(error_of("controller.pid.ki_per_s=-1"), ::testing::HasSubstr("(1/s), found -1"));
  // Readers whose own wording named the unit must not print it a second time.
  const std::vector<std::pair<std::string, std::string>> kOnce = {
      {"can.bitrate_bps=0", "(bit/s)"},
      {"can.currents_in.de.x.scale_A_per_count=0", "(A/count)"},
      {"controller.pid.ki_per_s=-1", "(1/s)"}};
  for (const auto& [set, unit] : kOnce) {
    const std::string text = error_of(set);
    const std::size_t first = text.find(unit);
    ASSERT_NE(first, std::string::npos) << text;
    EXPECT_EQ(text.find(unit, first + 1), std::string::npos) << "printed twice: " << text;
  }
}

// Every key of every rig whose name is a compound X_per_Y carries a unit with a "/".
TEST(ConfigKeys, EveryCompoundKeyOfEveryRigHasAQuotientUnit) {
  std::size_t checked = 0;
  for (const std::string& rig : testing::RigConfigFiles()) {
    for (const ConfigKey& k : LoadConfig(testing::ConfigPath(rig)).keys) {
      const std::string last = k.path.substr(k.path.rfind('.') + 1);
      if (last.find("_per_") == std::string::npos) continue;
      EXPECT_NE(k.unit.find('/'), std::string::npos)
          << rig << ": " << k.path << " [" << k.unit << "]";
      ++checked;
    }
  }
  EXPECT_GT(checked, 20u);
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
    const std::vector<ConfigKey> keys = LoadConfig(testing::ConfigPath(rig)).keys;
    for (const ConfigKey& k : keys) {
      if (k.key_class != KeyClass::kPhysical) continue;
      const FitRange r = DefaultFitRange(k, keys);
      EXPECT_LT(r.lower, r.upper) << k.path;
      EXPECT_TRUE(Accepted(k, r.lower) && Accepted(k, r.upper))
          << k.path << " [" << r.lower << ", " << r.upper << "]";
      EXPECT_TRUE(r.lower <= k.value && k.value <= r.upper) << k.path << " = " << k.value;
    }
  }
}

// A station's range does not depend on where the axial origin is, reaches towards its
// neighbours and stops short of them, and takes no more than a tenth of the machine.
TEST(ConfigKeys, AStationsRangeIsBoundedByItsNeighboursWhereverTheOriginIs) {
  const auto station = [](std::string path, double z) {
    ConfigKey k;
    k.path = std::move(path);
    k.value = z;
    k.unit = "m";
    k.key_class = KeyClass::kPhysical;
    return k;
  };
  const auto machine = [&](double origin) {
    return std::vector<ConfigKey>{station("tdb.nde.position_m", origin + 0.10),
                                  station("rotor.discs[0].position_m", origin + 0.30),
                                  station("unbalance.disc.position_m", origin + 0.3005),
                                  station("sensor.de.position_m", origin + 0.32),
                                  station("amb.de.position_m", origin + 0.70),
                                  station("tdb.de.position_m", origin + 1.00)};
  };
  for (const double origin : {0.0, 0.5, -0.2}) {
    SCOPED_TRACE(origin);
    const std::vector<ConfigKey> keys = machine(origin);
    // The disc: 0.2 m to the TDB below (a tenth of the 0.9 m machine caps it at 0.09 m), 0.02 m
    // to the sensor above (nine tenths of it); the unbalance at the disc is the disc's own.
    const FitRange disc = DefaultFitRange(keys[1], keys);
    EXPECT_NEAR(disc.lower - origin, 0.30 - 0.09, 1e-12);
    EXPECT_NEAR(disc.upper - origin, 0.30 + 0.9 * 0.02, 1e-12);
    // The last station: as far out as its gap inwards (0.3 m), capped at 0.09 m.
    const FitRange end = DefaultFitRange(keys[5], keys);
    EXPECT_NEAR(end.lower - origin, 1.00 - 0.09, 1e-12);
    EXPECT_NEAR(end.upper - origin, 1.00 + 0.09, 1e-12);
    for (const ConfigKey& k : keys) {
      const FitRange r = DefaultFitRange(k, keys);
      EXPECT_TRUE(r.lower < k.value && k.value < r.upper) << k.path;
      for (const ConfigKey& other : keys) {
        if (std::abs(other.value - k.value) > 1e-3) {
          EXPECT_FALSE(r.lower <= other.value && other.value <= r.upper)
              << k.path << " reaches " << other.path;
        }
      }
    }
  }
  // A station switched off is nobody's neighbour; a key that is not a station keeps its range.
  std::vector<ConfigKey> keys = machine(0.0);
  keys[3].in_force = false;
  EXPECT_NEAR(DefaultFitRange(keys[1], keys).upper, 0.30 + 0.09, 1e-12);
  ConfigKey clearance = station("tdb.de.clearance_m", 2e-4);
  const FitRange alone = DefaultFitRange(clearance);
  const FitRange among = DefaultFitRange(clearance, keys);
  EXPECT_EQ(alone.lower, among.lower);
  EXPECT_EQ(alone.upper, among.upper);
}

// Integer keys are in the registry too, marked integer with the reader's range, so that a fit
// can offer a controller's computation delay; counts that only decide how finely the model is
// computed (modes, elements) or observed (noise seeds) are not the machine's.
TEST(ConfigKeys, IntegerKeysAreListedWithTheirRangeAndClass) {
  const std::string path = testing::ConfigPath("jarroux2019_industrial_pid.toml");
  const LoadedConfig loaded = LoadConfig(path);
  const ConfigKey* delay = FindKey(loaded.keys, "controller.delay_samples");
  ASSERT_NE(delay, nullptr) << "controller.delay_samples is not in the registry";
  EXPECT_TRUE(delay->integer);
  EXPECT_EQ(delay->key_class, KeyClass::kPhysical);
  EXPECT_FALSE(delay->declared);
  EXPECT_EQ(delay->value, 0.0);
  EXPECT_EQ(delay->lower, 0.0);
  EXPECT_EQ(delay->upper, 16.0);
  EXPECT_EQ(delay->unit, "");
  const ConfigKey* modes = FindKey(loaded.keys, "rotor.modes");
  ASSERT_NE(modes, nullptr);
  EXPECT_TRUE(modes->integer);
  EXPECT_EQ(modes->key_class, KeyClass::kSolver);
  const ConfigKey* seed = FindKey(loaded.keys, "sensor.de.noise.seed");
  ASSERT_NE(seed, nullptr);
  EXPECT_TRUE(seed->integer);
  EXPECT_EQ(seed->key_class, KeyClass::kMeasurement);
  EXPECT_FALSE(FindKey(loaded.keys, "tdb.de.clearance_m")->integer);
  // A fit searches whole numbers of samples, inside the reader's range.
  const FitRange r = DefaultFitRange(*delay);
  EXPECT_EQ(r.lower, std::floor(r.lower));
  EXPECT_EQ(r.upper, std::floor(r.upper));
  EXPECT_TRUE(r.lower <= 0.0 && 0.0 < r.upper && r.upper <= 16.0) << r.lower << ", " << r.upper;

  // An integer override is written without a decimal point, which the integer reader refuses.
  EXPECT_EQ(OverrideInteger(2), "2");
  const LoadedConfig two = LoadConfig(path, {"controller.delay_samples=" + OverrideInteger(2)});
  EXPECT_EQ(two.params.controller.delay_samples, 2);
  const ConfigKey* set = FindKey(two.keys, "controller.delay_samples");
  ASSERT_NE(set, nullptr);
  EXPECT_EQ(set->value, 2.0);
  EXPECT_TRUE(set->declared);
  EXPECT_THROW(LoadConfig(path, {"controller.delay_samples=" + OverrideNumber(2.0)}), ConfigError);
  // OverrideFor picks the form the key takes.
  EXPECT_EQ(OverrideFor(*delay, 3.0), "controller.delay_samples=3");
  EXPECT_EQ(OverrideFor(*FindKey(loaded.keys, "tdb.de.clearance_m"), 2.0),
            "tdb.de.clearance_m=2.0");
}

// Every integer key of every rig, written back with OverrideInteger, reads the same value; a
// neighbouring value is read as given, or refused with a message that names the key's table.
TEST(ConfigKeys, EveryIntegerKeyOfEveryRigRoundTripsThroughSet) {
  std::size_t checked = 0;
  for (const std::string& rig : testing::RigConfigFiles()) {
    SCOPED_TRACE(rig);
    const std::string path = testing::ConfigPath(rig);
    for (const ConfigKey& k : LoadConfig(path).keys) {
      if (!k.integer) continue;
      const auto value = static_cast<std::int64_t>(k.value);
      ASSERT_EQ(static_cast<double>(value), k.value) << k.path;
      const LoadedConfig same = LoadConfig(path, {k.path + "=" + OverrideInteger(value)});
      const ConfigKey* again = FindKey(same.keys, k.path);
      ASSERT_NE(again, nullptr) << k.path;
      EXPECT_EQ(again->value, k.value) << k.path;
      EXPECT_TRUE(again->declared) << k.path;
      EXPECT_TRUE(again->integer) << k.path;
      const std::int64_t other = k.value + 1.0 <= k.upper ? value + 1 : value - 1;
      try {
        const LoadedConfig moved = LoadConfig(path, {k.path + "=" + OverrideInteger(other)});
        EXPECT_EQ(FindKey(moved.keys, k.path)->value, static_cast<double>(other)) << k.path;
      } catch (const ConfigError& e) {
        // Refused for what it does to its neighbours (a CAN signal overlapping another, a
        // second deck without its table): the message names the key's table.
        const std::string table = k.path.substr(0, k.path.rfind('.'));
        EXPECT_NE(std::string(e.what()).find(table), std::string::npos) << e.what();
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 20u);
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
      const FitRange r = DefaultFitRange(k, declared);
      double w = 0.5 * (r.lower + r.upper);
      if (w == k.value) w = r.lower + 0.25 * (r.upper - r.lower);
      // An integer key takes whole numbers (its range's ends are whole).
      if (k.integer) w = std::round(w) != k.value ? std::round(w) : r.upper;
      const std::string set = OverrideFor(k, w);
      LoadedConfig moved;
      try {
        moved = LoadConfig(path, {set});
      } catch (const ConfigError& e) {
        // Other keys may bound this one (a bore inside its shaft): that is a refusal with a
        // reason, not a lost key. It must name the key it was given; a count may change the
        // structure instead (a second deck needs its table), and name that table.
        const std::string named = k.integer ? k.path.substr(0, k.path.rfind('.')) : k.path;
        EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << set << ": " << e.what();
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
}  // namespace ambdrop::config_keys_test
