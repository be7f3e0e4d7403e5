// Seed 004 (Zhu & Zhang, Fig. 5(a)): rotor drop at 12 000 rpm onto auxiliary bearings whose house
// sits on a metal rubber ring (metal_rubber_ring.toml) or is rigidly mounted (rigid_mount.toml),
// through the case `ambdrop validate` runs (tools/validation/seed004_cases.cpp). The recommended
// ring, Krr = 1e6 N/m with Crr = 1e4 N s/m, gives a lower peak rotor / inner-race impact force
// over the 0.2 s after the drop than the rigid mount and than its neighbours on the decade grid
// (Krr 1e5, 1e7 at Crr 1e4; Crr 1e3, a known failure, and 1e5 at Krr 1e6).
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "tools/validation/validation_cases.hpp"
#include "validation_asserts.hpp"

namespace ambdrop::seed004_validation_test {
namespace {

using Seed004 = testing::ValidationCaseTest<&Seed004MetalRubberRing>;

// The neighbour below the recommended damping, Crr = 1e3 N s/m, is asserted on its own.
constexpr std::string_view kLowerDamping = "vs Crr 1e+03";

TEST_F(Seed004, RecommendedRingBeatsTheRigidMountAndItsGridNeighbours) {
  std::vector<ValidationCheck> checks;
  for (const ValidationCheck& c : About("peak impact, recommended ring vs")) {
    if (c.quantity.find(kLowerDamping) == std::string::npos) checks.push_back(c);
  }
  testing::AssertChecks(checks, 4);
}

TEST_F(Seed004, RecommendedRingBeatsLowerRingDamping) {
  testing::AssertChecks(About(kLowerDamping), 1);
}

}  // namespace
}  // namespace ambdrop::seed004_validation_test
