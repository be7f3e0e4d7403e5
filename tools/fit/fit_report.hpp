#pragma once
// Step f of `ambdrop fit`: fit.json (what a program reads) and report.md with its plots (what
// a person reads).
#include <filesystem>
#include <string>
#include <vector>

#include "io/files/json_writer.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/fit_step.hpp"
#include "tools/fit/model_discrepancy.hpp"
#include "tools/fit/residuals.hpp"
#include "tools/fit/sensor_noise_colour.hpp"

namespace ambdrop {

struct FitOutcome {
  std::string config_path;
  std::string measured_path;
  ResidualReport before;
  ResidualReport after;
  const Selection* selection = nullptr;
  const FitStep* step = nullptr;  ///< may be null
  const std::vector<Effect>* library = nullptr;
  std::vector<const Effect*> chosen;  ///< in selection->chosen order
  double wall_time_s = 0.0;
  /// The declared model against the rig (tools/fit/model_discrepancy.hpp); may be null.
  const Discrepancy* discrepancy = nullptr;
  /// The record's displacement noise (FitResult::sensor_noise); may be null.
  const SensorNoise* sensor_noise = nullptr;
};

/// A Discrepancy as a JSON object (fit.json's `discrepancy`, shared.json's per record).
void DiscrepancyJson(JsonWriter& json, const Discrepancy& d);

/// fit.json: rms_before and rms_after (per channel and overall), the agreement limits (the
/// declared model's, and the one the chosen effects were judged by), chosen (effects with fitted
/// parameters, uncertainties and their config keys), candidates (every effect of the library;
/// those tried with their score, `"tried": false` for those not fitted: undecidable, or the
/// declared model already agrees), undecidable (effects no channel of the record can reveal),
/// verdict and reason.
std::string FitJson(const FitOutcome& outcome, const ModelParams& params,
                    const MeasurementParams& measurement);

/// report.md and its SVG plots in `dir`: measured vs model before and after, the residual over
/// time, and the journal orbit at each TDB.
void WriteFitReport(const std::filesystem::path& dir, const FitOutcome& outcome,
                    const ModelParams& params, const MeasurementParams& measurement,
                    const MeasuredRecord& record, const SimulatedRecord& before,
                    const SimulatedRecord& after);

}  // namespace ambdrop
