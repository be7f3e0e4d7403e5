#pragma once
#include <string>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// The fit's predictions beside the record, in SI, as CSV text: `time_s`, then per channel
/// `<column>_measured`, `<column>_before`, `<column>_after` (the declared model and the model
/// with the chosen effects); a row per record row, empty where a value is not simulated (NaN).
/// For plotting and checking a fit with one's own tools (fit's DIR/prediction.csv).
std::string PredictionCsv(const MeasurementParams& measurement, const MeasuredRecord& record,
                          const SimulatedRecord& before, const SimulatedRecord& after);

}  // namespace ambdrop
