#pragma once
// The step the fit's runs take. A fit makes hundreds of runs of the record, and the config's
// step is chosen for the bench (a real-time rate, a stiff contact's worst case), not for this
// record: where a coarser step moves the prediction by far less than the record's own noise on
// every part the verdict judges, the fit runs at it. The agreement limit then carries what is
// left (its step sensitivity is taken at half the chosen step).
#include <string>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

struct FitStep {
  double declared_s = 0.0;  ///< the config's step (or the one the options gave)
  double step_s = 0.0;      ///< the fit's
  /// How far the prediction at step_s lies from the one at declared_s, as a fraction of the
  /// record's noise floor, on the part where that is largest (0 if step_s = declared_s).
  double move_over_noise = 0.0;
  std::string why;  ///< one sentence
};

struct FitStepRules {
  int max_factor = 4;  ///< at most this many declared steps
  /// The largest move a coarser step may make, as a fraction of each part's noise floor: at 0.2
  /// the step's term of the agreement limit (twice the move, in quadrature with 1.25 noise
  /// floors) widens it by under 8 %.
  double max_move_over_noise = 0.2;
};

/// Doubles the declared step while the run still succeeds, the step stays within half the
/// record's sample interval, and the prediction on the whole record, its drop's start and its
/// speeds (RecordCost's scopes) moves by at most `rules.max_move_over_noise` noise floors from
/// the declared step's.
FitStep ChooseFitStep(const ModelParams& declared, const MeasurementParams& measurement,
                      const MeasuredRecord& record, const RecordRunOptions& run,
                      const FitStepRules& rules = {});

}  // namespace ambdrop
