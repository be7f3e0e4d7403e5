#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// The fit report's plots, as SVG files in `dir`: per channel, measured against the model
/// before and after the fit, and the residual over time; per sensor plane with both axes
/// measured, the orbit (the sensors sit next to the TDBs). Returns the file names written.
std::vector<std::string> WriteFitPlots(const std::filesystem::path& dir, const ModelParams& params,
                                       const MeasurementParams& measurement,
                                       const MeasuredRecord& record, const SimulatedRecord& before,
                                       const SimulatedRecord& after);

}  // namespace ambdrop
