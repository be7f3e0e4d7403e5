#pragma once
// The displacement sensors' noise as a levitated record shows it, white or coloured.
//
// The fit draws the rotor's jitter (its controller answering sensor noise) and judges each
// channel against its noise. Both took the noise to be white: its sigma from second
// differences (NoiseSigma), the model's controller answering one independent draw a sample.
// A real sensor's noise has passed its electronics' bandwidth. Through a first-order low-pass
// at 2 kHz, on records sampled at 20 kHz, second differences read 0.62 of its sigma, and the
// levitated currents' spectrum, the controller's answer to that noise, fell away above the
// bandwidth as no white draw does: a derivative filter 1.6 times the declared was fitted to
// every one of six clean records (docs/verification.md, session 53).
//
// Above the loop's bandwidth a sensor's reading is its noise, whatever the rotor does below
// it. There each displacement channel's Welch power (the levitated spectrum's plan: mean,
// trend and 1X-3X taken out) is fitted by a first-order low-pass of white noise, AR(1) at the
// sample period, in log power, band by band in units of the band's own spread. The fit starts
// from the bands above a quarter of the Nyquist frequency and takes in lower ones while each
// stays within three spreads of it: the rotor's own motion, below the loop's bandwidth, stops
// it. The noise is coloured where the low-pass lowers the bands' chi-square beyond what one
// parameter more would by chance (a likelihood ratio at p = 0.001); white otherwise, with
// NoiseSigma's number. No white floor beside the low-pass: with one, a white noise over the
// rotor's low-frequency motion read as a 32 Hz bandwidth on a white record.
#include <cstddef>
#include <vector>

namespace ambdrop {

struct SensorNoise {
  double sigma_m = 0.0;        ///< standard deviation over all frequencies
  double bandwidth_Hz = 0.0;   ///< first-order bandwidth of a coloured noise; 0: white
  double white_sigma_m = 0.0;  ///< NoiseSigma's second-difference estimate, as before
};

/// Rows [first, end) of one displacement channel sampled at `time_s`, a rotor spinning at
/// `spin_rad_s` (its 1X-3X lines taken out). White (NoiseSigma) where the rows are too few
/// or unevenly sampled.
SensorNoise ChannelSensorNoise(const std::vector<double>& time_s, const std::vector<double>& values,
                               std::size_t first, std::size_t end, double spin_rad_s);

/// Over the channels (ChannelSensorNoise of each): the median sigma, white unless more than
/// half of them are coloured, then with their median bandwidth (the upper one of an even
/// count, a white channel's counted infinite). White and all zero without a channel.
SensorNoise MedianSensorNoise(const std::vector<SensorNoise>& channels);

/// The first-order bandwidth (Hz) of an AR(1) coefficient `a` at sample interval `dt_s`
/// (a = exp(-2 pi fc dt)); 0 for a <= 0.
double Ar1Bandwidth_Hz(double a, double dt_s);

}  // namespace ambdrop
