// The step with 4-DOF TDBs (Jarroux 2019 models #2 and #3, both bearing laws) is allocation-free
// and deterministic: zero heap allocations over 20 000 steps through the drop, and bit-identical
// states on a repeated run and from a copied state.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "malloc_guard.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

struct Variant {
  const char* config;
  std::vector<std::string> overrides;
};

std::vector<Variant> Variants() {
  return {{"jarroux2019_industrial_model2.toml", {}},
          {"jarroux2019_industrial_model2.toml",
           {"tdb.de.four_dof.bearing_law=\"hertz\"", "tdb.nde.four_dof.bearing_law=\"hertz\""}},
          {"jarroux2019_industrial_model3.toml", {}},
          {"jarroux2019_industrial_model3.toml",
           {"tdb.de.four_dof.bearing_law=\"hertz\"", "tdb.nde.four_dof.bearing_law=\"hertz\"",
            "tdb.de.misalignment.enabled=true", "tdb.de.misalignment.y_m=-2e-5"}}};
}

// The drop early, spinning, with the unbalance: contacts, friction, spin-up and ribbon all act.
Model Rig(const Variant& v) {
  std::vector<std::string> overrides = {"trigger.time_s=0.005", "unbalance.coupling.enabled=true"};
  overrides.insert(overrides.end(), v.overrides.begin(), v.overrides.end());
  return BuildModel(testing::LoadTestConfig(v.config, overrides));
}

ControlInput InputAt(const Model& m, std::int64_t step) {
  return step < m.trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
}

TEST(FourDofStep, NoHeapAllocationThroughTheDrop) {
  for (const Variant& v : Variants()) {
    SCOPED_TRACE(std::string(v.config) + (v.overrides.empty() ? "" : " " + v.overrides[0]));
    const Model model = Rig(v);
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
}

TEST(FourDofStep, RepeatedRunsAreBitIdentical) {
  for (const Variant& v : Variants()) {
    SCOPED_TRACE(v.config);
    const Model model = Rig(v);
    Simulator a(model), b(model);
    State sa = a.InitialState(), sb = b.InitialState();
    for (int i = 0; i < 20000; ++i) {
      ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
      ASSERT_EQ(b.Step(&sb, InputAt(model, sb.step_index)), StepStatus::kOk);
      ASSERT_EQ(std::memcmp(sa.y.data(), sb.y.data(), sizeof(double) * model.state_size), 0)
          << "step " << i;
    }
    State copy = sa;
    for (int i = 0; i < 1000; ++i) {
      ASSERT_EQ(a.Step(&sa, InputAt(model, sa.step_index)), StepStatus::kOk);
      ASSERT_EQ(b.Step(&copy, InputAt(model, copy.step_index)), StepStatus::kOk);
    }
    EXPECT_EQ(std::memcmp(sa.y.data(), copy.y.data(), sizeof(double) * model.state_size), 0);
  }
}

TEST(FourDofStep, StateHoldsTheRacesAndTheDahlForces) {
  // 2 x 12 modes, spin and angle, then per TDB 9 states (Kelvin-Voigt) or 11 (Dahl).
  EXPECT_EQ(Rig(Variants()[0]).state_size, 2 * 12 + 2 + 2 * 9);
  EXPECT_EQ(Rig(Variants()[2]).state_size, 2 * 12 + 2 + 2 * 11);
}

}  // namespace
}  // namespace ambdrop
