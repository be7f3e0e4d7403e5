#pragma once
// The model floor's start term: how far the declared model's prediction moves under a start the
// record cannot resolve (effect_selection.hpp's agreement limit holds it).
#include <Eigen/Core>

#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

/// The record's displacement noise before the trigger: the median of its displacement
/// channels' noise (RecordCost::sensor_noise: NoiseSigma's where white), m; 0 without a
/// displacement channel. What the real rotor's controller answers, and so how much it jitters
/// when the power fails.
double DisplacementNoiseMedian(const RecordCost& cost);

/// Runs of the declared model with the rotor's jitter drawn that StartSensitivity makes on the
/// drop's start (fewer if SelectionRules::jitter_draws is lower; none at 0).
inline constexpr int kStartJitterDraws = 8;

/// How far the declared model's prediction on `cost` (whose declared residual is
/// `residual_before`) moves when its start is shifted by what the record cannot resolve: the
/// model floor's start term (Selection::start_sensitivity). On the drop's start (closed loop,
/// the model's own levitated state) that includes the median move of `jitter_draws` runs with
/// the rotor's jitter at the trigger drawn. `per_channel`, if given, receives each measurement
/// channel's widest move alone (a probe's, the axes' together or a draw's; 0 for a channel not
/// compared), on the scale of sqrt(RecordCost::ChannelNoiseSse()); empty where no jitter was
/// drawn.
double StartSensitivity(const ConfigVariants& declared, const RecordCost& cost,
                        const Eigen::VectorXd& residual_before, int threads,
                        int jitter_draws = kStartJitterDraws,
                        std::vector<double>* per_channel = nullptr);

}  // namespace ambdrop
