// Rig sheets as they come (issue 23 items 4 and 5): a sensor's gain and offset per axis, the
// electromagnet constant k and a linear ball bearing's kb, cb given directly, disabled tables
// that need no numbers, a switchable housing contact. Each key: where it lands, that it gives
// the same physics as the longer way round, and the error when it clashes with the other way.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/ball_bearing.hpp"
#include "scratch_directory.hpp"
#include "test_configs.hpp"

namespace ambdrop::rig_sheet_keys_test {
namespace {

using ::testing::HasSubstr;

const std::string& kRigid = testing::kSmallRigidRotorWithSensor;

using testing::ConfigErrorOf;

// ---- 1. A sensor's gain and offset per axis ---------------------------------------------------

TEST(RigSheetKeys, SensorGainAndOffsetPerAxis) {
  const LoadedConfig loaded = LoadConfigFromString(kRigid + R"(gain = 0.98
offset_m = 2e-6
gain_x = 1.05
offset_y_m = -4e-6
)",
                                                   "test.toml");
  const SensorParams& s = loaded.params.sensors[0];
  EXPECT_EQ(s.AxisGain(0), 1.05);
  EXPECT_EQ(s.AxisGain(1), 0.98);  // the common gain where the axis has none of its own
  EXPECT_EQ(s.AxisOffset_m(0), 2e-6);
  EXPECT_EQ(s.AxisOffset_m(1), -4e-6);
  // In the key registry, physical, with their units; an axis without its own value shows the
  // common one as its default, so that a fit can move that axis alone with --set.
  const ConfigKey* gain_x = FindKey(loaded.keys, "sensor.a.gain_x");
  const ConfigKey* gain_y = FindKey(loaded.keys, "sensor.a.gain_y");
  const ConfigKey* offset_y = FindKey(loaded.keys, "sensor.a.offset_y_m");
  ASSERT_TRUE(gain_x && gain_y && offset_y);
  EXPECT_EQ(gain_x->key_class, KeyClass::kPhysical);
  EXPECT_EQ(gain_x->unit, "");
  EXPECT_TRUE(gain_x->declared);
  EXPECT_FALSE(gain_y->declared);
  EXPECT_EQ(gain_y->value, 0.98);
  EXPECT_EQ(offset_y->unit, "m");
  EXPECT_EQ(offset_y->key_class, KeyClass::kPhysical);
  // --set on one axis moves that axis only.
  const SensorParams moved =
      LoadConfigFromString(kRigid, "test.toml", {"sensor.a.gain_y=1.1"}).params.sensors[0];
  EXPECT_EQ(moved.AxisGain(0), 1.0);
  EXPECT_EQ(moved.AxisGain(1), 1.1);
  // Numbers still checked.
  EXPECT_THAT(ConfigErrorOf(kRigid + "offset_x_m = \"a\"\n"),
              HasSubstr("test.toml:11: key 'sensor.a.offset_x_m': expected"));
}

// ---- 4. Disabled tables need no numbers; given, they are still checked ---------------------

const std::string kElectromagnetAmb = kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
[amb.a.electromagnet]
pole_area_m2 = 1.96e-4
turns = 130
nominal_gap_m = 0.25e-3
bias_current_A = 2.0
)";

TEST(RigSheetKeys, DisabledSaturationNeedsNoFluxDensity) {
  const std::string table = kElectromagnetAmb + "[amb.a.electromagnet.saturation]\n";
  EXPECT_EQ(ConfigErrorOf(table + "enabled = false\n"), "no error");
  EXPECT_THAT(ConfigErrorOf(table + "enabled = false\nflux_density_T = -1.0\n"),
              HasSubstr("key 'amb.a.electromagnet.saturation.flux_density_T': expected a "
                        "positive number"));
  EXPECT_THAT(ConfigErrorOf(table + "enabled = true\n"),
              HasSubstr("missing key 'amb.a.electromagnet.saturation.flux_density_T'"));
}

TEST(RigSheetKeys, DisabledFluxDecayNeedsNoTimeConstant) {
  const std::string table = kElectromagnetAmb + "[amb.a.flux_decay]\n";
  EXPECT_EQ(ConfigErrorOf(table + "enabled = false\n"), "no error");
  EXPECT_THAT(ConfigErrorOf(table + "enabled = false\ntime_constant_s = 0.0\n"),
              HasSubstr("key 'amb.a.flux_decay.time_constant_s': expected a positive number"));
  EXPECT_THAT(ConfigErrorOf(table + "enabled = true\n"),
              HasSubstr("missing key 'amb.a.flux_decay.time_constant_s'"));
}

TEST(RigSheetKeys, DisabledSensorNoiseNeedsNoStdDev) {
  const std::string table = kRigid + "[sensor.a.noise]\n";
  EXPECT_EQ(ConfigErrorOf(table + "enabled = false\n"), "no error");
  EXPECT_THAT(ConfigErrorOf(table + "enabled = false\nstd_dev_m = -1e-6\n"),
              HasSubstr("key 'sensor.a.noise.std_dev_m': expected a non-negative number"));
  EXPECT_THAT(ConfigErrorOf(table + "enabled = true\n"), HasSubstr("missing key 'sensor.a.noise"));
  // The electronics' bandwidth the noise passes: optional (white), never negative.
  EXPECT_EQ(ConfigErrorOf(table + "enabled = true\nstd_dev_m = 1e-7\nbandwidth_Hz = 2000.0\n"),
            "no error");
  EXPECT_THAT(ConfigErrorOf(table + "enabled = true\nstd_dev_m = 1e-7\nbandwidth_Hz = -1.0\n"),
              HasSubstr("key 'sensor.a.noise.bandwidth_Hz': expected a non-negative number"));
}

TEST(RigSheetKeys, DisabledUnbalanceNeedsNoMass) {
  const std::string table = kRigid + "[unbalance.u]\nposition_m = 0.1\n";
  EXPECT_EQ(ConfigErrorOf(table + "enabled = false\n"), "no error");
  EXPECT_THAT(ConfigErrorOf(table + "enabled = false\nmass_kg = -1.0\n"),
              HasSubstr("key 'unbalance.u.mass_kg': expected a non-negative number"));
  EXPECT_THAT(ConfigErrorOf(table + "enabled = true\neccentricity_m = 1e-3\n"),
              HasSubstr("missing key 'unbalance.u.mass_kg'"));
}

TEST(RigSheetKeys, DisabledAmplifierStillChecksItsNumbers) {
  const std::string linear = kRigid + R"(
[controller]
kind = "internal_linear"
[controller.linear]
[[controller.linear.sections]]
kind = "gain"
gain = 1
[controller.amplifier]
enabled = false
)";
  EXPECT_EQ(ConfigErrorOf(linear), "no error");
  EXPECT_THAT(ConfigErrorOf(linear + "bandwidth_Hz = -5.0\n"),
              HasSubstr("key 'controller.amplifier.bandwidth_Hz': expected a positive number"));
}

/// configs/<file> with each (from, to) replaced once, written beside a copy of its base so that
/// `base = ...` resolves, and loaded.
std::string LoadEdited(const testing::ScratchDirectory& dir, const std::string& file,
                       const std::vector<std::pair<std::string, std::string>>& edits,
                       LoadedConfig* out = nullptr) {
  std::ifstream in(testing::ConfigPath(file));
  std::stringstream text;
  text << in.rdbuf();
  std::string config = text.str();
  for (const auto& [from, to] : edits) {
    const std::size_t at = config.find(from);
    if (at == std::string::npos) return "edit not found: " + from;
    config.replace(at, from.size(), to);
  }
  const std::size_t base = config.find("\nbase = \"");
  if (base != std::string::npos) {
    const std::size_t start = base + 9;
    const std::size_t end = config.find('"', start);
    config.replace(start, end - start, testing::ConfigPath(config.substr(start, end - start)));
  }
  const auto path = dir.File("edited.toml");
  std::ofstream(path) << config;
  try {
    LoadedConfig loaded = LoadConfig(path);
    if (out != nullptr) *out = std::move(loaded);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(RigSheetKeys, DisabledBearingSupportNeedsNoNumbers) {
  const testing::ScratchDirectory dir("rig_sheet_keys");
  const std::string full = R"(enabled = false
stiffness_N_per_m = 5.0e8              # Ks (paper)
damping_N_s_per_m = 27900.0            # Cs (paper)
outer_race_mass_kg = 0.12              # assumed: outer ring
)";
  EXPECT_EQ(LoadEdited(dir, "chen_itri_flexible.toml", {{full, "enabled = false\n"}}), "no error");
  EXPECT_THAT(
      LoadEdited(dir, "chen_itri_flexible.toml",
                 {{full, "enabled = false\nouter_race_mass_kg = 0.0\n"}}),
      HasSubstr(
          "key 'tdb.front.ball_bearing_tdb.support.outer_race_mass_kg': expected a positive"));
  EXPECT_THAT(LoadEdited(dir, "chen_itri_flexible.toml", {{full, "enabled = true\n"}}),
              HasSubstr("missing key 'tdb.front.ball_bearing_tdb.support.stiffness_N_per_m'"));
}

TEST(RigSheetKeys, HousingContactSwitchesOffWithoutItsNumbers) {
  const testing::ScratchDirectory dir("rig_sheet_keys");
  const std::string nde =
      R"([tdb.nde.four_dof.housing_contact] # Hunt-Crossley, Eq. (10), outer race / housing
stiffness_N_per_m_n = 5.0e9        # assumed
exponent = 1.0                     # Eq. (10) as printed
damping_s_per_m = 0.2              # assumed
)";
  LoadedConfig loaded;
  ASSERT_EQ(LoadEdited(dir, "jarroux2019_industrial_model2.toml", {}, &loaded), "no error");
  EXPECT_TRUE(loaded.params.tdbs[0].four_dof().housing_contact_enabled);  // the default
  ASSERT_EQ(LoadEdited(dir, "jarroux2019_industrial_model2.toml",
                       {{nde, "[tdb.nde.four_dof.housing_contact]\nenabled = false\n"}}, &loaded),
            "no error");
  for (const TdbParams& tdb : loaded.params.tdbs) {
    EXPECT_EQ(tdb.four_dof().housing_contact_enabled, tdb.name != "nde") << tdb.name;
  }
  EXPECT_THAT(
      LoadEdited(dir, "jarroux2019_industrial_model2.toml",
                 {{nde, "[tdb.nde.four_dof.housing_contact]\nenabled = false\nexponent = 3\n"}}),
      HasSubstr("key 'tdb.nde.four_dof.housing_contact.exponent': expected"));
  EXPECT_THAT(LoadEdited(dir, "jarroux2019_industrial_model2.toml",
                         {{nde, "[tdb.nde.four_dof.housing_contact]\nenabled = true\n"}}),
              HasSubstr("missing key 'tdb.nde.four_dof.housing_contact.stiffness_N_per_m_n'"));
}

// ---- 2. The electromagnet constant k given directly ------------------------------------------

TEST(RigSheetKeys, ElectromagnetConstantGivenDirectlyActsAsItsGeometry) {
  const AmbParams geometry = LoadConfigFromString(kElectromagnetAmb, "test.toml").params.ambs[0];
  const double k = ElectromagnetConstant(geometry.electromagnet);
  // mu0 N^2 A cos(22.5 deg) / 4: about 7.7e-7 N m^2/A^2 for this stator.
  EXPECT_NEAR(k, 1.25663706212e-6 * 130 * 130 * 1.96e-4 * std::cos(0.39269908169872414) / 4, 1e-20);
  const std::string direct_text = kRigid + fmt::format(R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
[amb.a.electromagnet]
constant_N_m2_per_A2 = {:.17g}
nominal_gap_m = 0.25e-3
bias_current_A = 2.0
)",
                                                       k);
  const LoadedConfig direct = LoadConfigFromString(direct_text, "test.toml");
  const AmbParams& amb = direct.params.ambs[0];
  // Same force at every current and gap, so the same linearised gains and feedforward.
  for (const double i : {-1.5, -0.3, 0.0, 0.7, 1.9}) {
    for (const double u : {-0.2e-3, -0.05e-3, 0.0, 0.1e-3, 0.2e-3}) {
      const double f_geometry = ElectromagnetForce(geometry.electromagnet, i, u);
      EXPECT_NEAR(ElectromagnetForce(amb.electromagnet, i, u), f_geometry,
                  1e-14 * std::max(1.0, std::abs(f_geometry)))
          << "i = " << i << " A, u = " << u << " m";
    }
  }
  EXPECT_NEAR(ElectromagnetCurrentGain(amb.electromagnet),
              ElectromagnetCurrentGain(geometry.electromagnet), 1e-12);
  const ConfigKey* key = FindKey(direct.keys, "amb.a.electromagnet.constant_N_m2_per_A2");
  ASSERT_NE(key, nullptr);
  EXPECT_EQ(key->unit, "N m^2/A^2");
  EXPECT_EQ(key->key_class, KeyClass::kPhysical);
  // The geometry config does not offer k as a key of its own (it would clash with the geometry).
  EXPECT_EQ(FindKey(LoadConfigFromString(kElectromagnetAmb, "test.toml").keys,
                    "amb.a.electromagnet.constant_N_m2_per_A2"),
            nullptr);
}

TEST(RigSheetKeys, ElectromagnetConstantExcludesTheGeometry) {
  EXPECT_THAT(ConfigErrorOf(kElectromagnetAmb, {"amb.a.electromagnet.constant_N_m2_per_A2=7.7e-7"}),
              HasSubstr("key 'amb.a.electromagnet.pole_area_m2': expected no pole_area_m2 next to "
                        "constant_N_m2_per_A2"));
  const std::string direct = kRigid + R"(
[amb.a]
position_m = 0.1
law = "electromagnet"
[amb.a.electromagnet]
constant_N_m2_per_A2 = 7.7e-7
nominal_gap_m = 0.25e-3
bias_current_A = 2.0
)";
  EXPECT_EQ(ConfigErrorOf(direct), "no error");
  EXPECT_THAT(ConfigErrorOf(direct + "pole_half_angle_rad = 0.3\n"),
              HasSubstr("test.toml:19: key 'amb.a.electromagnet.pole_half_angle_rad': expected "
                        "no pole_half_angle_rad next to constant_N_m2_per_A2"));
  EXPECT_THAT(ConfigErrorOf(direct, {"amb.a.electromagnet.constant_N_m2_per_A2=-1.0"}),
              HasSubstr("expected a positive number (N m^2/A^2), found -1"));
  // Saturation caps the flux through the pole face: without the face it cannot be evaluated.
  EXPECT_THAT(ConfigErrorOf(direct + "[amb.a.electromagnet.saturation]\nenabled = true\n"
                                     "flux_density_T = 1.2\n"),
              HasSubstr("saturation needs the pole geometry"));
  EXPECT_EQ(ConfigErrorOf(direct + "[amb.a.electromagnet.saturation]\nenabled = false\n"),
            "no error");
}

}  // namespace
}  // namespace ambdrop::rig_sheet_keys_test
