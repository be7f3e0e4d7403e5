// `--set` overrides (io/config/config_overrides.hpp) on the PID rig: each line of the input is one
// override; the config loads or the overrides are refused with a ConfigError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "io/config/config_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string rig =
      "base = \"" + ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid.toml") + "\"\n";
  std::vector<std::string> overrides;
  std::string line;
  for (std::size_t i = 0; i < size && overrides.size() < 8; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '\n') {
      overrides.push_back(line);
      line.clear();
    } else {
      line += c;
    }
  }
  if (!line.empty() && overrides.size() < 8) overrides.push_back(line);
  try {
    (void)ambdrop::LoadConfigFromString(rig, "fuzz.toml", overrides);
  } catch (const ambdrop::ConfigError&) {
  }
  return 0;
}
