// The step is allocation-free and deterministic: zero heap allocations over >= 10 000 steps
// (through the trigger, with contacts), and bit-identical states on a repeated run.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "drop_step_checks.hpp"
#include "malloc_guard.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::step_realtime_test {
namespace {

// Seed-000 rig with the drop early so contacts, friction and spin-up all happen in the window.
Model Rig() {
  return BuildModel(testing::LoadTestConfig(
      "jarroux2019_industrial.toml", {"trigger.time_s=0.005", "unbalance.coupling.enabled=true"}));
}

TEST(Step, NoHeapAllocationOverTwentyThousandSteps) {
  testing::ExpectDropAllocatesNothing(Rig());
}

TEST(Step, MallocGuardSeesAllocations) {
  if (!testing::MallocGuard::Available()) {
    GTEST_SKIP() << "sanitizer build: ASan owns malloc, so the allocation guard is compiled out";
  }
  // The guard itself must be able to fail.
  testing::MallocGuard guard;
  std::vector<double> v(1000);
  v[0] = 1.0;
  EXPECT_GT(guard.allocations(), 0);
}

TEST(Step, RepeatedRunsAreBitIdentical) {
  testing::ExpectDropBitIdentical(Rig());
}

TEST(Step, DivergenceIsReportedNotHidden) {
  ModelParams p = testing::LoadTestConfig(
      "jarroux2019_industrial.toml",
      {"simulation.step_s=2e-3", "simulation.output_interval_s=2e-3", "trigger.time_s=0.0"});
  const Model model = BuildModel(p);
  Simulator sim(model);
  State s = sim.InitialState();
  StepStatus status = StepStatus::kOk;
  const ControlInput off = ControlInput::PowerOff();
  for (int i = 0; i < 5000 && status == StepStatus::kOk; ++i) status = sim.Step(&s, off);
  EXPECT_NE(status, StepStatus::kOk);  // a 2 ms step cannot hold a 2e8 N/m contact
  EXPECT_EQ(s.faults.non_finite_state + s.faults.excursion_beyond_bound, 1);
}

}  // namespace
}  // namespace ambdrop::step_realtime_test
