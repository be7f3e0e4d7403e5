#pragma once
// The levitated loop's noise spectrum. While levitated, a controller answers its sensors' noise,
// and the coil currents carry that noise shaped by the closed loop: the loop's sensitivity
// rises where its phase margin is spent (ISO 14839-3 reads stability margins off it). A lag in
// the acquisition chain, a computation delay, an amplifier's bandwidth or a sensor's gain moves
// that shape and leaves the levitated mean, 1X and 2X alone: on the independent rigid truth
// rig, a 0.2-0.7 ms chain lag put 2.5 times the clean records' power into the currents' 80 to
// 320 Hz, where the drop's start could not tell it from the clean ones (docs/fit.md).
//
// What is compared is each current's power in bands of a Welch estimate (Hann windows, half
// overlapped), after its mean, trend and synchronous lines (1X to 3X, the levitated part's own
// blocks) are taken out. Two numbers of no interest are fitted away per channel: the level
// (the noise's absolute size: the record's sensors against the model's draw of it) and a white
// floor (the current channel's own measurement noise, which the model's expected reading does
// not carry; it fills the bins where the loop's answer falls away, near the controller's rate).
// The rest, in units of its own spread, is the residual.
#include <cstddef>
#include <utility>
#include <vector>

namespace ambdrop {

struct SpectrumPlan {
  std::size_t first_row = 0;  ///< rows [first_row, first_row + rows) of the record
  std::size_t rows = 0;
  std::size_t segment = 0;   ///< samples per Welch segment
  std::size_t segments = 0;  ///< segments, half overlapped
  double sample_interval_s = 0.0;
  /// DFT bins [first, second) of each band: single bins at the bottom, where the loop's
  /// features are a bin or two wide, then bands a quarter wider each.
  std::vector<std::pair<std::size_t, std::size_t>> bands;
  /// The variance of ln(band power) of one estimate, per band (BandLogVariance).
  std::vector<double> log_variance;
  /// The trend and synchronous basis over the rows (rows x columns, column-major) and the
  /// Hann window and DFT tables (segment x bins), built once per plan.
  std::vector<double> basis;
  std::size_t basis_columns = 0;
  std::vector<double> window;
  std::vector<double> cos_table;
  std::vector<double> sin_table;
  std::size_t first_bin = 1;
  std::size_t bins = 0;  ///< bins first_bin .. first_bin + bins - 1
};

/// The plan for rows [first, end) of a record sampled at `time_s`, a rotor spinning at
/// `spin_rad_s` (0: no synchronous lines), up to half its Nyquist frequency; empty bands (not
/// comparable) for fewer than 128 rows, or rows not evenly sampled.
SpectrumPlan PlanSpectrum(const std::vector<double>& time_s, std::size_t first, std::size_t end,
                          double spin_rad_s);

/// Power per band of `values` (indexed by record row) over the plan's rows, in arbitrary units
/// (the level is fitted away); empty if a value there is not finite.
std::vector<double> BandPowers(const SpectrumPlan& plan, const std::vector<double>& values);

/// Variance of the natural log of a band's Welch power of `bins` adjacent bins over `segments`
/// half-overlapped Hann segments, for Gaussian noise whose spectrum is smooth across the band:
/// the powers of adjacent bins correlate by (2/3)^2, of bins two apart by (1/6)^2, of
/// overlapping segments by (1/6)^2 (the Hann window's own overlaps).
double BandLogVariance(std::size_t bins, std::size_t segments);

struct SpectrumMatch {
  /// Per band: (ln measured - ln(model + floor) - level) / its standard deviation.
  std::vector<double> z;
  double level = 0.0;  ///< fitted ln(measured / model)
  double floor = 0.0;  ///< fitted white floor, power per bin in the measured band's units
};

/// The measured band powers against the model's (a mean over `model_runs` noise draws), each
/// band's variance `variance_scale` times BandLogVariance for the record's estimate plus the
/// model's mean. The level and the floor (>= 0) are those that minimise the squared z.
SpectrumMatch MatchSpectra(const SpectrumPlan& plan, const std::vector<double>& measured,
                           const std::vector<double>& model, int model_runs,
                           double variance_scale = 1.0);

}  // namespace ambdrop
