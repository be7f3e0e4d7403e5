// A fuzzed [can] frame map (io/config/config_can.cpp, io/can/can_frame_map.cpp): the input is the
// body of the PID rig's [can] table. It builds a frame map or is a ConfigError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "io/config/config_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string head =
      "base = \"" + ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid.toml") + "\"\n[can]\n";
  try {
    (void)ambdrop::LoadConfigFromString(
        head + std::string(reinterpret_cast<const char*>(data), size), "fuzz_can.toml", {});
  } catch (const ambdrop::ConfigError&) {
  }
  return 0;
}
