#pragma once
#include <string>
#include <vector>

namespace ambdrop {

struct CanExportOptions {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string header_path;  ///< "": no header
  std::string dbc_path;     ///< "": no DBC
};

/// `ambdrop can-export CONFIG --header FILE --dbc FILE`: the client kit's CAN files from the
/// config's [can] frame map (tools/cli/can_kit_files.hpp). Returns an ExitCode (exit_codes.hpp).
int RunCanExportCommand(const CanExportOptions& options);

}  // namespace ambdrop
