#pragma once
// The step the fit's runs take. A fit makes hundreds of runs of the record, and the config's
// step is chosen for the bench (a real-time rate, a stiff contact's worst case), not for this
// record: where a coarser step moves the prediction by less than the record can resolve on
// every part the verdict judges (its noise, and the model's own sensitivity to a start the
// record cannot pin down), the fit runs at it. The agreement limit then carries what is left
// (its step sensitivity is taken at half the chosen step).
#include <string>

#include "io/config/config_measurement.hpp"
#include "io/config/config_variants.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

struct FitStep {
  double declared_s = 0.0;  ///< the config's step (or the one the options gave)
  double step_s = 0.0;      ///< the fit's
  /// How far the prediction at step_s lies from the one at declared_s, as a fraction of the
  /// record's noise floor, on the part where that is largest (0 if step_s = declared_s).
  double move_over_noise = 0.0;
  /// By what factor step_s widens the agreement limit of the part it widens most, against the
  /// limit at declared_s (1 if step_s = declared_s).
  double limit_widening = 1.0;
  /// Each part's model floor for the selection: the start sensitivity at declared_s, and the
  /// move of the prediction at step_s from the one at half declared_s (NaN where not measured:
  /// the declared model stops early).
  ModelFloors floors;
  std::string why;  ///< one sentence
};

struct FitStepRules {
  int max_factor = 4;  ///< at most this many declared steps
  /// The largest move a coarser step may make where the model is not sensitive to its start,
  /// as a fraction of each part's noise floor: at 0.2 the step's term of the agreement limit
  /// (twice the move, in quadrature with 1.25 noise floors) widens it by 5 %. Where the model
  /// is, after the first impacts, the move may reach what widens that part's limit by the same
  /// 5 %: within its start sensitivity (a drop turned chaotic) it widens it not at all.
  double max_move_over_noise = 0.2;
};

/// Doubles the declared step while the run still succeeds, the step stays within half the
/// record's sample interval, and on the whole record, its drop's start and its speeds
/// (RecordCost's scopes) the step term of the model floor (the move from the prediction at half
/// the declared step) widens no part's agreement limit (`selection`'s rules, with the part's
/// start sensitivity at the declared step, except on the deterministic start) over the declared
/// step's by more than `rules.max_move_over_noise` noise floors widen a limit of noise alone.
FitStep ChooseFitStep(const ConfigVariants& declared, const MeasurementParams& measurement,
                      const MeasuredRecord& record, const RecordRunOptions& run,
                      const SelectionRules& selection, const FitStepRules& rules = {});

}  // namespace ambdrop
