#pragma once

namespace ambdrop {

/// Process exit codes of the ambdrop tool, so that scripts can tell what went wrong.
enum ExitCode : int {
  kExitOk = 0,
  kExitError = 1,      ///< I/O failure or an unexpected internal error
  kExitConfig = 2,     ///< the config (or a --set override) is invalid, or no model can be built
  kExitRunFailed = 3,  ///< the simulation diverged; partial outputs were written
  kExitExpectationFailed = 4,  ///< a scenario ran, and an outcome it expects did not happen
  kExitUsage = 64,             ///< bad command line (EX_USAGE of sysexits.h)
};

}  // namespace ambdrop
