// Seed 000 (Jarroux 2019) against its published numbers, through the same cases `ambdrop
// validate` runs (tools/validation/seed000_cases.cpp):
//  - Table 3: dropped at 6500 rpm, the TDBs reach the rotor speed after 0.11 s (DE) and
//    0.129 s (NDE), measured; within 25 %, DE first.
//  - Sec. 6.1, drop at rest: models #1 (contact law) and #2 (4-DOF, Kelvin-Voigt ribbon) agree
//    on the first peak load and the first rebound within 15 %; model #3 (Dahl ribbon) rebounds
//    at least 30 % lower than #2, and within 20 % of #2 with the threshold cut 30x / 4x.
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted.
#include <gtest/gtest.h>

#include <string>

#include "test_configs.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

std::string ConfigsDir() {
  const std::string path = testing::ConfigPath("jarroux2019_industrial.toml");
  return path.substr(0, path.rfind('/'));
}

void Assert(const std::vector<ValidationCheck>& checks) {
  ASSERT_FALSE(checks.empty());
  std::string known;
  for (const ValidationCheck& c : checks) {
    std::printf("%-44s published %-24s ambdrop %-20s %s\n", c.quantity.c_str(), c.published.c_str(),
                c.ambdrop.c_str(), c.pass ? "pass" : "FAIL");
    if (!c.pass && !c.known_failure.empty()) {
      known += "\n  " + c.quantity + ": ambdrop " + c.ambdrop + ", published " + c.published;
      continue;
    }
    EXPECT_TRUE(c.pass) << c.case_name << ": " << c.quantity << ": published " << c.published
                        << ", ambdrop " << c.ambdrop << " (" << c.criterion << ")";
  }
  if (!known.empty() && !::testing::Test::HasFailure()) {
    GTEST_SKIP() << "known failures (issue 5):" << known;
  }
}

TEST(Seed000, Table3SpinUpTimesAt6500Rpm) {
  Assert(Seed000SpinUpTable3(ConfigsDir()));
}

TEST(Seed000, TdbModelsDropAtRest) {
  Assert(Seed000ModelsDropAtRest(ConfigsDir()));
}

}  // namespace
}  // namespace ambdrop
