#pragma once
// Whether the record needs each chosen value to differ from what is declared. A value's sigma
// is the curvature of the cost at the optimum, which a drop's contacts make rough: on the rigid
// truth rig's offset NDE TDB of seed 803 the offset's y (8 um fitted, 19.7 true, declared 0)
// came with a sigma of 0.1 um from the noise and 2.5 um from the jitter at the trigger, yet
// the start's cost barely moves between y = 0 and 25 um. The question asked here is the one the
// verdict asks of the whole model, asked of each number: is the record explained without it?
#include <functional>
#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_library.hpp"

namespace ambdrop {

/// For each value of `fit` (two or more across its effects) whose parameter has a declared value
/// (EffectParameter::declared) it differs from, runs the model with that one value set back to
/// it and every other as fitted; where `explains` says that model still explains the record
/// (the caller's test: the judged part within its limit, and every other part the chosen model
/// agrees with still agreeing), the value is not decided
/// (ParameterEstimate::decided false, declared_rms the judged part's residual there). A value
/// is set back alone: with the others refitted the record could only need it less, so no value
/// is called open that a refit would need. Then each pair of values correlated in the fit's
/// covariance (EffectFit::covariance) is moved along their valley until one is at its declared
/// value; where that still explains the record, both are not decided alone and carry the one
/// combination the record decides (ParameterEstimate::traded_with). A value with no declared
/// one is moved to each edge of what ParameterDecided calls decided, its most correlated
/// partner following; where that still explains the record it is not decided either
/// (ParameterEstimate::explained_at). One run per value, per direction of each correlated pair
/// and per edge (12 along a partner's range where the covariance leaves it out); `threads` runs
/// at once.
void MarkValuesTheRecordDoesNotNeed(
    const ConfigVariants& declared, const std::vector<Effect>& library, int threads,
    const std::function<bool(const ModelParams& params, double* judged_rms)>& explains,
    EffectFit* fit);

}  // namespace ambdrop
