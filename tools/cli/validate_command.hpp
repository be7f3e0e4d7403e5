#pragma once
#include <string>
#include <vector>

namespace ambdrop {

struct ValidateOptions {
  std::string out_dir = "out";
  std::string configs_dir = "configs";  ///< where the seed rigs' configs are
  std::vector<std::string> cases;       ///< case names to run; empty: all
  /// Checks marked as known failures (an open issue explains each) do not fail the exit code;
  /// they are still printed and written as failed.
  bool allow_known_failures = false;
  bool quiet = false;
};

/// `ambdrop validate`: runs every seed case (tools/validation/validation_cases.hpp), prints one
/// table (case, quantity, published, ambdrop, deviation, pass/fail) and writes
/// DIR/validate.json: one object per check with case, quantity, published, ambdrop, deviation
/// and pass. Exits 1 when a check fails (known failures too, unless allow_known_failures).
int RunValidateCommand(const ValidateOptions& options);

}  // namespace ambdrop
