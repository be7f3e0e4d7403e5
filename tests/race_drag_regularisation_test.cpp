// tdb.NAME.spin.drag_regularisation_s_per_rad: the race drag torque's own smooth sign,
// Td k W / sqrt(1 + (k W)^2), instead of the friction's (x = vref Rir W). Checked on the race
// acceleration at slow speeds and on a race coasting down under drag alone, whose ODE
// I W' = -Td u / sqrt(1 + u^2), u = k W, integrates in closed form.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop::race_drag_regularisation_test {
namespace {

using ::testing::HasSubstr;

double SmoothSign(double x) {
  return x / std::sqrt(1.0 + x * x);
}

TdbParams Race() {
  TdbParams p;
  p.journal_radius_m = 0.04;
  p.clearance_m = 2e-4;
  p.friction.regularisation_s_per_m = 100.0;
  p.spin.inertia_kg_m2 = 2e-3;
  p.spin.drag_torque_N_m = 0.02;
  return p;
}

TEST(RaceDragRegularisation, DragAtSlowSpeedsFollowsItsOwnKey) {
  TdbParams p = Race();
  const double inner_race_radius_m = 0.0402;
  for (double w : {-3.0, -0.05, 0.01, 0.1, 0.7, 5.0}) {
    // Unset: the friction's scale, vref Rir (as before the key).
    p.spin.drag_regularisation_s_per_rad = 0.0;
    const double shared = -0.02 * SmoothSign(100.0 * inner_race_radius_m * w) / 2e-3;
    EXPECT_NEAR(RaceAcceleration(p, w, 0.0, 0.0), shared, 1e-12 * std::abs(shared)) << w;
    // Set: k W alone.
    p.spin.drag_regularisation_s_per_rad = 0.5;
    const double own = -0.02 * SmoothSign(0.5 * w) / 2e-3;
    EXPECT_NEAR(RaceAcceleration(p, w, 0.0, 0.0), own, 1e-12 * std::abs(own)) << w;
  }
}

TEST(RaceDragRegularisation, PalmgrenTorqueKeepsTheFrictionScale) {
  TdbParams p = Race();
  p.spin.palmgren_f1 = 2e-3;
  p.spin.pitch_diameter_m = 0.06;
  p.spin.drag_regularisation_s_per_rad = 0.5;
  const double normal_N = 500.0, friction_N = 3.0, w = 0.2;
  const double m1 = 2e-3 * normal_N * 0.06;
  const double expected =
      (friction_N * 0.0402 - m1 * SmoothSign(100.0 * w * 0.0402) - 0.02 * SmoothSign(0.5 * w)) /
      2e-3;
  EXPECT_NEAR(RaceAcceleration(p, w, friction_N, normal_N), expected, 1e-12 * std::abs(expected));
}

// A rigid rotor at rest, centred and weightless: its TDB is never touched, so the race coasts
// under its drag alone.
const std::string kRig = R"(name = "coasting race"
[simulation]
step_s = 5e-6
initial_position = "centred"
[gravity]
enabled = false
[trigger]
time_s = 0
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 50
polar_inertia_kg_m2 = 0.5
transverse_inertia_kg_m2 = 4
centre_of_mass_m = 0
[tdb.de]
position_m = 0
journal_radius_m = 0.04
clearance_m = 2e-4
[tdb.de.contact_law]
bearing_stiffness_N_per_m = 1e8
bearing_damping_N_s_per_m = 100
ribbon_stiffness_N_per_m = 5e6
ribbon_damping_N_s_per_m = 50
ribbon_crushing_m = 1e-4
[tdb.de.spin]
inertia_kg_m2 = 2e-3
drag_torque_N_m = 0.02
)";

double RaceSpeedAfter(const std::vector<std::string>& overrides, double w0, double duration_s) {
  const Model model = BuildModel(LoadConfigFromString(kRig, "race.toml", overrides).params);
  Simulator sim(model);
  State s = sim.InitialState();
  const int race = model.tdb_state_offset[0];  // the contact-law TDB's state: its race speed
  s.y(race) = w0;
  const auto steps = std::llround(duration_s / model.params.simulation.step_s);
  for (long long i = 0; i < steps; ++i) {
    EXPECT_EQ(sim.Step(&s, ControlInput::PowerOff()), StepStatus::kOk);
  }
  return s.y(race);
}

// I W' = -Td u / sqrt(1 + u^2), u = k W: sqrt(1 + u^2)/u du = -(Td k / I) dt, and
// F(u) = sqrt(1 + u^2) + ln(u / (1 + sqrt(1 + u^2))) is its antiderivative, so
// F(u(t)) = F(u0) - Td k t / I; F increases with u, so bisection finds u(t).
double ClosedFormRaceSpeed(double k, double w0, double t) {
  const auto f = [](double u) {
    const double s = std::sqrt(1.0 + u * u);
    return s + std::log(u / (1.0 + s));
  };
  const double target = f(k * w0) - 0.02 * k * t / 2e-3;
  double lo = 1e-300, hi = k * w0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) / k;
}

TEST(RaceDragRegularisation, CoastingRaceFollowsTheClosedForm) {
  const double k = 0.5, w0 = 10.0, t = 0.9;
  const double expected = ClosedFormRaceSpeed(k, w0, t);
  ASSERT_LT(expected * k, 1.0);  // it ends inside the regularised band, where k matters
  const double w = RaceSpeedAfter({"tdb.de.spin.drag_regularisation_s_per_rad=0.5"}, w0, t);
  EXPECT_NEAR(w / expected, 1.0, 1e-8);
  // Without the key the same race follows the friction's scale, vref Rir = 4.02 s/rad.
  const double shared = RaceSpeedAfter({}, w0, t);
  EXPECT_NEAR(shared / ClosedFormRaceSpeed(100.0 * 0.0402, w0, t), 1.0, 1e-8);
  EXPECT_GT(std::abs(shared / w - 1.0), 0.1);
}

TEST(RaceDragRegularisation, AbsentKeyIsTheFrictionScale) {
  const ModelParams p = LoadConfigFromString(kRig, "race.toml").params;
  EXPECT_EQ(p.tdbs[0].spin.drag_regularisation_s_per_rad, 0.0);
  const ModelParams set =
      LoadConfigFromString(kRig, "race.toml", {"tdb.de.spin.drag_regularisation_s_per_rad=3"})
          .params;
  EXPECT_EQ(set.tdbs[0].spin.drag_regularisation_s_per_rad, 3.0);
}

std::string ErrorOf(const std::string& value) {
  std::string text = kRig + "drag_regularisation_s_per_rad = " + value + "\n";
  try {
    LoadConfigFromString(text, "race.toml");
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "loaded without a ConfigError";
  return {};
}

TEST(RaceDragRegularisation, KeyMustBePositiveAndFinite) {
  // The key is appended on the line after kRig's last.
  const auto line = 1 + std::count(kRig.begin(), kRig.end(), '\n');
  for (const char* value : {"0", "-1", "inf", "nan", "\"fast\""}) {
    const std::string message = ErrorOf(value);
    EXPECT_THAT(message, ::testing::StartsWith("race.toml:" + std::to_string(line) + ":")) << value;
    EXPECT_THAT(message, HasSubstr("'tdb.de.spin.drag_regularisation_s_per_rad'")) << value;
    EXPECT_THAT(message, HasSubstr("expected a positive number (s/rad)")) << value;
    EXPECT_THAT(message, HasSubstr(std::string("found ") + value)) << value;
  }
}

}  // namespace
}  // namespace ambdrop::race_drag_regularisation_test
