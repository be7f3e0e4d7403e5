// The one step driver holds all of a run's mutable physics: the state, the power state with its
// power-loss law, the sensors' noise generators and delay lines, the input. A copy taken
// mid-run therefore goes on bit for bit like the original, through sensor noise, a trigger and
// a flux decay; and a step allocates nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "controller_if/loop/closed_loop_state.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"

namespace ambdrop::step_driver_test {
namespace {

// A profile-like source: a fixed command that moves with each sample taken (so that the
// sensors' noise reaches the physics), and the rig's scheduled failure.
struct TestHooks : StepHooks {
  const Model* model = nullptr;
  PowerEvent failure;
  std::int64_t samples = 0;
  double last_reading = 0.0;
  void OnSensors(StepDriver& d, std::int64_t) noexcept {
    ++samples;
    last_reading = d.readings().reading_m[0][1];
  }
  void PowerEvents(StepDriver& d, std::int64_t k) noexcept {
    if (k == model->trigger_step) d.ApplyPower(failure);
  }
  bool Command(StepDriver& d, std::int64_t) noexcept {
    for (std::size_t a = 0; a < model->params.ambs.size(); ++a) {
      d.command()[a] = {0.0, -2e3 * last_reading};
    }
    return true;
  }
};

Model Rig() {
  return BuildModel(testing::LoadTestConfig(
      "jarroux2019_industrial_pid.toml",
      {"simulation.duration_s=0.02", "trigger.time_s=0.005", "amb.nde.flux_decay.enabled=true",
       "amb.de.flux_decay.enabled=true"}));
}

bool SameBits(const State& a, const State& b) {
  return a.step_index == b.step_index && a.y.size() == b.y.size() &&
         std::memcmp(a.y.data(), b.y.data(), sizeof(double) * a.y.size()) == 0;
}

TEST(StepDriver, ACopyTakenMidRunGoesOnBitForBit) {
  const Model model = Rig();
  ASSERT_TRUE(model.params.sensors[0].noise.enabled);
  StepDriver driver(model, 10);
  TestHooks hooks;
  hooks.model = &model;
  hooks.failure = ScheduledFailure(model);
  driver.SetInput(StaticLoadInput(model));
  driver.Start(driver.sim().InitialState(StaticLoadInput(model)));
  // Copy before the trigger, with noise drawn and the delay lines full.
  while (driver.state().step_index < model.trigger_step / 2) ASSERT_TRUE(driver.Step(hooks));
  StepDriver copy = driver;
  TestHooks copy_hooks = hooks;
  while (driver.state().step_index < model.total_steps) {
    ASSERT_TRUE(driver.Step(hooks));
    ASSERT_TRUE(copy.Step(copy_hooks));
    ASSERT_TRUE(SameBits(driver.state(), copy.state())) << "step " << driver.state().step_index;
    ASSERT_EQ(std::memcmp(&driver.input(), &copy.input(), sizeof(ControlInput)), 0);
  }
  EXPECT_EQ(hooks.samples, copy_hooks.samples);
  EXPECT_GT(hooks.samples, model.total_steps / 10 - 2);
  // The decay ran: the unpowered force scale has fallen well below one.
  EXPECT_LT(driver.input().amb[0].force_scale[1], 0.01);
}

// The in-process controller's state is part of the run: a ClosedLoopState copied mid-run (the
// driver and the PID's integrators and filters together) goes on bit for bit with its original
// through the trigger, the sensors' noise feeding back through the controller.
struct ControllerHooks : StepHooks {
  const Model* model = nullptr;
  ReferenceController* controller = nullptr;
  std::int64_t substeps = 1;
  PowerEvent failure;
  ControlInput out;
  void PowerEvents(StepDriver& d, std::int64_t k) noexcept {
    if (k == model->trigger_step) d.ApplyPower(failure);
  }
  bool Command(StepDriver& d, std::int64_t k) noexcept {
    if (k % substeps != 0) return true;
    controller->Update(d.readings(), &out);
    for (std::size_t a = 0; a < model->params.ambs.size(); ++a) {
      d.command()[a] = out.amb[a].current_A;
    }
    return true;
  }
};

TEST(ClosedLoopState, ACopyTakenMidRunGoesOnBitForBitControllerIncluded) {
  const Model model = Rig();
  const std::int64_t substeps = ControllerSubsteps(model);
  ClosedLoopState run(model, substeps, true);
  ControlInput input;
  run.controller->Initial(&input);
  run.driver.SetInput(input);
  run.driver.Start(run.driver.sim().InitialState(StaticLoadInput(model)));
  ControllerHooks hooks;
  hooks.model = &model;
  hooks.substeps = substeps;
  hooks.failure = ScheduledFailure(model);
  hooks.controller = &*run.controller;
  while (run.driver.state().step_index < model.trigger_step / 2) {
    ASSERT_TRUE(run.driver.Step(hooks));
  }
  // Levitated by the controller before the trigger: the journal within 2 % of the clearance.
  const double clearance = model.params.tdbs[0].clearance_m;
  Observation o;
  run.driver.sim().Observe(run.driver.state(), &o);
  EXPECT_LT(std::abs(o.tdb_journal_xy_m[0][1]), 0.02 * clearance);
  ClosedLoopState copy = run;
  ControllerHooks copy_hooks = hooks;
  copy_hooks.controller = &*copy.controller;
  while (run.driver.state().step_index < model.total_steps) {
    ASSERT_TRUE(run.driver.Step(hooks));
    ASSERT_TRUE(copy.driver.Step(copy_hooks));
    ASSERT_TRUE(SameBits(run.driver.state(), copy.driver.state()))
        << "step " << run.driver.state().step_index;
  }
  // 15 ms after the trigger the rotor lies on its TDB (free fall alone takes 7 ms to the
  // clearance).
  run.driver.sim().Observe(run.driver.state(), &o);
  EXPECT_LT(o.tdb_journal_xy_m[0][1], -0.5 * clearance);
}

TEST(StepDriver, StepsDoNotAllocate) {
  const Model model = Rig();
  StepDriver driver(model, 10);
  TestHooks hooks;
  hooks.model = &model;
  hooks.failure = ScheduledFailure(model);
  driver.SetInput(StaticLoadInput(model));
  driver.Start(driver.sim().InitialState(StaticLoadInput(model)));
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int k = 0; k < 3000; ++k) {
      if (!driver.Step(hooks)) break;
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(driver.state().step_index, 3000);  // through the trigger at step 1000
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace ambdrop::step_driver_test
