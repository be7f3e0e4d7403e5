#pragma once
// `ambdrop fit` without its files: the declared model held against a record, every effect of
// the library tried, the chosen ones fitted, and the residual before and after.
#include <memory>
#include <string>
#include <vector>

#include "tools/fit/effect_selection.hpp"
#include "tools/fit/fit_report.hpp"
#include "tools/fit/fit_step.hpp"

namespace ambdrop {

struct FitRecordOptions {
  RecordRunOptions run;
  SelectionRules rules;
  /// Let the fit run at a coarser step where the record cannot tell (ChooseFitStep); false:
  /// the config's step (or run.step_s).
  bool choose_step = true;
};

struct FitResult {
  std::vector<Effect> library;
  FitStep step;  ///< the step every run of the fit took, and why
  Selection selection;
  std::vector<const Effect*> chosen;  ///< into library, in selection.chosen order
  /// The chosen effects as `--set` lines, and the declared config read with them.
  std::vector<std::string> fitted_overrides;
  ModelParams fitted;
  SimulatedRecord before;
  SimulatedRecord after;
  ResidualReport residual_before;
  ResidualReport residual_after;
  /// Channels left out of the comparison (they never move beyond their noise), described.
  std::vector<std::string> left_out;
  /// The measurement the fit ran with: the caller's, or with the drop's start taken from the
  /// record (trigger_state = "record_start") where the model's own state departed there and
  /// the lead window's estimate agreed (FitRecord).
  MeasurementParams measurement;
  /// The record's displacement noise before the trigger, white or coloured: what the model's
  /// controller answers wherever the fit draws the rotor's jitter.
  SensorNoise sensor_noise;
};

/// Throws (std::runtime_error and its kin) when the record cannot be used with the model, or
/// none of its channels moves beyond its noise (there would be nothing to compare);
/// DeclaredModelStopped when the declared model's run on it stops early.
std::unique_ptr<FitResult> FitRecord(const ConfigVariants& declared,
                                     const MeasurementParams& measurement,
                                     const MeasuredRecord& record, const FitRecordOptions& options);

/// The parameter of `effect` named `name` among the chosen ones; nullptr if not chosen.
const ParameterEstimate* ChosenParameter(const FitResult& fit, const std::string& effect,
                                         const std::string& name);

}  // namespace ambdrop
