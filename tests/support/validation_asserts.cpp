#include "validation_asserts.hpp"

#include <cstdio>
#include <cstdlib>

namespace ambdrop::testing {
namespace {

bool RunKnownFailures() {
  const char* run = std::getenv("AMBDROP_RUN_KNOWN_FAILURES");
  return run != nullptr && std::string(run) == "1";
}

}  // namespace

std::string ConfigsDir() {
  return std::string(AMBDROP_SOURCE_DIR) + "/configs";
}

bool IsRunCheck(const ValidationCheck& c) {
  return c.quantity.find("run to the end") != std::string::npos;
}

std::vector<ValidationCheck> ChecksAbout(const std::vector<ValidationCheck>& checks,
                                         std::string_view about) {
  std::vector<ValidationCheck> selected;
  for (const ValidationCheck& c : checks) {
    if (c.quantity.find(about) != std::string::npos || IsRunCheck(c)) selected.push_back(c);
  }
  return selected;
}

void AssertChecks(const std::vector<ValidationCheck>& checks, std::size_t expected) {
  ASSERT_FALSE(checks.empty());
  if (expected != 0) {
    std::size_t selected = 0;
    for (const ValidationCheck& c : checks) selected += IsRunCheck(c) ? 0 : 1;
    ASSERT_EQ(selected, expected) << "checks of the case about this test's quantity";
  }
  std::string known;
  for (const ValidationCheck& c : checks) {
    std::printf("%-44s published %-24s ambdrop %-26s %s\n", c.quantity.c_str(), c.published.c_str(),
                c.ambdrop.c_str(), c.pass ? "pass" : "FAIL");
    if (!c.pass && !c.known_failure.empty() && !RunKnownFailures()) {
      known += "\n  " + c.quantity + ": ambdrop " + c.ambdrop + ", published " + c.published +
               "\n    " + c.known_failure;
      continue;
    }
    EXPECT_TRUE(c.pass) << c.case_name << ": " << c.quantity << ": published " << c.published
                        << ", ambdrop " << c.ambdrop << " (" << c.criterion << ")";
  }
  if (!known.empty() && !::testing::Test::HasFailure()) {
    GTEST_SKIP() << "known failures:" << known << "\nSet AMBDROP_RUN_KNOWN_FAILURES=1 to run them.";
  }
}

}  // namespace ambdrop::testing
