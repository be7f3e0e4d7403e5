#pragma once
// A levitated channel's mean and synchronous (1X, 2X) content over a window of rows: how the fit
// compares what a controller answering its sensors' noise makes of a record before the trigger
// (record_cost.hpp), and how much of that content is the noise's rather than the machine's.
#include <cstddef>
#include <vector>

namespace ambdrop {

/// The five blocks' coefficients over rows [first, last) of `time_s`: the mean, then the cosine
/// and sine of 1X, then of 2X at `spin_rad_s`, each such that the sum of coefficient * value
/// is that component's amplitude.
std::vector<std::vector<double>> SynchronousBlockCoefficients(const std::vector<double>& time_s,
                                                              std::size_t first, std::size_t last,
                                                              double spin_rad_s);

/// The variance each of those blocks carries from what is neither constant nor synchronous
/// (sensor noise, and the rotor's own jitter as the controller answers it): the channel's
/// mean, drift, 1X and 2X are removed by least squares, and what is left is projected as the
/// blocks project, onto neighbouring frequencies (2 and 3 frequency bins of the window off
/// each block's, on both sides; bins 2 to 5 for the mean). Empty when the window holds fewer
/// than six turns (2X's neighbours would reach 1X's) or fewer than 64 rows.
std::vector<double> SynchronousBlockNoise(const std::vector<double>& time_s,
                                          const std::vector<double>& values, std::size_t first,
                                          std::size_t last, double spin_rad_s);

}  // namespace ambdrop
