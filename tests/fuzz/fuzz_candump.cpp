// A candump -l log replayed on the PID rig's [can] map (tools/record/candump_record.hpp): it is
// read (malformed lines, times going back and frames after the end counted and skipped) or it is
// a std::runtime_error when nothing is usable; no undefined behaviour on any receive time.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_support.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "tools/record/candump_record.hpp"

namespace {

struct Rig {
  ambdrop::LoadedConfig config =
      ambdrop::LoadConfig(ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid_can.toml"));
  ambdrop::Model model = ambdrop::BuildModel(config.params);
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Rig rig;
  const std::string path = ambdrop::fuzz::InputFile(data, size, ".log");
  try {
    (void)ambdrop::ReadCandumpRecord(path, rig.model, *rig.config.can);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
