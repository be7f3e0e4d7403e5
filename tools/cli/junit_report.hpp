#pragma once
// JUnit XML, the test-report format CI servers (Jenkins, GitLab, GitHub's test reporters) read:
// one <testsuite> per run, one <testcase> per check, a <failure> for each that failed.
#include <filesystem>
#include <string>
#include <vector>

namespace ambdrop {

struct JunitCase {
  std::string classname;  ///< "hil.checks", "hil.scenario"
  std::string name;
  bool pass = true;
  std::string message;  ///< why it failed (the expected and the actual value)
};

/// The XML text of one suite.
std::string JunitXml(const std::string& suite, const std::vector<JunitCase>& cases, double time_s);

/// Writes it to `path` (throws std::runtime_error when the file cannot be written).
void WriteJunit(const std::filesystem::path& path, const std::string& suite,
                const std::vector<JunitCase>& cases, double time_s);

}  // namespace ambdrop
