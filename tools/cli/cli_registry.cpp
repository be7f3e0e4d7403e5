#include "tools/cli/cli_registry.hpp"

#include <cmath>
#include <cstdlib>

namespace ambdrop {

CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides) {
  return command
      ->add_option("--set", *overrides,
                   "Override a config value, e.g. --set simulation.duration_s=0.3 (TOML value "
                   "syntax; repeatable, applied in order)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

const CLI::Validator kFinite(
    [](std::string& text) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
        return "expected a finite number, found " + text;
      }
      return std::string();
    },
    "FINITE");

}  // namespace ambdrop
