// A measured record as it comes (io/files/measured_csv.hpp, io/files/measured_record_si.hpp): read
// against a [measurement] table with logger units (ms, um, mA, kN, rpm), converted to SI. Any bytes
// either read or are a MeasuredRecordError naming the file and line; nothing else escapes.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "fuzz_support.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/measured_record_si.hpp"

namespace {

const ambdrop::MeasurementParams& Measurement() {
  static const ambdrop::LoadedConfig config = ambdrop::LoadConfigFromString(
      "base = \"" + ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid.toml") + "\"\n" +
          R"([measurement]
sample_rate_Hz = 20000.0
trigger_time_s = 0.001
time_column = "time_ms"
time_unit = "ms"
[[measurement.channel]]
column = "x_nde"
quantity = "displacement"
sensor = "nde"
axis = "x"
unit = "um"
[[measurement.channel]]
column = "i_de_y"
quantity = "current"
amb = "de"
axis = "y"
unit = "mA"
window = "before_trigger"
[[measurement.channel]]
column = "f_de"
quantity = "tdb_normal_force"
tdb = "de"
unit = "kN"
[[measurement.channel]]
column = "w_rotor"
quantity = "rotor_speed"
unit = "rpm"
)",
      "fuzz_measurement.toml");
  return *config.measurement;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ambdrop::MeasurementParams& m = Measurement();
  const std::string path = ambdrop::fuzz::InputFile(data, size, ".csv");
  try {
    (void)ambdrop::ReadMeasuredRecord(path, m);
  } catch (const ambdrop::MeasuredRecordError&) {
  }
  return 0;
}
