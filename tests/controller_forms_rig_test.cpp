// The linear controller form on a rig: seed 000's industrial rotor
// (configs/jarroux2019_industrial_pid.toml) levitated by a PD + notch declared through --set,
// and the computation delay seen through the same ReferenceController every driver builds.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"

namespace ambdrop::controller_forms_rig_test {
namespace {

const std::vector<std::string> kPdNotch = {
    "controller.kind=internal_linear",
    "controller.linear.sections[0].kind=pid",
    "controller.linear.sections[0].kp=2.5",
    "controller.linear.sections[0].kd_s=2.5e-3",
    "controller.linear.sections[0].derivative_filter_s=7e-5",
    "controller.linear.sections[1].kind=notch",
    "controller.linear.sections[1].frequency_Hz=2000",
    "controller.linear.sections[1].pole_damping=0.3",
    "controller.linear.sections[1].prewarp_Hz=2000",
};

Model RigWith(std::vector<std::string> overrides) {
  overrides.insert(overrides.begin(), "simulation.duration_s=0.21");
  return BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml", overrides));
}

TEST(ControllerForms, PdWithNotchLevitatesTheIndustrialRotor) {
  for (const bool delayed : {false, true}) {
    std::vector<std::string> overrides = kPdNotch;
    if (delayed) {
      overrides.push_back("controller.delay_samples=1");
      overrides.push_back("controller.amplifier.enabled=true");
      overrides.push_back("controller.amplifier.bandwidth_Hz=1500");
    }
    const Model model = RigWith(overrides);
    double max_levitated_m = 0.0;
    const double trigger = model.params.trigger.time_s;
    const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
      if (o.time_s < trigger && o.time_s > 0.05) {
        for (int s = 0; s < 2; ++s) {
          max_levitated_m =
              std::max(max_levitated_m, std::hypot(o.sensor_xy_m[s][0], o.sensor_xy_m[s][1]));
        }
      }
    });
    ASSERT_EQ(r.status, StepStatus::kOk) << r.failure_message;
    // PD without an integrator: the offset is what the feedforward leaves, well inside the
    // 0.25 mm TDB clearance.
    EXPECT_LT(max_levitated_m, 10e-6) << (delayed ? "delayed and amplified" : "plain");
  }
}

TEST(ControllerForms, DelayShiftsTheCommandsByExactlyItsSamples) {
  const int d = 3;
  const Model plain = RigWith(kPdNotch);
  std::vector<std::string> overrides = kPdNotch;
  overrides.push_back("controller.delay_samples=" + std::to_string(d));
  const Model delayed = RigWith(overrides);
  const double period = 1.0 / plain.params.controller.rate_Hz;
  ReferenceController a(plain, period), b(delayed, period);
  ControlInput initial, in_a, in_b;
  a.Initial(&initial);
  std::vector<double> commands, applied;
  for (int k = 0; k < 50; ++k) {
    SensorReadings r{};
    r.reading_m[0][1] = 1e-6 * std::sin(0.3 * k);
    r.reading_m[1][0] = 2e-6 * std::cos(0.2 * k);
    a.Update(r, &in_a);
    b.Update(r, &in_b);
    commands.push_back(in_a.amb[0].current_A[1]);
    applied.push_back(in_b.amb[0].current_A[1]);
  }
  for (int k = 0; k < 50; ++k) {
    const double expected = k < d ? initial.amb[0].current_A[1] : commands[k - d];
    EXPECT_EQ(applied[k], expected) << k;
  }
}

// The amplifier is an analog loop: advanced at the physics step, the coil current between two
// controller samples is the first-order response to the held command, i(t) = c + (i0 - c)
// exp(-w t) (Franklin, Powell & Workman, 3rd ed., Sec. 4.3.3), at every step's end, and Update
// alone leaves it where it was.
TEST(ControllerForms, TheAmplifierFollowsItsCommandBetweenTheControllersSamples) {
  std::vector<std::string> overrides = kPdNotch;
  const Model plain = RigWith(overrides);
  overrides.push_back("controller.amplifier.enabled=true");
  overrides.push_back("controller.amplifier.bandwidth_Hz=1500");
  const Model amplified = RigWith(overrides);
  const double period = 1.0 / plain.params.controller.rate_Hz;
  constexpr int kSteps = 10;
  const double step = period / kSteps;
  ReferenceController command(plain, period);
  ReferenceController coil(amplified, period, step);
  ASSERT_TRUE(coil.advances_amplifier());
  ControlInput commanded, current;
  coil.Initial(&current);
  const double w = 2.0 * 3.14159265358979323846 * 1500.0;
  double coil_A = current.amb[0].current_A[1];  // the loop's state: the current at a step's end
  for (int k = 0; k < 5; ++k) {
    SensorReadings r{};
    r.reading_m[0][1] = 3e-6 * std::sin(0.7 * k);
    command.Update(r, &commanded);
    const double before = current.amb[0].current_A[1];
    coil.Update(r, &current);
    EXPECT_EQ(current.amb[0].current_A[1], before) << "sample " << k;
    const double c = commanded.amb[0].current_A[1];
    for (int j = 1; j <= kSteps; ++j) {
      coil.Advance(&current);
      const double expected = c + (coil_A - c) * std::exp(-w * step);
      coil_A = expected;
      EXPECT_NEAR(current.amb[0].current_A[1], expected, 1e-12 + 1e-12 * std::abs(c))
          << "sample " << k << " step " << j;
    }
  }
}

}  // namespace
}  // namespace ambdrop::controller_forms_rig_test
