#include "io/config/config_loader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "scratch_directory.hpp"

namespace ambdrop::config_loader_test {
namespace {

using ::testing::HasSubstr;

constexpr char kSource[] = "test.toml";

/// The smallest valid flexible config: one 0.5 m steel section, everything else defaulted.
constexpr std::string_view kMinimalFlexible = R"(name = "minimal flexible"
[rotor]
model = "flexible"
[rotor.materials.steel]
youngs_modulus_Pa = 211e9
shear_modulus_Pa = 81.2e9
density_kg_m3 = 7810
[[rotor.sections]]
length_m = 0.5
outer_diameter_m = 0.05
material = "steel"
)";

constexpr std::string_view kMinimalRigid = R"(name = "minimal rigid"
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 12.5
polar_inertia_kg_m2 = 0.02
transverse_inertia_kg_m2 = 0.3
centre_of_mass_m = 0.24
)";

/// Every table of the schema, each key on its own line so a test can change one line. The shaft
/// is 0.2 m + 0.3 m = 0.5 m long.
constexpr std::string_view kFullFlexible = R"(name = "full flexible"

[simulation]
step_s = 1e-5
duration_s = 0.5
output_interval_s = 1e-4
spin_speed_rad_s = 1000
initial_position = "centred"
max_excursion_over_clearance = 20

[gravity]
enabled = false
acceleration_m_s2 = 9.8

[trigger]
enabled = true
time_s = 0.1

[rotor]
model = "flexible"
modes = 10
modal_damping_ratio = 0.01

[rotor.materials.steel]
youngs_modulus_Pa = 211e9
shear_modulus_Pa = 81.2e9
density_kg_m3 = 7800

[rotor.materials.titanium]
youngs_modulus_Pa = 110e9
shear_modulus_Pa = 44e9
density_kg_m3 = 4500

[[rotor.sections]]
length_m = 0.2
outer_diameter_m = 0.04
material = "steel"
elements = 4

[[rotor.sections]]
length_m = 0.3
outer_diameter_m = 0.06
inner_diameter_m = 0.02
material = "titanium"

[[rotor.discs]]
name = "impeller"
position_m = 0.25
mass_kg = 3.5
polar_inertia_kg_m2 = 0.01
transverse_inertia_kg_m2 = 0.006

[[rotor.discs]]
position_m = 0.4
outer_diameter_m = 0.2
inner_diameter_m = 0.06
thickness_m = 0.03
material = "steel"

[bearing.coupling]
position_m = 0.0
stiffness_N_per_m = 1e5
damping_x_N_s_per_m = 10
damping_y_N_s_per_m = 20

[amb.nde]
position_m = 0.45
stiffness_N_per_m = 2e6
damping_N_s_per_m = 800
gravity_compensation = false

[amb.de]
position_m = 0.1
law = "linearised_currents"
current_gain_N_per_A = 150
position_gain_N_per_m = 4e5
current_profile = [[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]]

[sensor.s1]
position_m = 0.12

[tdb.de]
position_m = 0.05
journal_radius_m = 0.02
clearance_m = 2e-4
model = "contact_law"

[tdb.de.contact_law]
bearing_stiffness_N_per_m = 1e8
bearing_damping_N_s_per_m = 100
ribbon_stiffness_N_per_m = 5e6
ribbon_damping_N_s_per_m = 50
ribbon_crushing_m = 1e-4

[tdb.de.friction]
law = "regularised_coulomb"
coefficient = 0.3
regularisation_s_per_m = 50
whirl_damping_N_s_per_m = 5

[tdb.de.spin]
enabled = false
inertia_kg_m2 = 1e-3
rotational_damping_N_m_s = 1e-4
palmgren_f1 = 0.001
pitch_diameter_m = 0.05
drag_torque_N_m = 0.01

[tdb.de.misalignment]
enabled = true
x_m = 1e-5
y_m = -2e-5

[unbalance.u1]
position_m = 0.26
mass_kg = 0.001
eccentricity_m = 0.1
phase_rad = 1.5
)";

/// `text` with its only occurrence of `from` replaced by `to`.
std::string Replace(std::string_view text, std::string_view from, std::string_view to) {
  std::string out(text);
  const auto pos = out.find(from);
  EXPECT_NE(pos, std::string::npos) << "not in the config: " << from;
  EXPECT_EQ(out.find(from, pos + 1), std::string::npos) << "ambiguous: " << from;
  if (pos != std::string::npos) out.replace(pos, from.size(), to);
  return out;
}

std::string Full(std::string_view from, std::string_view to) {
  return Replace(kFullFlexible, from, to);
}

/// The 1-based line on which `marker` starts.
int LineOf(const std::string& text, std::string_view marker) {
  const auto pos = text.find(marker);
  EXPECT_NE(pos, std::string::npos) << "marker not in the config: " << marker;
  if (pos == std::string::npos) return -1;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

/// `count` copies of `pattern`, each with '#' replaced by the copy's index.
std::string Repeat(std::string_view pattern, int count) {
  std::string out;
  for (int i = 0; i < count; ++i) {
    for (const char c : pattern) {
      if (c == '#') {
        out += std::to_string(i);
      } else {
        out += c;
      }
    }
  }
  return out;
}

std::string ErrorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    LoadConfigFromString(text, kSource, overrides);
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "loaded without a ConfigError";
  return {};
}

// ---------------------------------------------------------------------------------------------
// Valid configs

TEST(ConfigLoader, MinimalFlexibleTakesDefaults) {
  const LoadedConfig loaded = LoadConfigFromString(std::string(kMinimalFlexible), kSource);
  const ModelParams& params = loaded.params;
  EXPECT_EQ(params.name, "minimal flexible");
  EXPECT_EQ(loaded.source_path, kSource);
  EXPECT_EQ(loaded.source_text, kMinimalFlexible);
  EXPECT_EQ(params.rotor.kind, RotorKind::kFlexible);
  ASSERT_EQ(params.rotor.sections.size(), 1u);
  const ShaftSection& section = params.rotor.sections[0];
  EXPECT_DOUBLE_EQ(section.length_m, 0.5);
  EXPECT_DOUBLE_EQ(section.outer_diameter_m, 0.05);
  EXPECT_DOUBLE_EQ(section.inner_diameter_m, 0.0);
  EXPECT_DOUBLE_EQ(section.material.youngs_modulus_Pa, 211e9);
  EXPECT_DOUBLE_EQ(section.material.shear_modulus_Pa, 81.2e9);
  EXPECT_DOUBLE_EQ(section.material.density_kg_m3, 7810.0);
  EXPECT_EQ(section.elements, 1);
  EXPECT_EQ(params.rotor.modes, 12);
  EXPECT_DOUBLE_EQ(params.rotor.modal_damping_ratio, 0.005);
  EXPECT_TRUE(params.rotor.discs.empty());
  EXPECT_TRUE(params.tdbs.empty());
  EXPECT_TRUE(params.ambs.empty());
  EXPECT_DOUBLE_EQ(params.simulation.step_s, 5e-6);
  EXPECT_DOUBLE_EQ(params.simulation.duration_s, 1.0);
  EXPECT_DOUBLE_EQ(params.simulation.output_interval_s, 5e-5);
  EXPECT_EQ(params.simulation.initial_position, InitialPosition::kEquilibrium);
  EXPECT_DOUBLE_EQ(params.simulation.max_excursion_over_clearance, 50.0);
  EXPECT_TRUE(params.gravity.enabled);
  EXPECT_DOUBLE_EQ(params.gravity.acceleration_m_s2, 9.81);
  EXPECT_TRUE(params.trigger.enabled);
  EXPECT_DOUBLE_EQ(params.trigger.time_s, 0.2);
}

TEST(ConfigLoader, MinimalRigid) {
  const ModelParams params = LoadConfigFromString(std::string(kMinimalRigid), kSource).params;
  EXPECT_EQ(params.name, "minimal rigid");
  EXPECT_EQ(params.rotor.kind, RotorKind::kRigid);
  EXPECT_DOUBLE_EQ(params.rotor.rigid.mass_kg, 12.5);
  EXPECT_DOUBLE_EQ(params.rotor.rigid.polar_inertia_kg_m2, 0.02);
  EXPECT_DOUBLE_EQ(params.rotor.rigid.transverse_inertia_kg_m2, 0.3);
  EXPECT_DOUBLE_EQ(params.rotor.rigid.centre_of_mass_m, 0.24);
  EXPECT_TRUE(params.rotor.sections.empty());
}

TEST(ConfigLoader, RigidRotorComponentsMayLieAnywhere) {
  // Appended, not std::string + literal: GCC 12 at -O3 warns falsely on that (PR 105651).
  std::string text(kMinimalRigid);
  text += "[sensor.far]\nposition_m = -3\n";
  const ModelParams params = LoadConfigFromString(text, kSource).params;
  ASSERT_EQ(params.sensors.size(), 1u);
  EXPECT_DOUBLE_EQ(params.sensors[0].position_m, -3.0);
}

TEST(ConfigLoader, FullFlexibleReadsEveryTable) {
  const ModelParams params = LoadConfigFromString(std::string(kFullFlexible), kSource).params;

  EXPECT_DOUBLE_EQ(params.simulation.step_s, 1e-5);
  EXPECT_DOUBLE_EQ(params.simulation.output_interval_s, 1e-4);
  EXPECT_DOUBLE_EQ(params.simulation.spin_speed_rad_s, 1000.0);  // an integer in the file
  EXPECT_EQ(params.simulation.initial_position, InitialPosition::kCentred);
  EXPECT_DOUBLE_EQ(params.simulation.max_excursion_over_clearance, 20.0);
  EXPECT_FALSE(params.gravity.enabled);
  EXPECT_DOUBLE_EQ(params.gravity.acceleration_m_s2, 9.8);
  EXPECT_DOUBLE_EQ(params.trigger.time_s, 0.1);

  EXPECT_EQ(params.rotor.modes, 10);
  EXPECT_DOUBLE_EQ(params.rotor.modal_damping_ratio, 0.01);
  ASSERT_EQ(params.rotor.sections.size(), 2u);
  EXPECT_EQ(params.rotor.sections[0].elements, 4);
  EXPECT_DOUBLE_EQ(params.rotor.sections[1].inner_diameter_m, 0.02);
  EXPECT_DOUBLE_EQ(params.rotor.sections[1].material.density_kg_m3, 4500.0);
  EXPECT_DOUBLE_EQ(params.rotor.sections[1].material.shear_modulus_Pa, 44e9);

  ASSERT_EQ(params.rotor.discs.size(), 2u);
  const Disc& impeller = params.rotor.discs[0];
  EXPECT_EQ(impeller.name, "impeller");
  EXPECT_DOUBLE_EQ(impeller.position_m, 0.25);
  EXPECT_DOUBLE_EQ(impeller.mass_kg, 3.5);
  EXPECT_DOUBLE_EQ(impeller.polar_inertia_kg_m2, 0.01);
  EXPECT_DOUBLE_EQ(impeller.transverse_inertia_kg_m2, 0.006);
  // Steel ring D = 0.2, d = 0.06, h = 0.03: m = 7800 pi/4 (0.04 - 0.0036) 0.03 = 6.68971 kg,
  // Ip = m/8 (0.0436) = 0.0364589, Id = m/16 (0.0436) + m 0.0009/12 = m 0.0028 = 0.0187312.
  const Disc& ring = params.rotor.discs[1];
  EXPECT_EQ(ring.name, "disc1");
  EXPECT_DOUBLE_EQ(ring.position_m, 0.4);
  EXPECT_NEAR(ring.mass_kg, 6.689707396554107, 1e-12);
  EXPECT_NEAR(ring.polar_inertia_kg_m2, 0.03645890531121989, 1e-14);
  EXPECT_NEAR(ring.transverse_inertia_kg_m2, 0.018731180710351503, 1e-14);

  ASSERT_EQ(params.bearings.size(), 1u);
  EXPECT_EQ(params.bearings[0].name, "coupling");
  EXPECT_DOUBLE_EQ(params.bearings[0].stiffness_x_N_per_m, 1e5);
  EXPECT_DOUBLE_EQ(params.bearings[0].stiffness_y_N_per_m, 1e5);
  EXPECT_DOUBLE_EQ(params.bearings[0].damping_x_N_s_per_m, 10.0);
  EXPECT_DOUBLE_EQ(params.bearings[0].damping_y_N_s_per_m, 20.0);

  ASSERT_EQ(params.ambs.size(), 2u);  // sorted by name
  const AmbParams& de = params.ambs[0];
  EXPECT_EQ(de.name, "de");
  EXPECT_EQ(de.law, AmbForceLaw::kLinearisedCurrents);
  EXPECT_DOUBLE_EQ(de.current_gain_N_per_A, 150.0);
  EXPECT_DOUBLE_EQ(de.position_gain_N_per_m, 4e5);
  ASSERT_EQ(de.current_profile.size(), 2u);
  EXPECT_DOUBLE_EQ(de.current_profile[1].time_s, 0.1);
  EXPECT_DOUBLE_EQ(de.current_profile[1].current_x_A, 0.5);
  EXPECT_DOUBLE_EQ(de.current_profile[1].current_y_A, 0.25);
  const AmbParams& nde = params.ambs[1];
  EXPECT_EQ(nde.name, "nde");
  EXPECT_EQ(nde.law, AmbForceLaw::kEquivalent);
  EXPECT_DOUBLE_EQ(nde.position_m, 0.45);
  EXPECT_DOUBLE_EQ(nde.stiffness_N_per_m, 2e6);
  EXPECT_DOUBLE_EQ(nde.damping_N_s_per_m, 800.0);
  EXPECT_FALSE(nde.gravity_compensation);

  ASSERT_EQ(params.sensors.size(), 1u);
  EXPECT_EQ(params.sensors[0].name, "s1");
  EXPECT_DOUBLE_EQ(params.sensors[0].position_m, 0.12);

  ASSERT_EQ(params.tdbs.size(), 1u);
  const TdbParams& tdb = params.tdbs[0];
  EXPECT_EQ(tdb.name, "de");
  EXPECT_DOUBLE_EQ(tdb.clearance_m, 2e-4);
  EXPECT_DOUBLE_EQ(tdb.journal_radius_m, 0.02);
  EXPECT_EQ(tdb.model(), TdbModelKind::kContactLaw);
  EXPECT_DOUBLE_EQ(tdb.contact_law().bearing_stiffness_N_per_m, 1e8);
  EXPECT_DOUBLE_EQ(tdb.contact_law().ribbon_crushing_m, 1e-4);
  EXPECT_EQ(tdb.friction.law, FrictionLaw::kRegularisedCoulomb);
  EXPECT_DOUBLE_EQ(tdb.friction.coefficient, 0.3);
  EXPECT_DOUBLE_EQ(tdb.friction.whirl_damping_N_s_per_m, 5.0);
  EXPECT_FALSE(tdb.spin.enabled);
  EXPECT_DOUBLE_EQ(tdb.spin.inertia_kg_m2, 1e-3);
  EXPECT_DOUBLE_EQ(tdb.spin.drag_torque_N_m, 0.01);
  EXPECT_TRUE(tdb.misalignment.enabled);
  EXPECT_DOUBLE_EQ(tdb.misalignment.y_m, -2e-5);

  ASSERT_EQ(params.unbalances.size(), 1u);
  EXPECT_EQ(params.unbalances[0].name, "u1");
  EXPECT_TRUE(params.unbalances[0].enabled);
  EXPECT_DOUBLE_EQ(params.unbalances[0].eccentricity_m, 0.1);
  EXPECT_DOUBLE_EQ(params.unbalances[0].phase_rad, 1.5);
}

TEST(ConfigLoader, OmittedTdbSubtablesTakeStructDefaults) {
  const std::string text = std::string(kMinimalFlexible) + R"(
[tdb.a]
position_m = 0.5
journal_radius_m = 0.02
clearance_m = 2e-4
[tdb.a.contact_law]
bearing_stiffness_N_per_m = 1e8
bearing_damping_N_s_per_m = 0
ribbon_stiffness_N_per_m = 5e6
ribbon_damping_N_s_per_m = 0
ribbon_crushing_m = 0
)";
  const TdbParams tdb = LoadConfigFromString(text, kSource).params.tdbs.at(0);
  EXPECT_DOUBLE_EQ(tdb.position_m, 0.5);  // the shaft end is on the shaft
  EXPECT_EQ(tdb.friction.law, FrictionParams{}.law);
  EXPECT_DOUBLE_EQ(tdb.friction.coefficient, FrictionParams{}.coefficient);
  EXPECT_DOUBLE_EQ(tdb.spin.inertia_kg_m2, TdbSpinParams{}.inertia_kg_m2);
  EXPECT_FALSE(tdb.misalignment.enabled);
}

TEST(ConfigLoader, ShaftEndToleratesRoundingOfSectionLengths) {
  // 0.7 + 0.1 is 0.7999999999999999 in binary floating point.
  const std::string text = Replace(kMinimalFlexible, "length_m = 0.5", "length_m = 0.7") +
                           "[[rotor.sections]]\nlength_m = 0.1\nouter_diameter_m = 0.05\n"
                           "material = \"steel\"\n[sensor.end]\nposition_m = 0.8\n";
  const ModelParams params = LoadConfigFromString(text, kSource).params;
  EXPECT_LE(params.sensors.at(0).position_m, 0.7 + 0.1);
  EXPECT_NEAR(params.sensors.at(0).position_m, 0.8, 1e-12);
}

TEST(ConfigLoader, LoadsFromFile) {
  const testing::ScratchDirectory dir("ambdrop_config_loader");
  const auto path = dir.File("config.toml");
  {
    std::ofstream file(path);
    file << kMinimalRigid;
  }
  const LoadedConfig loaded = LoadConfig(path, {"rotor.rigid.mass_kg=20"});
  EXPECT_EQ(loaded.source_path, path.string());
  EXPECT_EQ(loaded.source_text, kMinimalRigid);
  EXPECT_DOUBLE_EQ(loaded.params.rotor.rigid.mass_kg, 20.0);
}

TEST(ConfigLoader, MissingFileNamesThePath) {
  try {
    LoadConfig("/nonexistent/ambdrop.toml");
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("/nonexistent/ambdrop.toml"));
  }
}

// ---------------------------------------------------------------------------------------------
// Overrides

TEST(ConfigOverrides, ChangeExistingValues) {
  const ModelParams params =
      LoadConfigFromString(std::string(kFullFlexible), kSource,
                           {"tdb.de.friction.coefficient=0.5", "rotor.sections[0].length_m = 0.25",
                            "gravity.enabled=true", "amb.de.current_profile[1]=[0.2, 3, 4]"})
          .params;
  EXPECT_DOUBLE_EQ(params.tdbs.at(0).friction.coefficient, 0.5);
  EXPECT_DOUBLE_EQ(params.rotor.sections.at(0).length_m, 0.25);
  EXPECT_TRUE(params.gravity.enabled);
  EXPECT_DOUBLE_EQ(params.ambs.at(0).current_profile.at(1).time_s, 0.2);
  EXPECT_DOUBLE_EQ(params.ambs.at(0).current_profile.at(1).current_y_A, 4.0);
}

TEST(ConfigOverrides, BareWordIsAString) {
  const ModelParams params =
      LoadConfigFromString(std::string(kFullFlexible), kSource,
                           {"simulation.initial_position=equilibrium", "name=renamed run"})
          .params;
  EXPECT_EQ(params.simulation.initial_position, InitialPosition::kEquilibrium);
  EXPECT_EQ(params.name, "renamed run");
}

TEST(ConfigOverrides, CreateMissingTablesAndKeys) {
  const ModelParams params =
      LoadConfigFromString(
          std::string(kMinimalFlexible), kSource,
          {"simulation.duration_s=2", "sensor.probe.position_m=0.3",
           "rotor.discs[0].position_m=0.1", "rotor.discs[0].mass_kg=1",
           "rotor.discs[0].polar_inertia_kg_m2=0.1", "rotor.discs[0].transverse_inertia_kg_m2=0.2"})
          .params;
  EXPECT_DOUBLE_EQ(params.simulation.duration_s, 2.0);
  ASSERT_EQ(params.sensors.size(), 1u);
  EXPECT_EQ(params.sensors[0].name, "probe");
  EXPECT_DOUBLE_EQ(params.sensors[0].position_m, 0.3);
  ASSERT_EQ(params.rotor.discs.size(), 1u);
  EXPECT_DOUBLE_EQ(params.rotor.discs[0].transverse_inertia_kg_m2, 0.2);
}

TEST(ConfigOverrides, LaterOverrideWins) {
  const ModelParams params = LoadConfigFromString(std::string(kMinimalFlexible), kSource,
                                                  {"trigger.time_s=0.3", "trigger.time_s=0.4"})
                                 .params;
  EXPECT_DOUBLE_EQ(params.trigger.time_s, 0.4);
}

TEST(ConfigOverrides, EffectiveTomlReloadsToTheSameParams) {
  const LoadedConfig loaded = LoadConfigFromString(
      std::string(kFullFlexible), kSource, {"tdb.de.clearance_m=3e-4", "sensor.s9.position_m=0.2"});
  EXPECT_THAT(loaded.effective_toml, HasSubstr("[sensor.s9]"));
  EXPECT_EQ(loaded.source_text, kFullFlexible);
  const ModelParams reloaded = LoadConfigFromString(loaded.effective_toml, "effective.toml").params;
  EXPECT_DOUBLE_EQ(reloaded.tdbs.at(0).clearance_m, 3e-4);
  EXPECT_EQ(reloaded.sensors.size(), 2u);
  EXPECT_DOUBLE_EQ(reloaded.rotor.discs.at(1).mass_kg, loaded.params.rotor.discs.at(1).mass_kg);
}

TEST(ConfigOverrides, MisspeltKeyIsAnUnknownKeyAtTheOverride) {
  const std::string message =
      ErrorOf(std::string(kFullFlexible), {"tdb.de.friction.coeficient=0.3"});
  EXPECT_THAT(message, HasSubstr("--set tdb.de.friction.coeficient=0.3: unknown key "
                                 "'tdb.de.friction.coeficient' (allowed here: law, coefficient"));
}

TEST(ConfigOverrides, MisspeltTableIsAnUnknownKeyAtTheOverride) {
  const std::string message = ErrorOf(std::string(kFullFlexible), {"tdb.de.fricton.law=none"});
  EXPECT_THAT(message,
              HasSubstr("--set tdb.de.fricton.law=none: unknown key 'tdb.de.fricton' (allowed"));
}

TEST(ConfigOverrides, BadValueIsReportedAtTheOverride) {
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"tdb.de.clearance_m=-1"}),
              HasSubstr("--set tdb.de.clearance_m=-1: key 'tdb.de.clearance_m': expected a "
                        "positive number (m), found -1"));
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"simulation.step_s=fast"}),
              HasSubstr("--set simulation.step_s=fast: key 'simulation.step_s': expected a "
                        "positive number (s), found \"fast\""));
}

TEST(ConfigOverrides, MissingKeyInCreatedTableIsReportedAtTheOverride) {
  EXPECT_THAT(ErrorOf(std::string(kMinimalFlexible), {"tdb.new.position_m=0.1"}),
              HasSubstr("--set tdb.new.position_m=0.1: missing key 'tdb.new.journal_radius_m': "
                        "expected a positive number (m)"));
}

TEST(ConfigOverrides, MalformedOverridesAreErrors) {
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"simulation.step_s"}),
              HasSubstr("--set simulation.step_s: expected dotted.path=value"));
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"simulation..step_s=1"}),
              HasSubstr("--set simulation..step_s=1: expected a dotted key path"));
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"rotor.sections[5].length_m=1"}),
              HasSubstr("--set rotor.sections[5].length_m=1: key 'rotor.sections[5]': expected "
                        "an index in [0, 2]"));
  EXPECT_THAT(ErrorOf(std::string(kFullFlexible), {"rotor.model.kind=1"}),
              HasSubstr("--set rotor.model.kind=1: key 'rotor.model': expected a table, found "
                        "\"flexible\""));
}

// ---------------------------------------------------------------------------------------------
// One case per validation rule: the message must name the file and line, the key and what was
// expected.

struct RuleCase {
  std::string name;
  std::string toml;
  std::string line_marker;  ///< text that starts on the line the error must point at
  std::string key;          ///< the dotted key in the message, quoted
  std::string expected;     ///< text that must follow the key, e.g. "expected a positive number"
  std::string found = {};   ///< optional text after "found "
};

void PrintTo(const RuleCase& rule, std::ostream* out) {
  *out << rule.name;
}

class ConfigRule : public ::testing::TestWithParam<RuleCase> {};

TEST_P(ConfigRule, ErrorNamesFileLineKeyAndExpectation) {
  const RuleCase& rule = GetParam();
  const std::string message = ErrorOf(rule.toml);
  const std::string location =
      std::string(kSource) + ":" + std::to_string(LineOf(rule.toml, rule.line_marker)) + ":";
  EXPECT_THAT(message, ::testing::StartsWith(location));
  EXPECT_THAT(message, HasSubstr("'" + rule.key + "'"));
  EXPECT_THAT(message, HasSubstr(rule.expected));
  if (!rule.found.empty()) {
    EXPECT_THAT(message, HasSubstr("found " + rule.found));
  }
}

std::vector<RuleCase> TopLevelCases() {
  return {
      {"UnknownTopLevelKey", Full("name = \"full flexible\"", "nmae = \"x\""), "nmae", "nmae",
       "unknown key 'nmae' (allowed here: name, simulation, gravity, trigger, rotor"},
      {"NameNotString", Full("name = \"full flexible\"", "name = 3"), "name = 3", "name",
       "expected a string", "3"},
      {"StepNotPositive", Full("step_s = 1e-5", "step_s = 0"), "step_s = 0", "simulation.step_s",
       "expected a positive number (s)", "0"},
      {"StepIsString", Full("step_s = 1e-5", "step_s = \"fast\""), "step_s", "simulation.step_s",
       "expected a positive number (s)", "\"fast\""},
      {"DurationNotFinite", Full("duration_s = 0.5", "duration_s = inf"), "duration_s",
       "simulation.duration_s", "expected a positive number (s)", "inf"},
      {"DurationBeyondMaxSteps", Full("duration_s = 0.5", "duration_s = 1e300"), "duration_s",
       "simulation.duration_s",
       "expected simulation.duration_s <= 10000 s: at most simulation.max_steps = 1000000000 "
       "steps of 1e-05 s",
       "duration_s = 1e+300 s"},
      {"OutputIntervalBelowStep", Full("output_interval_s = 1e-4", "output_interval_s = 1e-6"),
       "output_interval_s", "simulation.output_interval_s",
       "expected a number in [simulation.step_s, simulation.max_steps * simulation.step_s] = "
       "[1e-05, 10000] (s)",
       "1e-06"},
      {"SpinSpeedNegative", Full("spin_speed_rad_s = 1000", "spin_speed_rad_s = -1"),
       "spin_speed_rad_s", "simulation.spin_speed_rad_s", "expected a non-negative number (rad/s)",
       "-1"},
      {"InitialPositionUnknown",
       Full("initial_position = \"centred\"", "initial_position = \"center\""), "initial_position",
       "simulation.initial_position", "expected one of \"equilibrium\", \"centred\"", "\"center\""},
      {"MaxExcursionNotPositive",
       Full("max_excursion_over_clearance = 20", "max_excursion_over_clearance = 0"),
       "max_excursion_over_clearance", "simulation.max_excursion_over_clearance",
       "expected a positive number"},
      {"SimulationUnknownKey", Full("step_s = 1e-5", "stepsize_s = 1e-5"), "stepsize_s",
       "simulation.stepsize_s", "(allowed here: step_s, duration_s, output_interval_s"},
      {"GravityEnabledNotBool", Full("[gravity]\nenabled = false", "[gravity]\nenabled = \"no\""),
       "enabled = \"no\"", "gravity.enabled", "expected a boolean (true or false)", "\"no\""},
      {"GravityNegative", Full("acceleration_m_s2 = 9.8", "acceleration_m_s2 = -9.8"),
       "acceleration_m_s2", "gravity.acceleration_m_s2", "expected a non-negative number (m/s^2)"},
      {"TriggerTimeNegative", Full("time_s = 0.1", "time_s = -0.1"), "time_s = -0.1",
       "trigger.time_s", "expected a non-negative number (s)", "-0.1"},
      {"TriggerNotTable",
       Replace(Full("[trigger]\nenabled = true\ntime_s = 0.1\n", ""), "name = \"full flexible\"",
               "name = \"full flexible\"\ntrigger = 0.1"),
       "trigger = 0.1", "trigger", "expected a table ([trigger])", "0.1"},
  };
}

std::vector<RuleCase> RotorCases() {
  const std::string flexible_without_sections(
      kMinimalFlexible.substr(0, kMinimalFlexible.find("[[rotor.sections]]")));
  return {
      {"RotorMissing", "name = \"no rotor\"\n", "name", "rotor", "expected a table ([rotor])"},
      {"RotorModelMissing", Full("model = \"flexible\"\n", ""), "[rotor]", "rotor.model",
       "missing key 'rotor.model': expected one of \"flexible\", \"rigid\""},
      {"RotorModelUnknown", Full("model = \"flexible\"", "model = \"elastic\""),
       "model =", "rotor.model", "expected one of \"flexible\", \"rigid\"", "\"elastic\""},
      {"ModesAboveMax", Full("modes = 10", "modes = 41"), "modes", "rotor.modes",
       "expected an integer in [1, 40]", "41"},
      {"ModesNotInteger", Full("modes = 10", "modes = 10.5"), "modes", "rotor.modes",
       "expected an integer in [1, 40]", "10.5"},
      {"ModalDampingNotBelowOne", Full("modal_damping_ratio = 0.01", "modal_damping_ratio = 1"),
       "modal_damping_ratio", "rotor.modal_damping_ratio", "expected a number in [0, 1)", "1"},
      {"RotorUnknownKey", Full("modes = 10", "mode = 10"), "mode = 10", "rotor.mode",
       "unknown key 'rotor.mode' (allowed here: model, modes, modal_damping_ratio, materials, "
       "sections, discs, element_theory, coast_down)"},
      {"MaterialKeyMissing", Full("density_kg_m3 = 4500\n", ""), "[rotor.materials.titanium]",
       "rotor.materials.titanium.density_kg_m3",
       "missing key 'rotor.materials.titanium.density_kg_m3': expected a positive number "
       "(kg/m^3)"},
      {"MaterialNotPositive", Full("youngs_modulus_Pa = 211e9", "youngs_modulus_Pa = 0"),
       "youngs_modulus_Pa = 0", "rotor.materials.steel.youngs_modulus_Pa",
       "expected a positive number (Pa)"},
      {"SectionsMissing", flexible_without_sections, "[rotor]", "rotor.sections",
       "missing key 'rotor.sections': expected at least one shaft section ([[rotor.sections]])"},
      {"SectionsEmpty", Replace(flexible_without_sections, "model", "sections = []\nmodel"),
       "sections = []", "rotor.sections", "expected at least one shaft section", "[]"},
      {"SectionsNotAnArrayOfTables",
       Replace(flexible_without_sections, "model", "sections = 3\nmodel"), "sections = 3",
       "rotor.sections", "expected an array of tables ([[rotor.sections]])", "3"},
      {"DiscNotATable", Replace(kMinimalFlexible, "model", "discs = [1]\nmodel"), "discs = [1]",
       "rotor.discs[0]", "expected a table (an element of [[rotor.discs]])", "1"},
      {"SectionLengthNotPositive", Full("length_m = 0.2", "length_m = -0.2"), "length_m = -0.2",
       "rotor.sections[0].length_m", "expected a positive number (m)", "-0.2"},
      {"SectionOuterDiameterNotPositive", Full("outer_diameter_m = 0.04", "outer_diameter_m = 0"),
       "outer_diameter_m = 0\n", "rotor.sections[0].outer_diameter_m",
       "expected a positive number (m)"},
      {"SectionBoreNotBelowOuterDiameter",
       Full("inner_diameter_m = 0.02", "inner_diameter_m = 0.07"), "inner_diameter_m = 0.07",
       "rotor.sections[1].inner_diameter_m",
       "expected a non-negative number less than outer_diameter_m = 0.06 (m)", "0.07"},
      {"SectionMaterialMissing", Full("material = \"titanium\"\n", ""),
       "[[rotor.sections]]\nlength_m = 0.3", "rotor.sections[1].material",
       "missing key 'rotor.sections[1].material': expected one of the materials \"steel\", "
       "\"titanium\""},
      {"SectionMaterialUnknown", Full("material = \"titanium\"", "material = \"titanum\""),
       "material = \"titanum\"", "rotor.sections[1].material",
       "expected one of the materials \"steel\", \"titanium\" (from [rotor.materials])",
       "\"titanum\""},
      {"SectionElementsBelowOne", Full("elements = 4", "elements = 0"), "elements",
       "rotor.sections[0].elements", "expected an integer in [1, 500]", "0"},
      {"SectionElementsAboveBound", Full("elements = 4", "elements = 100000"), "elements",
       "rotor.sections[0].elements", "expected an integer in [1, 500]", "100000"},
      {"SectionUnknownKey", Full("elements = 4", "elemnts = 4"), "elemnts",
       "rotor.sections[0].elemnts", "(allowed here: length_m, outer_diameter_m"},
      {"DiscPositionMissing", Full("position_m = 0.25\n", ""), "[[rotor.discs]]",
       "rotor.discs[0].position_m",
       "missing key 'rotor.discs[0].position_m': expected a position on the shaft, in [0, 0.5] "
       "(m)"},
      {"DiscPositionOffShaft", Full("position_m = 0.4\n", "position_m = 0.6\n"), "position_m = 0.6",
       "rotor.discs[1].position_m", "expected a position on the shaft, in [0, 0.5] (m)", "0.6"},
      {"DiscMassFormIncomplete", Full("transverse_inertia_kg_m2 = 0.006\n", ""), "[[rotor.discs]]",
       "rotor.discs[0].transverse_inertia_kg_m2", "expected a non-negative number (kg m^2)"},
      {"DiscMassNegative", Full("mass_kg = 3.5", "mass_kg = -3.5"), "mass_kg = -3.5",
       "rotor.discs[0].mass_kg", "expected a non-negative number (kg)", "-3.5"},
      {"DiscMixesMassAndGeometry", Full("mass_kg = 3.5", "mass_kg = 3.5\nthickness_m = 0.01"),
       "thickness_m = 0.01", "rotor.discs[0].thickness_m",
       "expected no geometry key next to mass_kg", "0.01"},
      {"DiscHasNeitherMassNorGeometry",
       Full("mass_kg = 3.5\npolar_inertia_kg_m2 = 0.01\ntransverse_inertia_kg_m2 = 0.006\n", ""),
       "[[rotor.discs]]", "rotor.discs[0].mass_kg",
       "or a geometric disc (outer_diameter_m, thickness_m, material)"},
      {"DiscGeometryIncomplete", Full("thickness_m = 0.03\n", ""),
       "[[rotor.discs]]\nposition_m = 0.4", "rotor.discs[1].thickness_m",
       "missing key 'rotor.discs[1].thickness_m': expected a positive number (m)"},
      {"DiscBoreNotBelowOuterDiameter", Full("inner_diameter_m = 0.06", "inner_diameter_m = 0.2"),
       "inner_diameter_m = 0.2", "rotor.discs[1].inner_diameter_m",
       "expected a non-negative number less than outer_diameter_m = 0.2 (m)"},
      {"DiscMaterialUnknown",
       Full("thickness_m = 0.03\nmaterial = \"steel\"", "thickness_m = 0.03\nmaterial = \"lead\""),
       "material = \"lead\"", "rotor.discs[1].material", "expected one of the materials",
       "\"lead\""},
      {"RigidTableMissing",
       std::string(kMinimalRigid.substr(0, kMinimalRigid.find("[rotor.rigid]"))), "[rotor]",
       "rotor.rigid", "missing key 'rotor.rigid': expected a table ([rotor.rigid])"},
      {"RigidWithSections", std::string(kMinimalRigid) + "[[rotor.sections]]\nlength_m = 0.5\n",
       "[[rotor.sections]]", "rotor.sections", "expected no sections with model = \"rigid\""},
      {"FlexibleWithRigidTable", std::string(kMinimalFlexible) + "[rotor.rigid]\nmass_kg = 1\n",
       "[rotor.rigid]", "rotor.rigid", "expected no [rotor.rigid] table with model = \"flexible\"",
       "a table"},
      {"RigidMassNotPositive", Replace(kMinimalRigid, "mass_kg = 12.5", "mass_kg = 0"),
       "mass_kg = 0", "rotor.rigid.mass_kg", "expected a positive number (kg)", "0"},
      {"RigidCentreOfMassMissing", Replace(kMinimalRigid, "centre_of_mass_m = 0.24\n", ""),
       "[rotor.rigid]", "rotor.rigid.centre_of_mass_m",
       "missing key 'rotor.rigid.centre_of_mass_m': expected a finite number (m)"},
  };
}

std::vector<RuleCase> SupportCases() {
  return {
      {"BearingPositionMissing",
       Full("[bearing.coupling]\nposition_m = 0.0\n", "[bearing.coupling]\n"), "[bearing.coupling]",
       "bearing.coupling.position_m", "missing key 'bearing.coupling.position_m'"},
      {"BearingOffShaft",
       Full("[bearing.coupling]\nposition_m = 0.0", "[bearing.coupling]\nposition_m = -0.1"),
       "position_m = -0.1", "bearing.coupling.position_m",
       "expected a position on the shaft, in [0, 0.5] (m)", "-0.1"},
      {"BearingStiffnessMissing", Full("stiffness_N_per_m = 1e5\n", ""), "[bearing.coupling]",
       "bearing.coupling.stiffness_N_per_m",
       "expected a non-negative number (N/m), or stiffness_x_N_per_m and stiffness_y_N_per_m"},
      {"BearingStiffnessFormsMixed",
       Full("stiffness_N_per_m = 1e5", "stiffness_N_per_m = 1e5\nstiffness_x_N_per_m = 2e5"),
       "stiffness_x_N_per_m", "bearing.coupling.stiffness_x_N_per_m",
       "expected no stiffness_x_N_per_m next to stiffness_N_per_m", "200000"},
      {"BearingStiffnessHalfGiven", Full("stiffness_N_per_m = 1e5", "stiffness_x_N_per_m = 1e5"),
       "[bearing.coupling]", "bearing.coupling.stiffness_y_N_per_m",
       "missing key 'bearing.coupling.stiffness_y_N_per_m': expected a non-negative number "
       "(N/m)"},
      {"BearingDampingNegative", Full("damping_x_N_s_per_m = 10", "damping_x_N_s_per_m = -10"),
       "damping_x_N_s_per_m", "bearing.coupling.damping_x_N_s_per_m",
       "expected a non-negative number (N s/m)"},
      {"TooManyBearings",
       std::string(kFullFlexible) +
           Repeat("[bearing.extra#]\nposition_m = 0.1\nstiffness_N_per_m = 1\n", 4),
       "[bearing.coupling]", "bearing", "expected at most 4 linear bearings", "5 linear bearings"},
      {"AmbLawUnknown", Full("law = \"linearised_currents\"", "law = \"pid\""), "law = \"pid\"",
       "amb.de.law", "expected one of \"equivalent\", \"linearised_currents\"", "\"pid\""},
      {"AmbEquivalentStiffnessMissing", Full("stiffness_N_per_m = 2e6\n", ""), "[amb.nde]",
       "amb.nde.stiffness_N_per_m",
       "missing key 'amb.nde.stiffness_N_per_m': expected a non-negative number (N/m)"},
      {"AmbEquivalentDampingNegative", Full("damping_N_s_per_m = 800", "damping_N_s_per_m = -8"),
       "damping_N_s_per_m = -8", "amb.nde.damping_N_s_per_m",
       "expected a non-negative number (N s/m)"},
      {"AmbEquivalentWithLinearisedKey",
       Full("gravity_compensation = false",
            "gravity_compensation = false\nposition_gain_N_per_m = 1"),
       "position_gain_N_per_m = 1\n", "amb.nde.position_gain_N_per_m",
       "expected no position_gain_N_per_m with law = \"equivalent\" (it belongs to law = "
       "\"linearised_currents\")"},
      {"AmbLinearisedWithEquivalentKey",
       Full("current_gain_N_per_A = 150",
            "current_gain_N_per_A = 150\ngravity_compensation = true"),
       "gravity_compensation = true", "amb.de.gravity_compensation",
       "expected no gravity_compensation with law = \"linearised_currents\""},
      {"AmbCurrentGainMissing", Full("current_gain_N_per_A = 150\n", ""), "[amb.de]",
       "amb.de.current_gain_N_per_A",
       "missing key 'amb.de.current_gain_N_per_A': expected a finite number (N/A)"},
      {"AmbPositionGainNegative",
       Full("position_gain_N_per_m = 4e5", "position_gain_N_per_m = -4e5"), "position_gain_N_per_m",
       "amb.de.position_gain_N_per_m", "expected a non-negative number (N/m)"},
      {"AmbProfileNotAnArray",
       Full("current_profile = [[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]]", "current_profile = 1.0"),
       "current_profile", "amb.de.current_profile",
       "expected an array of [time_s, current_x_A, current_y_A] triples", "1"},
      {"AmbProfilePointNotATriple",
       Full("[[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]]", "[[0.0, 1.0], [0.1, 0.5, 0.25]]"),
       "current_profile", "amb.de.current_profile[0]",
       "expected a triple [time_s, current_x_A, current_y_A] of finite numbers", "[0, 1]"},
      {"AmbProfileCurrentNotFinite",
       Full("[[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]]", "[[0.0, 1.0, -1.0], [0.1, nan, 0.25]]"),
       "current_profile", "amb.de.current_profile[1]",
       "expected a triple [time_s, current_x_A, current_y_A] of finite numbers",
       "[0.1, nan, 0.25]"},
      {"AmbProfileTimesNotIncreasing",
       Full("[[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]]", "[[0.1, 1.0, -1.0], [0.1, 0.5, 0.25]]"),
       "current_profile", "amb.de.current_profile[1]",
       "expected a time_s greater than that of the previous point (0.1 s)"},
      {"AmbProfileTooLong",
       Full("[0.0, 1.0, -1.0], [0.1, 0.5, 0.25]", Repeat("[#, 0, 0], ", 1024) + "[1e6, 0, 0]"),
       "current_profile", "amb.de.current_profile", "expected at most 1024 points", "1025 points"},
      {"AmbOffShaft", Full("position_m = 0.45", "position_m = 0.55"), "position_m = 0.55",
       "amb.nde.position_m", "expected a position on the shaft, in [0, 0.5] (m)", "0.55"},
      {"TooManyAmbs", std::string(kFullFlexible) + Repeat("[amb.extra#]\nposition_m = 0.1\n", 3),
       "[amb.nde]", "amb", "expected at most 4 magnetic bearings", "5 magnetic bearings"},
      {"SensorPositionMissing", Full("[sensor.s1]\nposition_m = 0.12", "[sensor.s1]"),
       "[sensor.s1]", "sensor.s1.position_m", "missing key 'sensor.s1.position_m'"},
      {"SensorOffShaft", Full("position_m = 0.12", "position_m = 1.2"), "position_m = 1.2",
       "sensor.s1.position_m", "expected a position on the shaft, in [0, 0.5] (m)", "1.2"},
      {"SensorNotATable", Full("[sensor.s1]\nposition_m = 0.12", "[sensor]\ns1 = 0.12"),
       "s1 = 0.12", "sensor.s1", "expected a table ([sensor.s1])", "0.12"},
      {"TooManySensors", std::string(kFullFlexible) + Repeat("[sensor.x#]\nposition_m = 0\n", 8),
       "[sensor.s1]", "sensor", "expected at most 8 sensors", "9 sensors"},
      {"UnbalanceMassMissing", Full("mass_kg = 0.001\n", ""), "[unbalance.u1]",
       "unbalance.u1.mass_kg",
       "missing key 'unbalance.u1.mass_kg': expected a non-negative "
       "number (kg)"},
      {"UnbalanceEccentricityNegative", Full("eccentricity_m = 0.1", "eccentricity_m = -0.1"),
       "eccentricity_m", "unbalance.u1.eccentricity_m", "expected a non-negative number (m)"},
      {"UnbalancePhaseNotFinite", Full("phase_rad = 1.5", "phase_rad = nan"), "phase_rad",
       "unbalance.u1.phase_rad", "expected a finite number (rad)", "nan"},
      {"UnbalanceOffShaft", Full("position_m = 0.26", "position_m = 0.51"), "position_m = 0.51",
       "unbalance.u1.position_m", "expected a position on the shaft, in [0, 0.5] (m)"},
      {"TooManyUnbalances",
       std::string(kFullFlexible) +
           Repeat("[unbalance.x#]\nposition_m = 0\nmass_kg = 0\neccentricity_m = 0\n", 8),
       "[unbalance.u1]", "unbalance", "expected at most 8 unbalances", "9 unbalances"},
  };
}

std::vector<RuleCase> TdbCases() {
  return {
      {"TdbClearanceMissing", Full("clearance_m = 2e-4\n", ""), "[tdb.de]", "tdb.de.clearance_m",
       "missing key 'tdb.de.clearance_m': expected a positive number (m)"},
      {"TdbClearanceNotPositive", Full("clearance_m = 2e-4", "clearance_m = -0.001"), "clearance_m",
       "tdb.de.clearance_m", "expected a positive number (m)", "-0.001"},
      {"TdbJournalRadiusNotPositive", Full("journal_radius_m = 0.02", "journal_radius_m = 0"),
       "journal_radius_m", "tdb.de.journal_radius_m", "expected a positive number (m)"},
      {"TdbOffShaft", Full("position_m = 0.05", "position_m = 5"), "position_m = 5",
       "tdb.de.position_m", "expected a position on the shaft, in [0, 0.5] (m)", "5"},
      {"TdbModelUnknown", Full("model = \"contact_law\"", "model = \"hertz\""), "model = \"hertz\"",
       "tdb.de.model", "expected one of \"contact_law\"", "\"hertz\""},
      {"TdbUnknownKey", Full("clearance_m = 2e-4", "clearence_m = 2e-4"), "clearence_m",
       "tdb.de.clearence_m",
       "unknown key 'tdb.de.clearence_m' (allowed here: position_m, journal_radius_m, "
       "clearance_m, inner_race_radius_m, model, contact_law, friction, spin, misalignment, "
       "four_dof, ball_bearing_tdb, catcher_bearing)"},
      {"TdbContactLawMissing",
       Full("[tdb.de.contact_law]\nbearing_stiffness_N_per_m = 1e8\nbearing_damping_N_s_per_m = "
            "100\nribbon_stiffness_N_per_m = 5e6\nribbon_damping_N_s_per_m = 50\n"
            "ribbon_crushing_m = 1e-4\n",
            ""),
       "[tdb.de]", "tdb.de.contact_law",
       "missing key 'tdb.de.contact_law': expected a table ([tdb.de.contact_law])"},
      {"TdbContactLawKeyMissing", Full("ribbon_crushing_m = 1e-4\n", ""), "[tdb.de.contact_law]",
       "tdb.de.contact_law.ribbon_crushing_m",
       "missing key 'tdb.de.contact_law.ribbon_crushing_m': expected a non-negative number (m)"},
      {"TdbContactStiffnessNotPositive",
       Full("ribbon_stiffness_N_per_m = 5e6", "ribbon_stiffness_N_per_m = 0"),
       "ribbon_stiffness_N_per_m", "tdb.de.contact_law.ribbon_stiffness_N_per_m",
       "expected a positive number (N/m)"},
      {"TdbContactDampingNegative",
       Full("bearing_damping_N_s_per_m = 100", "bearing_damping_N_s_per_m = -1"),
       "bearing_damping_N_s_per_m", "tdb.de.contact_law.bearing_damping_N_s_per_m",
       "expected a non-negative number (N s/m)"},
      {"TdbFrictionLawUnknown", Full("law = \"regularised_coulomb\"", "law = \"coulomb\""),
       "law = \"coulomb\"", "tdb.de.friction.law",
       "expected one of \"regularised_coulomb\", \"none\"", "\"coulomb\""},
      {"TdbFrictionCoefficientNegative", Full("coefficient = 0.3", "coefficient = -0.3"),
       "coefficient", "tdb.de.friction.coefficient", "expected a non-negative number", "-0.3"},
      {"TdbFrictionRegularisationNotPositive",
       Full("regularisation_s_per_m = 50", "regularisation_s_per_m = 0"), "regularisation_s_per_m",
       "tdb.de.friction.regularisation_s_per_m", "expected a positive number (s/m)"},
      {"TdbSpinInertiaNotPositive", Full("inertia_kg_m2 = 1e-3", "inertia_kg_m2 = -1e-3"),
       "inertia_kg_m2 = -1e-3", "tdb.de.spin.inertia_kg_m2", "expected a positive number (kg m^2)"},
      {"TdbSpinDragNegative", Full("drag_torque_N_m = 0.01", "drag_torque_N_m = -0.01"),
       "drag_torque_N_m", "tdb.de.spin.drag_torque_N_m", "expected a non-negative number (N m)"},
      {"TdbMisalignmentNotFinite", Full("x_m = 1e-5", "x_m = -inf"), "x_m = -inf",
       "tdb.de.misalignment.x_m", "expected a finite number (m)", "-inf"},
      {"TdbGroupNotATable", Replace(kMinimalFlexible, "[rotor]\n", "tdb = 3\n[rotor]\n"), "tdb = 3",
       "tdb", "expected a table of named entries ([tdb.NAME])", "3"},
      {"TooManyTdbs", std::string(kFullFlexible) + Repeat("[tdb.x#]\nposition_m = 0\n", 4),
       "[tdb.de]", "tdb", "expected at most 4 touchdown bearings", "5 touchdown bearings"},
  };
}

std::string CaseName(const ::testing::TestParamInfo<RuleCase>& info) {
  return info.param.name;
}

INSTANTIATE_TEST_SUITE_P(TopLevel, ConfigRule, ::testing::ValuesIn(TopLevelCases()), CaseName);
INSTANTIATE_TEST_SUITE_P(Rotor, ConfigRule, ::testing::ValuesIn(RotorCases()), CaseName);
INSTANTIATE_TEST_SUITE_P(Supports, ConfigRule, ::testing::ValuesIn(SupportCases()), CaseName);
INSTANTIATE_TEST_SUITE_P(Tdb, ConfigRule, ::testing::ValuesIn(TdbCases()), CaseName);

TEST(ConfigSyntax, ParseErrorNamesFileAndLine) {
  const std::string text = Full("modes = 10", "modes = = 10");
  const std::string message = ErrorOf(text);
  EXPECT_THAT(message, ::testing::StartsWith(std::string(kSource) + ":" +
                                             std::to_string(LineOf(text, "modes = =")) + ":"));
}

TEST(ConfigSyntax, DuplicateKeyIsAParseError) {
  const std::string text = Full("modes = 10", "modes = 10\nmodes = 11");
  EXPECT_THAT(ErrorOf(text), ::testing::StartsWith(std::string(kSource) + ":" +
                                                   std::to_string(LineOf(text, "modes = 11"))));
}

}  // namespace
}  // namespace ambdrop::config_loader_test
