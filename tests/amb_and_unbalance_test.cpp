// AMB force laws and unbalance forcing against closed-form results on a rigid rotor.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "controller_if/loop/offline_run.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::amb_and_unbalance_test {
namespace {

// Symmetric rigid rotor, centre of mass at 0.5 m, supports at 0.1 and 0.9 m.
ModelParams RigidRig() {
  ModelParams p;
  p.rotor.kind = RotorKind::kRigid;
  p.rotor.rigid = {50.0, 0.2, 2.0, 0.5};
  p.simulation.step_s = 5e-6;
  p.simulation.initial_position = InitialPosition::kCentred;
  p.trigger.enabled = false;
  return p;
}

TEST(Amb, LinearisedCurrentLawGivesTheStaticDeflection) {
  // f = ki i + ks u against a linear bearing k at each plane: u = ki i / (k - ks).
  ModelParams p = RigidRig();
  p.gravity.enabled = false;
  const double k = 2e6, ks = 5e5, ki = 200.0, i0 = 1.5;
  for (double z : {0.1, 0.9}) {
    p.bearings.push_back({"b", z, k, k, 2e3, 2e3});
    AmbParams a;
    a.name = "a";
    a.position_m = z;
    a.law = AmbForceLaw::kLinearisedCurrents;
    a.current_gain_N_per_A = ki;
    a.position_gain_N_per_m = ks;
    a.current_profile = {{0.0, 0.0, i0}};
    p.ambs.push_back(a);
  }
  SensorParams sensor;
  sensor.name = std::string(1, 's');
  sensor.position_m = 0.1;
  p.sensors.push_back(sensor);
  p.simulation.duration_s = 0.6;  // released centred; the transient decays as exp(-40 t)
  const Model model = BuildModel(p);
  Observation last;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) { last = o; });
  ASSERT_EQ(r.status, StepStatus::kOk);
  EXPECT_NEAR(last.sensor_xy_m[0][1], ki * i0 / (k - ks), 1e-9);
  EXPECT_NEAR(last.sensor_xy_m[0][0], 0.0, 1e-15);
}

TEST(Amb, GravityCompensationLevitatesOnTheMagneticCentre) {
  // Equivalent-law AMBs with integral action hold the flexible seed-000 rotor with zero static
  // deflection at the AMB planes, though its weight is not shared equally.
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial.toml");
  const Model model = BuildModel(p);
  Simulator sim(model);
  const State s = sim.InitialState();
  for (std::size_t a = 0; a < p.ambs.size(); ++a) {
    const Eigen::Vector2d xy = model.amb_shapes[a] * s.y.head(model.modes());
    EXPECT_NEAR(xy(1), 0.0, 1e-12) << p.ambs[a].name;
  }
  const double weight = model.rotor.mass_kg * 9.81;
  const double lift = model.amb_bias_force_N[0][1] + model.amb_bias_force_N[1][1];
  EXPECT_NEAR(lift, weight, 1e-6 * weight);
  // The coupling half sits at DE: the DE AMB carries more.
  const int de = p.ambs[0].name == "de" ? 0 : 1;
  EXPECT_GT(model.amb_bias_force_N[de][1], 0.5 * weight);
  // And it stays there: after 0.1 s levitated nothing has moved.
  State t = s;
  for (int i = 0; i < 20000; ++i) ASSERT_EQ(sim.Step(&t, ControlInput{}), StepStatus::kOk);
  EXPECT_LT((t.y.head(model.modes()) - s.y.head(model.modes())).norm(), 1e-12);
}

TEST(Unbalance, SteadyStateResponseMatchesTheAnalyticalAmplitude) {
  // Unbalance at the centre of mass on two equal supports: pure translation,
  // |x| = m e W^2 / |2k - M W^2 + i 2c W|.
  ModelParams p = RigidRig();
  p.gravity.enabled = false;
  const double k = 1e6, c = 500.0, me = 1e-4, spin = 300.0;
  for (double z : {0.1, 0.9}) p.bearings.push_back({"b", z, k, k, c, c});
  p.unbalances.push_back({"u", true, 0.5, 1e-2, me / 1e-2, 0.3});
  SensorParams sensor;
  sensor.name = std::string(1, 's');
  sensor.position_m = 0.5;
  p.sensors.push_back(sensor);
  p.simulation.spin_speed_rad_s = spin;
  p.simulation.duration_s = 1.5;  // transients decay with tau = M / c = 0.05 s
  const Model model = BuildModel(p);
  double peak_x = 0.0, peak_y = 0.0;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    if (o.time_s < 1.2) return;
    peak_x = std::max(peak_x, std::abs(o.sensor_xy_m[0][0]));
    peak_y = std::max(peak_y, std::abs(o.sensor_xy_m[0][1]));
  });
  ASSERT_EQ(r.status, StepStatus::kOk);
  const std::complex<double> dyn(2 * k - 50.0 * spin * spin, 2 * c * spin);
  const double amplitude = me * spin * spin / std::abs(dyn);
  EXPECT_NEAR(peak_x / amplitude, 1.0, 2e-3);
  EXPECT_NEAR(peak_y / amplitude, 1.0, 2e-3);
}

}  // namespace
}  // namespace ambdrop::amb_and_unbalance_test
