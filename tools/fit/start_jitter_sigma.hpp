#pragma once
// A fitted value's uncertainty from the rotor's jitter when the power failed: the record holds
// one draw of it, which the noise-free model does not know, and the fit absorbs what of its
// move the effect's parameters can.
#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

/// Adds to each parameter's sigma (in quadrature) the spread the rotor's jitter at the trigger
/// gives it on `cost`, the part its effects were judged on: the fitted model run `draws` times
/// with its controller answering sensor noise of the record's level, each run's move of the
/// residual carried onto the parameters by the least squares of the Jacobian there, and the
/// shifts' RMS taken (ParameterEstimate::start_sigma); `decided` again from the wider sigma.
/// The sigma from the noise alone misses it: fitted to six records of the rigid truth rig's
/// offset NDE TDB (seed 803) that differ only in their noise and jitter, the offset's y spreads
/// by 3.2 um, where its noise sigma is 0.1 um and this share 2.5 um (fit_start_jitter_sigma_
/// test). A bias is not in it: their mean, 2.5 um, is 17 um below the truth's 19.7. Nothing where
/// the run is open loop, the state at the trigger is the record's estimate, or the record has no
/// displacement noise.
void AddStartJitterToSigmas(const ConfigVariants& declared, const RecordCost& cost,
                            const std::vector<Effect>& library, int draws, int threads,
                            EffectFit* fit);

}  // namespace ambdrop
