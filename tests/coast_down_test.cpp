// Coast-down losses ([rotor.coast_down]): once the drive stops, a rotor that touches nothing
// slows as Ip W' = -(T0 + c1 W + c2 W^2), whose closed forms each term is checked against alone;
// Ip comes from the rigid rotor's declared inertia or from the flexible shaft's geometry.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop::coast_down_test {
namespace {

using ::testing::HasSubstr;

constexpr char kSource[] = "coast.toml";
constexpr double kSpin0_rad_s = 1000.0;

// No gravity, no TDB, no support: nothing but the coast-down losses acts on the spin.
constexpr std::string_view kRigid = R"(name = "coasting rigid rotor"
[simulation]
step_s = 5e-6
spin_speed_rad_s = 1000
initial_position = "centred"
[gravity]
enabled = false
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 50
polar_inertia_kg_m2 = 0.5
transverse_inertia_kg_m2 = 4
centre_of_mass_m = 0.3
[rotor.coast_down]
enabled = true
)";

// Hollow steel shaft with one disc of declared polar inertia.
constexpr double kShaftLength_m = 0.6, kOuter_m = 0.08, kInner_m = 0.03, kDensity = 7800.0;
constexpr double kDiscPolar_kg_m2 = 0.15;
constexpr std::string_view kFlexible = R"(name = "coasting flexible rotor"
[simulation]
step_s = 5e-6
spin_speed_rad_s = 1000
initial_position = "centred"
[gravity]
enabled = false
[rotor]
model = "flexible"
modes = 8
[rotor.materials.steel]
youngs_modulus_Pa = 211e9
shear_modulus_Pa = 81.2e9
density_kg_m3 = 7800
[[rotor.sections]]
length_m = 0.6
outer_diameter_m = 0.08
inner_diameter_m = 0.03
material = "steel"
elements = 6
[[rotor.discs]]
position_m = 0.3
mass_kg = 20
polar_inertia_kg_m2 = 0.15
transverse_inertia_kg_m2 = 0.08
[rotor.coast_down]
enabled = true
)";

// Ip of the flexible rotor from its geometry: rho pi/32 (D^4 - d^4) L plus the disc.
double FlexiblePolarInertia() {
  const double d4 = std::pow(kOuter_m, 4) - std::pow(kInner_m, 4);
  return kDensity * std::numbers::pi / 32.0 * d4 * kShaftLength_m + kDiscPolar_kg_m2;
}

/// A --set value that reads back as the same double (std::to_string keeps only 6 decimals).
std::string Exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

ModelParams Load(std::string_view text, const std::vector<std::string>& overrides) {
  return LoadConfigFromString(std::string(text), kSource, overrides).params;
}

/// Spin speed after `duration_s` with the drive off (or on) from kSpin0_rad_s.
double SpinAfter(const ModelParams& params, double duration_s, bool motor_on = false) {
  const Model model = BuildModel(params);
  Simulator sim(model);
  State s = sim.InitialState();
  const ControlInput input = motor_on ? ControlInput::Powered() : ControlInput::PowerOff();
  const auto steps = static_cast<std::int64_t>(std::llround(duration_s / params.simulation.step_s));
  for (std::int64_t i = 0; i < steps; ++i) {
    EXPECT_EQ(sim.Step(&s, input), StepStatus::kOk);
  }
  return s.y(model.spin_index());
}

constexpr double kDuration_s = 0.3;
constexpr double kTolerance = 1e-8;  // RK4 at 5 us: the truncation error is ~1e-13 here

struct Rotor {
  const char* name;
  std::string_view config;
  double polar_inertia_kg_m2;
};

std::vector<Rotor> Rotors() {
  return {{"rigid", kRigid, 0.5}, {"flexible", kFlexible, FlexiblePolarInertia()}};
}

TEST(CoastDown, ModelUsesThePolarInertiaOfTheGeometry) {
  const Model model = BuildModel(Load(kFlexible, {}));
  EXPECT_NEAR(model.rotor.polar_inertia_kg_m2 / FlexiblePolarInertia(), 1.0, 1e-12);
}

TEST(CoastDown, ViscousAloneDecaysExponentially) {
  for (const Rotor& r : Rotors()) {
    const double ip = r.polar_inertia_kg_m2;
    const double c1 = 3.0 * ip;  // W falls to exp(-0.9) in 0.3 s
    const ModelParams p = Load(r.config, {"rotor.coast_down.viscous_N_m_s=" + Exact(c1)});
    const double expected = kSpin0_rad_s * std::exp(-c1 * kDuration_s / ip);
    EXPECT_NEAR(SpinAfter(p, kDuration_s) / expected, 1.0, kTolerance) << r.name;
  }
}

TEST(CoastDown, WindageAloneFallsHyperbolically) {
  for (const Rotor& r : Rotors()) {
    const double ip = r.polar_inertia_kg_m2;
    const double c2 = ip / (kSpin0_rad_s * kDuration_s);  // halves W in 0.3 s
    const ModelParams p = Load(r.config, {"rotor.coast_down.windage_N_m_s2=" + Exact(c2)});
    const double expected = kSpin0_rad_s / (1.0 + c2 * kSpin0_rad_s * kDuration_s / ip);
    EXPECT_NEAR(SpinAfter(p, kDuration_s) / expected, 1.0, kTolerance) << r.name;
  }
}

TEST(CoastDown, ConstantAloneFallsLinearly) {
  for (const Rotor& r : Rotors()) {
    const double ip = r.polar_inertia_kg_m2;
    const double t0 = 2000.0 * ip;  // 2000 rad/s^2: from 1000 to 400 rad/s in 0.3 s
    const ModelParams p = Load(r.config, {"rotor.coast_down.constant_torque_N_m=" + Exact(t0)});
    const double expected = kSpin0_rad_s - t0 * kDuration_s / ip;
    EXPECT_NEAR(SpinAfter(p, kDuration_s) / expected, 1.0, kTolerance) << r.name;
  }
}

TEST(CoastDown, ConstantTorqueStopsTheRotorWithoutReversingIt) {
  // Ip W0 / T0 = 0.25 s to stop; below ~1/k the smooth sign makes the torque viscous, T0 k W,
  // so W then decays at T0 k / Ip = 4e4 /s and never changes sign.
  const ModelParams p = Load(kRigid, {"rotor.coast_down.constant_torque_N_m=2000",
                                      "rotor.coast_down.sign_regularisation_s_per_rad=10"});
  const double w = SpinAfter(p, 0.3);
  EXPECT_GE(w, 0.0);
  EXPECT_LT(w, 1e-6);
}

TEST(CoastDown, AllThreeTogetherMatchTheIntegratedOde) {
  // W' = -(T0 + c1 W + c2 W^2)/Ip separates: t = Ip int dW / (c2 W^2 + c1 W + T0). With
  // discriminant D = c1^2 - 4 c2 T0 < 0 its closed form is
  // t = (2 Ip / s) [atan((2 c2 W0 + c1)/s) - atan((2 c2 W + c1)/s)], s = sqrt(-D); so
  // W(t) = ((s tan(atan((2 c2 W0 + c1)/s) - s t / (2 Ip))) - c1) / (2 c2).
  const double ip = 0.5, t0 = 100.0, c1 = 0.2, c2 = 5e-4;
  const ModelParams p =
      Load(kRigid, {"rotor.coast_down.constant_torque_N_m=100",
                    "rotor.coast_down.viscous_N_m_s=0.2", "rotor.coast_down.windage_N_m_s2=5e-4"});
  const double s = std::sqrt(4.0 * c2 * t0 - c1 * c1);
  const double phase = std::atan((2.0 * c2 * kSpin0_rad_s + c1) / s) - s * kDuration_s / (2 * ip);
  const double expected = (s * std::tan(phase) - c1) / (2.0 * c2);
  ASSERT_GT(expected, 100.0);  // still well above the regularised band
  EXPECT_NEAR(SpinAfter(p, kDuration_s) / expected, 1.0, kTolerance);
}

TEST(CoastDown, DisabledOrDrivenRotorKeepsItsSpeed) {
  const std::vector<std::string> losses = {"rotor.coast_down.constant_torque_N_m=5",
                                           "rotor.coast_down.viscous_N_m_s=0.1",
                                           "rotor.coast_down.windage_N_m_s2=1e-4"};
  std::vector<std::string> disabled = losses;
  disabled.push_back("rotor.coast_down.enabled=false");
  EXPECT_EQ(SpinAfter(Load(kRigid, disabled), 0.05), kSpin0_rad_s);
  // While the drive runs it holds the speed whatever the losses.
  EXPECT_EQ(SpinAfter(Load(kRigid, losses), 0.05, /*motor_on=*/true), kSpin0_rad_s);
}

TEST(CoastDown, DefaultsAreOffAndADisabledTableNeedsNoNumbers) {
  std::string text(kRigid);
  text.erase(text.find("[rotor.coast_down]"));
  const ModelParams none = Load(text, {});
  EXPECT_FALSE(none.rotor.coast_down.enabled);
  EXPECT_EQ(none.rotor.coast_down.constant_torque_N_m, 0.0);
  EXPECT_EQ(none.rotor.coast_down.viscous_N_m_s, 0.0);
  EXPECT_EQ(none.rotor.coast_down.windage_N_m_s2, 0.0);
  EXPECT_EQ(none.rotor.coast_down.sign_regularisation_s_per_rad, 100.0);
  text += "[rotor.coast_down]\nenabled = false\n";
  EXPECT_FALSE(Load(text, {}).rotor.coast_down.enabled);
}

// ---------------------------------------------------------------------------------------------
// Config rules: each error names the file, line, key and what was expected.

struct RuleCase {
  const char* name;
  std::string lines;        ///< the body of [rotor.coast_down]
  std::string line_marker;  ///< text that starts on the line the error must point at
  std::string key;
  std::string expected;
  std::string found = {};
};

void PrintTo(const RuleCase& rule, std::ostream* out) {
  *out << rule.name;
}

class CoastDownRule : public ::testing::TestWithParam<RuleCase> {};

TEST_P(CoastDownRule, ErrorNamesFileLineKeyAndExpectation) {
  const RuleCase& rule = GetParam();
  std::string text(kRigid);
  text.erase(text.find("[rotor.coast_down]"));
  text += "[rotor.coast_down]\n" + rule.lines;
  std::string message;
  try {
    LoadConfigFromString(text, kSource);
    ADD_FAILURE() << "loaded without a ConfigError";
  } catch (const ConfigError& error) {
    message = error.what();
  }
  const auto pos = text.find(rule.line_marker);
  ASSERT_NE(pos, std::string::npos);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
  EXPECT_THAT(message, ::testing::StartsWith(std::string(kSource) + ":" + std::to_string(line)));
  EXPECT_THAT(message, HasSubstr("'" + rule.key + "'"));
  EXPECT_THAT(message, HasSubstr(rule.expected));
  if (!rule.found.empty()) {
    EXPECT_THAT(message, HasSubstr("found " + rule.found));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Keys, CoastDownRule,
    ::testing::Values(
        RuleCase{"ConstantNegative", "enabled = true\nconstant_torque_N_m = -1\n",
                 "constant_torque_N_m", "rotor.coast_down.constant_torque_N_m",
                 "expected a non-negative number (N m)", "-1"},
        RuleCase{"ViscousNegative", "enabled = true\nviscous_N_m_s = -0.1\n", "viscous_N_m_s",
                 "rotor.coast_down.viscous_N_m_s", "expected a non-negative number (N m s)",
                 "-0.1"},
        RuleCase{"WindageNotFinite", "enabled = false\nwindage_N_m_s2 = nan\n", "windage_N_m_s2",
                 "rotor.coast_down.windage_N_m_s2", "expected a non-negative number (N m s^2)",
                 "nan"},
        RuleCase{"WindageNotANumber", "windage_N_m_s2 = \"high\"\n", "windage_N_m_s2",
                 "rotor.coast_down.windage_N_m_s2", "expected a non-negative number (N m s^2)"},
        RuleCase{"RegularisationNotPositive", "enabled = true\nsign_regularisation_s_per_rad = 0\n",
                 "sign_regularisation_s_per_rad", "rotor.coast_down.sign_regularisation_s_per_rad",
                 "expected a positive number (s/rad)", "0"},
        RuleCase{"EnabledNotBool", "enabled = \"yes\"\n", "enabled = \"yes\"",
                 "rotor.coast_down.enabled", "expected a boolean"},
        RuleCase{"UnknownKey", "enabled = true\nwindage_N_m_s = 1\n",
                 "windage_N_m_s =", "rotor.coast_down.windage_N_m_s",
                 "(allowed here: enabled, constant_torque_N_m, viscous_N_m_s, windage_N_m_s2, "
                 "sign_regularisation_s_per_rad)"}),
    [](const ::testing::TestParamInfo<RuleCase>& info) { return std::string(info.param.name); });

TEST(CoastDownRuleOverride, BadValueFromTheCommandLineNamesTheOverride) {
  try {
    LoadConfigFromString(std::string(kRigid), kSource, {"rotor.coast_down.viscous_N_m_s=-2"});
    ADD_FAILURE() << "loaded without a ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("--set rotor.coast_down.viscous_N_m_s=-2"));
    EXPECT_THAT(error.what(), HasSubstr("expected a non-negative number (N m s)"));
  }
}

}  // namespace
}  // namespace ambdrop::coast_down_test
