// The "equilibrium" start of a rotor under the in-process controller is the controller's own
// static equilibrium (rt_core/levitated_start.hpp): a controller holds its sensors' readings at
// the set point, so with a sensor offset (reading = gain x + offset) the rotor rests where
// x = -offset / gain, and the controller's integrators carry the currents that hold it there.
// Started there, nothing moves: that is what an equilibrium is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/replay_run.hpp"
#include "controller_if/loop/run_record.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"

namespace ambdrop::levitated_start_test {
namespace {

// The truth generator's rigid rig (tests/truth/rigid_rotor_a.toml): electromagnet AMBs, a
// Tustin PID section with a computation delay of one sample, sensors not at the AMBs. Run over
// its levitated 0.1 s (the power fails at 0.1 s).
ModelParams RigidRig(std::vector<std::string> overrides, bool exact_sensors = true) {
  std::vector<std::string> all = {"simulation.duration_s=0.1"};
  if (exact_sensors) {
    // Without noise and quantisation the equilibrium is tested exactly; with them the
    // quantisation alone makes a limit cycle of half a step (0.05 um), offset or not.
    for (const std::string s : {"nde", "de"}) {
      all.push_back("sensor." + s + ".noise.enabled=false");
      all.push_back("sensor." + s + ".quantisation_m=0");
    }
  }
  all.insert(all.end(), overrides.begin(), overrides.end());
  return LoadConfig(std::string(AMBDROP_SOURCE_DIR) + "/tests/truth/rigid_rotor_a.toml", all)
      .params;
}

/// Keeps what the run observed and what the controller read.
class RunLog final : public RunRecorder {
 public:
  RecordedRun run;
  std::vector<Observation> observed;
  void OnStart(const RecordedStart& start) noexcept override { run.start = start; }
  void OnInput(const RecordedInput& in) noexcept override { run.inputs.push_back(in); }
  void OnPower(const RecordedPower& power) noexcept override { run.power.push_back(power); }
  void OnSensors(const RecordedSensors& s) noexcept override { readings.push_back(s); }
  void OnState(const State&, const Observation& o) noexcept override { observed.push_back(o); }
  std::vector<RecordedSensors> readings;
};

struct Levitated {
  RunLog log;
  State final_state;
  /// Largest distance of each sensor plane (x, y) from where it started.
  double max_motion_m = 0.0;
  /// Largest |reading| the controller read, over every sensor axis and sample.
  double max_reading_m = 0.0;
};

Levitated RunLevitated(const ModelParams& params) {
  const Model model = BuildModel(params);
  Levitated out;
  const OfflineRunResult r = RunOffline(model, {}, {}, &out.log);
  EXPECT_EQ(r.status, StepStatus::kOk) << r.failure_message;
  out.final_state = r.final_state;
  const Observation& start = out.log.observed.front();
  for (const Observation& o : out.log.observed) {
    for (std::size_t s = 0; s < params.sensors.size(); ++s) {
      for (int axis = 0; axis < 2; ++axis) {
        out.max_motion_m = std::max(out.max_motion_m,
                                    std::abs(o.sensor_xy_m[s][axis] - start.sensor_xy_m[s][axis]));
      }
    }
  }
  for (const RecordedSensors& s : out.log.readings) {
    for (std::size_t i = 0; i < params.sensors.size(); ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        out.max_reading_m = std::max(out.max_reading_m, std::abs(s.readings.reading_m[i][axis]));
      }
    }
  }
  return out;
}

struct OffsetCase {
  std::vector<std::string> overrides;
  // Where each sensor plane must start: -offset / gain per axis, (nde x, nde y, de x, de y).
  std::array<double, 4> start_m;
};

TEST(EquilibriumStart, SensorOffsetsAndGainsStartAtTheSetPointAndNothingMoves) {
  const std::vector<OffsetCase> cases = {
      {{"sensor.nde.offset_x_m=2e-5"}, {-2e-5, 0.0, 0.0, 0.0}},
      {{"sensor.nde.offset_x_m=2e-5", "sensor.de.offset_y_m=-1.5e-5"}, {-2e-5, 0.0, 0.0, 1.5e-5}},
      {{"sensor.nde.gain_x=1.05", "sensor.nde.offset_x_m=2e-5"}, {-2e-5 / 1.05, 0.0, 0.0, 0.0}},
      {{"sensor.nde.gain=0.95", "sensor.nde.offset_m=1e-5", "sensor.de.gain_y=1.1",
        "sensor.de.offset_y_m=-3e-6"},
       {-1e-5 / 0.95, -1e-5 / 0.95, 0.0, 3e-6 / 1.1}},
  };
  for (const OffsetCase& c : cases) {
    SCOPED_TRACE(c.overrides.back());
    const Levitated run = RunLevitated(RigidRig(c.overrides));
    const Observation& start = run.log.observed.front();
    const ModelParams params = RigidRig(c.overrides);
    for (std::size_t s = 0; s < params.sensors.size(); ++s) {
      const int first = params.sensors[s].name == "nde" ? 0 : 2;
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_NEAR(start.sensor_xy_m[s][axis], c.start_m[first + axis], 1e-12)
            << params.sensors[s].name << " axis " << axis;
      }
    }
    // An equilibrium: over the levitated 0.1 s nothing moves and every reading stays at the
    // set point (the reading is what the rig's probe shows, offset included).
    EXPECT_LT(run.max_motion_m, 1e-10);
    EXPECT_LT(run.max_reading_m, 1e-12);
  }
}

// The rig as declared (noise 0.3 um, quantisation 0.1 um): it starts at its set point and stays
// there. The start at the magnetic centre overshot to -61 um at 5 ms and was still 0.9 um off
// the set point at 0.1 s.
TEST(EquilibriumStart, TheNoisyRigStaysAtItsSetPoint) {
  const ModelParams params = RigidRig({"sensor.nde.offset_x_m=2e-5"}, false);
  const Levitated run = RunLevitated(params);
  int nde = 0;
  while (params.sensors[nde].name != "nde") ++nde;
  double worst = 0.0, late_sum = 0.0;
  int late = 0;
  for (const Observation& o : run.log.observed) {
    const double off_set_point = o.sensor_xy_m[nde][0] + 2e-5;
    worst = std::max(worst, std::abs(off_set_point));
    if (o.time_s >= 0.05) {
      late_sum += off_set_point;
      ++late;
    }
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(std::abs(late_sum / late), 0.1e-6);
}

// Without the gravity feedforward the integrators hold the weight from the first sample: the
// rotor does not sag at the start (it fell by 50 um and came back).
TEST(EquilibriumStart, IntegratorsHoldTheWeightWithoutFeedforward) {
  const Levitated run = RunLevitated(RigidRig({"controller.linear.gravity_feedforward=false"}));
  EXPECT_LT(run.max_motion_m, 1e-10);
  EXPECT_LT(run.max_reading_m, 1e-12);
}

// A controller without integral action cannot hold the set point: with an offset its rotor rests
// where the proportional current balances the magnets' negative stiffness, off the set point,
// and starts there.
TEST(EquilibriumStart, AProportionalControllerStartsAtItsOwnEquilibrium) {
  const Levitated run = RunLevitated(
      RigidRig({"controller.linear.sections[0].ki_per_s=0", "sensor.nde.offset_x_m=2e-5"}));
  EXPECT_LT(run.max_motion_m, 1e-10);
  EXPECT_GT(run.max_reading_m, 1e-6);  // not at the set point
}

// The flexible seed-000 rotor under its PID form (internal_pid) on electromagnets, sensors
// outboard of the AMBs: the offset moves the start by exactly -offset / gain at its sensor, and
// the run is the offset-free run shifted (the static sag between AMB and sensor planes settles
// in both alike).
TEST(EquilibriumStart, OnAFlexibleRotorAnOffsetOnlyShiftsTheRun) {
  std::vector<std::string> base = {"simulation.duration_s=0.1"};
  for (const std::string s : {"nde", "de"}) {
    base.push_back("sensor." + s + ".noise.enabled=false");
    base.push_back("sensor." + s + ".quantisation_m=0");
  }
  std::vector<std::string> offset = base;
  offset.push_back("sensor.nde.offset_x_m=2e-5");
  offset.push_back("sensor.de.offset_y_m=-1e-5");
  const ModelParams plain_params = testing::LoadTestConfig("jarroux2019_industrial_pid.toml", base);
  const Levitated plain = RunLevitated(plain_params);
  const Levitated shifted =
      RunLevitated(testing::LoadTestConfig("jarroux2019_industrial_pid.toml", offset));
  ASSERT_EQ(plain.log.observed.size(), shifted.log.observed.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < plain.log.observed.size(); ++i) {
    for (std::size_t s = 0; s < plain_params.sensors.size(); ++s) {
      const bool nde = plain_params.sensors[s].name == "nde";
      const std::array<double, 2> expected =
          nde ? std::array<double, 2>{-2e-5, 0.0} : std::array<double, 2>{0.0, 1e-5};
      for (int axis = 0; axis < 2; ++axis) {
        const double shift = shifted.log.observed[i].sensor_xy_m[s][axis] -
                             plain.log.observed[i].sensor_xy_m[s][axis];
        if (i == 0) {
          EXPECT_NEAR(shift, expected[axis], 1e-12);
        }
        worst = std::max(worst, std::abs(shift - expected[axis]));
      }
    }
  }
  EXPECT_LT(worst, 5e-9);
}

// A record of a run with an offset replays bit for bit: the replay starts where the run did.
TEST(EquilibriumStart, ARunWithAnOffsetReplaysBitForBit) {
  const ModelParams params =
      RigidRig({"sensor.nde.offset_x_m=2e-5", "simulation.duration_s=0.12"}, false);
  const Model model = BuildModel(params);
  RunLog log;
  const OfflineRunResult live = RunOffline(model, {}, {}, &log);
  ASSERT_EQ(live.status, StepStatus::kOk);
  log.run.end_step = live.steps;
  const ReplayResult replay = ReplayRun(model, log.run, {}, {}, {}, nullptr);
  ASSERT_EQ(replay.steps, live.steps);
  EXPECT_TRUE(replay.final_state.y == live.final_state.y);
}

// Rigs whose sensors read no offset and whose feedforward carries the load keep the reference
// start (their golden trajectory hashes hold).
TEST(EquilibriumStart, EveryRigWithoutOffsetsKeepsTheReferenceStart) {
  for (const std::string& rig : testing::RigConfigFiles()) {
    EXPECT_FALSE(BuildModel(testing::LoadTestConfig(rig)).levitated.moved) << rig;
  }
  EXPECT_FALSE(BuildModel(RigidRig({})).levitated.moved);
  // An offset under a rig that starts centred, or on a rig without a controller, moves nothing.
  EXPECT_FALSE(BuildModel(RigidRig({"sensor.nde.offset_x_m=2e-5",
                                    "simulation.initial_position=\"centred\""}))
                   .levitated.moved);
  EXPECT_TRUE(BuildModel(RigidRig({"sensor.nde.offset_x_m=2e-5"})).levitated.moved);
}

}  // namespace
}  // namespace ambdrop::levitated_start_test
