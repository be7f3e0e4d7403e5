// Seed 000 (Jarroux 2019) against its published numbers, through the same cases `ambdrop
// validate` runs (tools/validation/seed000_cases.cpp):
//  - Table 3: dropped at 6500 rpm, the TDBs reach the rotor speed after 0.11 s (DE) and
//    0.129 s (NDE), measured; within 25 %, DE first.
//  - Sec. 6.1, drop at rest: models #1 (contact law) and #2 (4-DOF, Kelvin-Voigt ribbon) agree
//    on the first peak load and the first rebound within 15 %; model #3 (Dahl ribbon) rebounds
//    at least 30 % lower than #2, and within 20 % of #2 with the threshold cut 30x / 4x.
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <string>

#include "tools/validation/validation_cases.hpp"
#include "validation_asserts.hpp"

namespace ambdrop::seed000_validation_test {
namespace {

TEST(Seed000, Table3SpinUpTimesAt6500Rpm) {
  testing::AssertChecks(Seed000SpinUpTable3(testing::ConfigsDir()));
}

TEST(Seed000, TdbModelsDropAtRest) {
  testing::AssertChecks(Seed000ModelsDropAtRest(testing::ConfigsDir()));
}

}  // namespace
}  // namespace ambdrop::seed000_validation_test
