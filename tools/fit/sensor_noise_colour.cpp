#include "tools/fit/sensor_noise_colour.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "tools/fit/levitated_spectrum.hpp"
#include "tools/fit/noise_floor.hpp"

namespace ambdrop {
namespace {

// A likelihood ratio of one parameter more beyond chance at p = 0.001 (chi-square, 1 dof).
constexpr double kColouredChiSquare = 10.83;
// Bands taken in below the start only while within this many of their own spreads.
constexpr double kBandWithin = 3.0;
// The AR(1) coefficient's grid (a = 0: white).
constexpr int kCoefficientSteps = 999;

struct Band {
  double log_power = 0.0;  ///< ln of the mean power per bin, in variance per unit sigma^2
  double variance = 0.0;   ///< of log_power
  std::vector<double> cos_omega;
};

// Mean over the band's bins of the AR(1) spectrum with unit variance,
// (1 - a^2) / (1 - 2 a cos w + a^2), which averages 1 over [0, pi].
double Shape(const Band& b, double a) {
  double sum = 0.0;
  for (const double c : b.cos_omega) sum += (1.0 - a * a) / (1.0 - 2.0 * a * c + a * a);
  return sum / static_cast<double>(b.cos_omega.size());
}

struct Ar1Fit {
  double a = 0.0;
  double log_scale = 0.0;  ///< ln of the variance
  double chi_square = std::numeric_limits<double>::infinity();
};

// For a fixed, ln(variance) is the weighted mean of the log residuals.
Ar1Fit FitAt(const std::vector<Band>& bands, std::size_t from, double a) {
  Ar1Fit f;
  f.a = a;
  double num = 0.0, den = 0.0;
  std::vector<double> shape(bands.size() - from);
  for (std::size_t i = from; i < bands.size(); ++i) {
    shape[i - from] = std::log(Shape(bands[i], a));
    num += (bands[i].log_power - shape[i - from]) / bands[i].variance;
    den += 1.0 / bands[i].variance;
  }
  f.log_scale = num / den;
  f.chi_square = 0.0;
  for (std::size_t i = from; i < bands.size(); ++i) {
    const double z = bands[i].log_power - f.log_scale - shape[i - from];
    f.chi_square += z * z / bands[i].variance;
  }
  return f;
}

Ar1Fit BestFit(const std::vector<Band>& bands, std::size_t from, bool white) {
  Ar1Fit best = FitAt(bands, from, 0.0);
  if (white) return best;
  for (int i = 1; i <= kCoefficientSteps; ++i) {
    const Ar1Fit f = FitAt(bands, from, static_cast<double>(i) / (kCoefficientSteps + 1));
    if (f.chi_square < best.chi_square) best = f;
  }
  return best;
}

}  // namespace

double Ar1Bandwidth_Hz(double a, double dt_s) {
  if (!(a > 0.0) || !(dt_s > 0.0)) return 0.0;
  return -std::log(a) / (2.0 * std::numbers::pi * dt_s);
}

SensorNoise ChannelSensorNoise(const std::vector<double>& time_s, const std::vector<double>& values,
                               std::size_t first, std::size_t end, double spin_rad_s) {
  SensorNoise out;
  out.white_sigma_m = NoiseSigma(values, first, end);
  out.sigma_m = out.white_sigma_m;
  const SpectrumPlan plan = PlanSpectrum(time_s, first, end, spin_rad_s);
  if (plan.bands.empty()) return out;
  const std::vector<double> power = BandPowers(plan, values);
  if (power.size() != plan.bands.size()) return out;
  // A bin's expected power is the spectrum there times the window's energy (white noise of
  // variance s^2 gives s^2 sum w^2), so each band's mean per bin reads in variance.
  double energy = 0.0;
  for (const double w : plan.window) energy += w * w;
  const double n = static_cast<double>(plan.segment);
  std::vector<Band> bands;
  std::size_t start = plan.bands.size();
  for (std::size_t k = 0; k < plan.bands.size(); ++k) {
    const auto [lo, hi] = plan.bands[k];
    const double per_bin = power[k] / (static_cast<double>(hi - lo) * energy);
    if (!(per_bin > 0.0) || !std::isfinite(per_bin)) return out;
    Band b;
    b.log_power = std::log(per_bin);
    b.variance = plan.log_variance[k];
    for (std::size_t bin = lo; bin < hi; ++bin) {
      const double omega = 2.0 * std::numbers::pi * static_cast<double>(plan.first_bin + bin) / n;
      b.cos_omega.push_back(std::cos(omega));
    }
    // The bands wholly above a quarter of the Nyquist frequency start the fit.
    if (start == plan.bands.size() && 4 * (plan.first_bin + lo) >= plan.segment / 2) start = k;
    bands.push_back(std::move(b));
  }
  if (bands.size() < start + 4) return out;
  // Take in lower bands while each stays within its spreads of the fit so far.
  Ar1Fit fit = BestFit(bands, start, false);
  while (start > 0) {
    const Band& b = bands[start - 1];
    const double model = fit.log_scale + std::log(Shape(b, fit.a));
    if (std::abs(b.log_power - model) > kBandWithin * std::sqrt(b.variance)) break;
    --start;
    fit = BestFit(bands, start, false);
  }
  const Ar1Fit white = BestFit(bands, start, true);
  if (!(white.chi_square - fit.chi_square > kColouredChiSquare) || !(fit.a > 0.0)) return out;
  out.sigma_m = std::sqrt(std::exp(fit.log_scale));
  out.bandwidth_Hz = Ar1Bandwidth_Hz(fit.a, plan.sample_interval_s);
  return out;
}

SensorNoise MedianSensorNoise(const std::vector<SensorNoise>& each) {
  SensorNoise out;
  if (each.empty()) return out;
  const auto median_of = [&](auto get) {
    std::vector<double> v;
    for (const SensorNoise& s : each) v.push_back(get(s));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  out.white_sigma_m = median_of([](const SensorNoise& s) { return s.white_sigma_m; });
  // A white channel's bandwidth is infinite: the median bandwidth, the upper one of an even
  // count, is finite only where more than half the channels are coloured.
  std::vector<double> widths;
  for (const SensorNoise& s : each) {
    widths.push_back(s.bandwidth_Hz > 0.0 ? s.bandwidth_Hz
                                          : std::numeric_limits<double>::infinity());
  }
  std::sort(widths.begin(), widths.end());
  const double width = widths[widths.size() / 2];
  if (std::isfinite(width)) {
    out.bandwidth_Hz = width;
    out.sigma_m = median_of([](const SensorNoise& s) { return s.sigma_m; });
  } else {
    out.sigma_m = out.white_sigma_m;
  }
  return out;
}

}  // namespace ambdrop
