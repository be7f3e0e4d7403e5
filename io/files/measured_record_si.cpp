#include "io/files/measured_record_si.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ambdrop {

void ConvertRecordToSi(const MeasurementParams& m, MeasuredRecord* record) {
  // Exact for SI records: a scale of 1 leaves every value's bits alone.
  if (m.time_scale_s != 1.0) {
    for (double& t : record->time_s) t *= m.time_scale_s;
  }
  for (const MeasurementChannel& ch : m.channels) {
    const int c = record->Column(ch.column);
    if (c < 0 || ch.scale == 1.0) continue;
    std::vector<double>& values = record->values[static_cast<std::size_t>(c)];
    for (std::size_t row = 0; row < values.size(); ++row) {
      values[row] *= ch.scale;
      if (!std::isfinite(values[row])) {
        throw MeasuredRecordError(
            fmt::format("{}: column '{}', data row {}: the value times its scale {} leaves the "
                        "range of a double",
                        record->source, ch.column, row + 1, ch.scale));
      }
    }
  }
}

MeasuredRecord ReadMeasuredRecord(const std::filesystem::path& path, const MeasurementParams& m) {
  MeasuredRecord record = ReadMeasuredCsv(path, m.time_column, m.time_unit);
  ConvertRecordToSi(m, &record);
  return record;
}

}  // namespace ambdrop
