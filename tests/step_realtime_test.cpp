// The step is allocation-free and deterministic: zero heap allocations over >= 10 000 steps
// (through the trigger, with contacts), and bit-identical states on a repeated run.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "malloc_guard.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

// Seed-000 rig with the drop early so contacts, friction and spin-up all happen in the window.
Model Rig() {
  return BuildModel(testing::LoadTestConfig(
      "jarroux2019_industrial.toml", {"trigger.time_s=0.005", "unbalance.coupling.enabled=true"}));
}

ControlInput InputAt(const Model& m, std::int64_t step) {
  return step < m.trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
}

TEST(Step, NoHeapAllocationOverTwentyThousandSteps) {
  const Model model = Rig();
  Simulator sim(model);
  State s = sim.InitialState();
  Observation obs;
  double peak = 0.0;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int i = 0; i < 20000; ++i) {
      if (sim.Step(&s, InputAt(model, s.step_index)) != StepStatus::kOk) break;
      sim.Observe(s, &obs);
      peak = std::max(peak, obs.tdb[0].normal_force_N);
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(s.step_index, 20000);
  EXPECT_GT(peak, 0.0);  // the window really contained contacts
  EXPECT_EQ(allocations, 0);
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
  const Model model = Rig();
  Simulator a(model), b(model);
  State sa = a.InitialState(), sb = b.InitialState();
  for (int i = 0; i < 20000; ++i) {
    ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
    ASSERT_EQ(b.Step(&sb, InputAt(model, sb.step_index)), StepStatus::kOk);
    ASSERT_EQ(std::memcmp(sa.y.data(), sb.y.data(), sizeof(double) * model.state_size), 0)
        << "step " << i;
  }
  // A copied state continues identically: copying the state copies the run.
  State copy = sa;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
    ASSERT_EQ(b.Step(&copy, InputAt(model, copy.step_index)), StepStatus::kOk);
  }
  EXPECT_EQ(std::memcmp(sa.y.data(), copy.y.data(), sizeof(double) * model.state_size), 0);
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
}  // namespace ambdrop
