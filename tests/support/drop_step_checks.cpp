#include "drop_step_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "malloc_guard.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop::testing {
namespace {

ControlInput InputAt(const Model& m, std::int64_t step) {
  return step < m.trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
}

bool SameBits(const Model& model, const State& a, const State& b) {
  return std::memcmp(a.y.data(), b.y.data(), sizeof(double) * model.state_size) == 0;
}

}  // namespace

void ExpectDropAllocatesNothing(const Model& model, int steps) {
  Simulator sim(model);
  State s = sim.InitialState();
  Observation obs;
  double peak = 0.0;
  std::int64_t allocations = 0;
  {
    MallocGuard guard;
    for (int i = 0; i < steps; ++i) {
      if (sim.Step(&s, InputAt(model, s.step_index)) != StepStatus::kOk) break;
      sim.Observe(s, &obs);
      for (const TdbForce& t : obs.tdb) peak = std::max(peak, t.normal_force_N);
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(s.step_index, steps);
  EXPECT_GT(peak, 0.0);  // the window really contained contacts
  EXPECT_EQ(allocations, 0);
}

void ExpectDropBitIdentical(const Model& model, int steps, int after_copy) {
  Simulator a(model), b(model);
  State sa = a.InitialState(), sb = b.InitialState();
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
    ASSERT_EQ(b.Step(&sb, InputAt(model, sb.step_index)), StepStatus::kOk);
    ASSERT_TRUE(SameBits(model, sa, sb)) << "step " << i;
  }
  // Copying the state copies the run.
  State copy = sa;
  for (int i = 0; i < after_copy; ++i) {
    ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
    ASSERT_EQ(b.Step(&copy, InputAt(model, copy.step_index)), StepStatus::kOk);
  }
  EXPECT_TRUE(SameBits(model, sa, copy));
}

}  // namespace ambdrop::testing
