// A run record (tools/record/run_record_reader.hpp) and what `replay` and `fit` do with it:
// read (damage ends the reading with a warning; std::runtime_error only when nothing is usable),
// turned into a measured record as `fit --measured REC.lcm` does, and replayed on the PID rig
// for at most 2000 steps (a fuzzed end step must not make the replay run for ever).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "controller_if/loop/replay_run.hpp"
#include "fuzz_support.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "tools/fit/run_record_measurement.hpp"
#include "tools/record/run_record_reader.hpp"

namespace {

const ambdrop::Model& Rig() {
  static const ambdrop::Model model = ambdrop::BuildModel(
      ambdrop::LoadConfig(ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid.toml")).params);
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ambdrop::Model& model = Rig();
  const std::string path = ambdrop::fuzz::InputFile(data, size, ".lcm");
  ambdrop::RunRecordFile file;
  try {
    file = ambdrop::ReadRunRecord(path);
  } catch (const std::runtime_error&) {
    return 0;
  }
  try {
    (void)ambdrop::MeasurementFromRunRecord(file, model.params);
  } catch (const std::invalid_argument&) {
  }
  ambdrop::RecordedRun run = file.run;
  run.end_step = std::clamp<std::int64_t>(run.end_step, 0, 2000);
  (void)ambdrop::ReplayRun(model, run, {}, {});
  return 0;
}
