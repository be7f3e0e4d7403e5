#pragma once
// A measured record as it comes (its own time column and units), read and converted to SI once,
// as the [measurement] table describes it (io/config/config_measurement.hpp): the time column
// scaled by time_unit, each channel's column by its unit or scale. Column names stay the record's
// own, so every later message names what the file calls them.
#include <filesystem>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"

namespace ambdrop {

/// Multiplies the time column by measurement.time_scale_s and each channel's column by its
/// scale. Columns no channel reads stay as written. A value that leaves the range of a double
/// (a scale of 1e300 on 1e10) is a MeasuredRecordError naming the column and row.
void ConvertRecordToSi(const MeasurementParams& measurement, MeasuredRecord* record);

/// ReadMeasuredCsv with the table's time column, then ConvertRecordToSi.
MeasuredRecord ReadMeasuredRecord(const std::filesystem::path& path,
                                  const MeasurementParams& measurement);

}  // namespace ambdrop
