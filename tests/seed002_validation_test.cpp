// Chen, Liu, Yuliane, Kuan (ITRI) 2019 (seed 002), Sec. IV: the 32 kg flexible rotor of
// configs/chen_itri_flexible.toml dropped at 18 000, 14 000 and 10 000 rpm onto its two
// discrete-ball TDBs, 0.2 s after the drop, through the case `ambdrop validate` runs
// (tools/validation/seed002_cases.cpp):
//  - "the orbit and the rotor responses are less than critical clearance of 2e-4 m" (the
//    paper's maxima are 1.0-1.2e-4 m), past the 1e-4 m air gap, at every speed;
//  - with the support Ks = 5e8 N/m, Cs = 27 900 N s/m (Fig. 19) the contact forces after 0.1 s
//    are lower than without (Fig. 12), at 18 000 rpm;
//  - peak contact forces 2.3e4 / 2.35e4 N (front / rear) at 18 000 rpm, 2.25e4 / 2.15e4 N at
//    14 000 (the text says 15 000 once) and 2.1e4 / 1.9e4 N at 10 000, each within 25 %, and
//    falling with the speed; the medians over 8 unbalance phases, which the paper does not give
//    (the rear at 14 000 and both at 10 000 rpm are known failures).
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "tools/validation/validation_cases.hpp"
#include "validation_asserts.hpp"

namespace ambdrop::seed002_validation_test {
namespace {

using Seed002 = testing::ValidationCaseTest<&Seed002DropSpeeds>;

TEST_F(Seed002, DisplacementStaysBelowTheCriticalClearance) {
  testing::AssertChecks(About("max displacement"), 4);
}

TEST_F(Seed002, SupportLowersTheContactForcesAfterAFifthOfTheRun) {
  testing::AssertChecks(About("contact force after 0.1 s"), 1);
}

TEST_F(Seed002, PeakContactForcesMatchThePaper) {
  testing::AssertChecks(About("peak contact force"), 8);
}

}  // namespace
}  // namespace ambdrop::seed002_validation_test
