#pragma once
// What the seed validation tests share: they run the cases `ambdrop validate` runs
// (tools/validation/) and assert their checks. A check marked as a known failure (an open
// issue explains it) makes its test skip with that reason after every other check has been
// asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "tools/validation/validation_check.hpp"

namespace ambdrop::testing {

/// The source tree's configs/ folder.
std::string ConfigsDir();

/// A case's check that its runs reached their end (present only when one did not).
bool IsRunCheck(const ValidationCheck& check);

/// The checks whose quantity names `about`, and the failed-run check if any.
std::vector<ValidationCheck> ChecksAbout(const std::vector<ValidationCheck>& checks,
                                         std::string_view about);

/// Asserts every check; `expected` (if not 0) is how many are about the test's quantity, so a
/// renamed quantity cannot drop a check quietly. Skips with the known failures' reasons last.
void AssertChecks(const std::vector<ValidationCheck>& checks, std::size_t expected = 0);

/// A fixture that runs one validation case once for all the tests of the suite.
template <std::vector<ValidationCheck> (*RunCase)(const std::string& configs_dir)>
class ValidationCaseTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    checks_ = new std::vector<ValidationCheck>(RunCase(ConfigsDir()));
  }
  static void TearDownTestSuite() {
    delete checks_;
    checks_ = nullptr;
  }
  static const std::vector<ValidationCheck>& Checks() { return *checks_; }
  static std::vector<ValidationCheck> About(std::string_view about) {
    return ChecksAbout(*checks_, about);
  }

 private:
  static inline std::vector<ValidationCheck>* checks_ = nullptr;
};

}  // namespace ambdrop::testing
