// The step with 4-DOF TDBs (Jarroux 2019 models #2 and #3, both bearing laws) is allocation-free
// and deterministic: zero heap allocations over 20 000 steps through the drop, and bit-identical
// states on a repeated run and from a copied state.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "drop_step_checks.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::four_dof_step_test {
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

TEST(FourDofStep, NoHeapAllocationThroughTheDrop) {
  for (const Variant& v : Variants()) {
    SCOPED_TRACE(std::string(v.config) + (v.overrides.empty() ? "" : " " + v.overrides[0]));
    testing::ExpectDropAllocatesNothing(Rig(v));
  }
}

TEST(FourDofStep, RepeatedRunsAreBitIdentical) {
  for (const Variant& v : Variants()) {
    SCOPED_TRACE(v.config);
    testing::ExpectDropBitIdentical(Rig(v));
  }
}

TEST(FourDofStep, StateHoldsTheRacesAndTheDahlForces) {
  // 2 x 12 modes, spin and angle, then per TDB 9 states (Kelvin-Voigt) or 11 (Dahl).
  EXPECT_EQ(Rig(Variants()[0]).state_size, 2 * 12 + 2 + 2 * 9);
  EXPECT_EQ(Rig(Variants()[2]).state_size, 2 * 12 + 2 + 2 * 11);
}

}  // namespace
}  // namespace ambdrop::four_dof_step_test
