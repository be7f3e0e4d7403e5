#include "tools/fit/levitated_spectrum.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace ambdrop {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Fifteen half-overlapped segments: each bin's estimate then spreads by about a quarter of
// itself, and on the rigid truth rig's 0.1 s of levitation a segment still resolves 80 Hz.
constexpr std::size_t kSegments = 15;
constexpr std::size_t kMinRows = 128;
// Hann window: the correlation of the powers of adjacent bins, of bins two apart, and of
// half-overlapped segments (each the square of the complex correlation, 2/3, 1/6 and 1/6).
constexpr double kAdjacentBins = 4.0 / 9.0;
constexpr double kBinsTwoApart = 1.0 / 36.0;
constexpr double kOverlappedSegments = 1.0 / 36.0;
constexpr double kBandGrowth = 1.25;

// psi'(x), the trigamma function, by recurrence to x >= 6 and its asymptotic series.
double Trigamma(double x) {
  double sum = 0.0;
  while (x < 6.0) {
    sum += 1.0 / (x * x);
    x += 1.0;
  }
  const double x2 = x * x;
  return sum + 1.0 / x + 1.0 / (2.0 * x2) + 1.0 / (6.0 * x2 * x) - 1.0 / (30.0 * x2 * x2 * x);
}

}  // namespace

double BandLogVariance(std::size_t bins, std::size_t segments) {
  const double b = static_cast<double>(std::max<std::size_t>(bins, 1));
  const double k = static_cast<double>(std::max<std::size_t>(segments, 1));
  const double across_bins =
      (b + 2.0 * (b - 1.0) * kAdjacentBins + 2.0 * std::max(0.0, b - 2.0) * kBinsTwoApart) /
      (b * b);
  const double across_segments = (1.0 + 2.0 * kOverlappedSegments * (k - 1.0) / k) / k;
  // A band's power is about a scaled chi-square of nu = 2 / (its relative variance) degrees
  // of freedom; the log of one has variance psi'(nu / 2).
  const double relative = across_bins * across_segments;
  return Trigamma(1.0 / relative);
}

SpectrumPlan PlanSpectrum(const std::vector<double>& time_s, std::size_t first, std::size_t end,
                          double spin_rad_s) {
  SpectrumPlan plan;
  if (end > time_s.size() || end < first + kMinRows) return plan;
  const std::size_t rows = end - first;
  const double dt = (time_s[end - 1] - time_s[first]) / static_cast<double>(rows - 1);
  if (!(dt > 0.0) || !std::isfinite(dt)) return plan;
  for (std::size_t j = first + 1; j < end; ++j) {
    if (std::abs(time_s[j] - time_s[j - 1] - dt) > 1e-3 * dt) return plan;
  }
  plan.first_row = first;
  plan.rows = rows;
  plan.sample_interval_s = dt;
  plan.segment = 2 * (rows / (kSegments + 1));
  plan.segments = (rows - plan.segment) / (plan.segment / 2) + 1;

  // Mean, trend and the synchronous lines a window of at least two turns resolves (the
  // levitated part's blocks judge those), below the Nyquist frequency.
  const double span = dt * static_cast<double>(rows);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(rows), 2);
  for (std::size_t i = 0; i < rows; ++i) {
    const double t = static_cast<double>(i) * dt;
    a(static_cast<Eigen::Index>(i), 0) = 1.0;
    a(static_cast<Eigen::Index>(i), 1) = t / span - 0.5;
  }
  for (int h = 1; h <= 3; ++h) {
    const double w = h * std::abs(spin_rad_s);
    if (w * span < 4.0 * kPi || w * dt > 0.9 * kPi) continue;
    const Eigen::Index c = a.cols();
    a.conservativeResize(Eigen::NoChange, c + 2);
    for (std::size_t i = 0; i < rows; ++i) {
      const double phase = w * static_cast<double>(i) * dt;
      a(static_cast<Eigen::Index>(i), c) = std::cos(phase);
      a(static_cast<Eigen::Index>(i), c + 1) = std::sin(phase);
    }
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), a.cols());
  plan.basis.assign(q.data(), q.data() + q.size());
  plan.basis_columns = static_cast<std::size_t>(q.cols());

  const std::size_t n = plan.segment;
  plan.window.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    plan.window[i] =
        0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(n));
  }
  // Bins from 1 (the mean's is taken out) up to 0.7 of the Nyquist frequency: above it a real
  // acquisition's anti-aliasing filter and its current sensors' bandwidth shape the record,
  // which no key of the model declares, and aliasing folds in what the samples cannot resolve.
  // On the flexible truth rig the two bands below the Nyquist frequency stood 1.5 to 3 spreads
  // above a clean record's model even with the white floor fitted, the rest at the noise; the
  // loop's own features (its crossover, a notch, an amplifier's bandwidth) lie far below.
  plan.first_bin = 1;
  plan.bins = 7 * n / 20;
  plan.cos_table.resize(plan.bins * n);
  plan.sin_table.resize(plan.bins * n);
  for (std::size_t b = 0; b < plan.bins; ++b) {
    const std::size_t k = plan.first_bin + b;
    for (std::size_t i = 0; i < n; ++i) {
      // The index product reduced modulo n keeps the phase exact for large products.
      const double phase = 2.0 * kPi * static_cast<double>((k * i) % n) / static_cast<double>(n);
      plan.cos_table[b * n + i] = std::cos(phase);
      plan.sin_table[b * n + i] = std::sin(phase);
    }
  }
  std::size_t k = 0;
  while (k < plan.bins) {
    const std::size_t grown =
        static_cast<std::size_t>(std::ceil(kBandGrowth * static_cast<double>(k + plan.first_bin))) -
        plan.first_bin;
    std::size_t stop = std::min(plan.bins, std::max(k + 1, grown));
    // A remainder narrower than half this band joins it.
    if (2 * (plan.bins - stop) < stop - k) stop = plan.bins;
    plan.bands.emplace_back(k, stop);
    plan.log_variance.push_back(BandLogVariance(stop - k, plan.segments));
    k = stop;
  }
  return plan;
}

std::vector<double> BandPowers(const SpectrumPlan& plan, const std::vector<double>& values) {
  if (plan.bands.empty() || values.size() < plan.first_row + plan.rows) return {};
  std::vector<double> x(values.begin() + static_cast<std::ptrdiff_t>(plan.first_row),
                        values.begin() + static_cast<std::ptrdiff_t>(plan.first_row + plan.rows));
  for (const double v : x) {
    if (!std::isfinite(v)) return {};
  }
  // Take out the projection on the orthonormal trend and synchronous basis.
  for (std::size_t c = 0; c < plan.basis_columns; ++c) {
    const double* q = plan.basis.data() + c * plan.rows;
    double dot = 0.0;
    for (std::size_t i = 0; i < plan.rows; ++i) dot += q[i] * x[i];
    for (std::size_t i = 0; i < plan.rows; ++i) x[i] -= dot * q[i];
  }
  const std::size_t n = plan.segment;
  std::vector<double> bin_power(plan.bins, 0.0);
  std::vector<double> seg(n);
  for (std::size_t s = 0; s < plan.segments; ++s) {
    const std::size_t start = s * (n / 2);
    for (std::size_t i = 0; i < n; ++i) seg[i] = plan.window[i] * x[start + i];
    for (std::size_t b = 0; b < plan.bins; ++b) {
      const double* c = plan.cos_table.data() + b * n;
      const double* si = plan.sin_table.data() + b * n;
      double re = 0.0;
      double im = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        re += seg[i] * c[i];
        im += seg[i] * si[i];
      }
      bin_power[b] += re * re + im * im;
    }
  }
  std::vector<double> out;
  out.reserve(plan.bands.size());
  for (const auto& [lo, hi] : plan.bands) {
    double sum = 0.0;
    for (std::size_t b = lo; b < hi; ++b) sum += bin_power[b];
    out.push_back(sum / static_cast<double>(plan.segments));
  }
  return out;
}

SpectrumMatch MatchSpectra(const SpectrumPlan& plan, const std::vector<double>& measured,
                           const std::vector<double>& model, int model_runs,
                           double variance_scale) {
  SpectrumMatch m;
  const std::size_t n = plan.bands.size();
  if (measured.size() != n || model.size() != n || n == 0) return m;
  std::vector<double> width(n);
  std::vector<double> weight(n);
  const double runs = static_cast<double>(std::max(model_runs, 1));
  double per_bin_lo = std::numeric_limits<double>::infinity();
  double per_bin_hi = 0.0;
  for (std::size_t b = 0; b < n; ++b) {
    width[b] = static_cast<double>(plan.bands[b].second - plan.bands[b].first);
    weight[b] = 1.0 / (plan.log_variance[b] * variance_scale * (1.0 + 1.0 / runs));
    if (model[b] > 0.0) {
      per_bin_lo = std::min(per_bin_lo, model[b] / width[b]);
      per_bin_hi = std::max(per_bin_hi, model[b] / width[b]);
    }
  }
  const auto residuals = [&](double floor, std::vector<double>* d, double* level) {
    double sum = 0.0;
    double total = 0.0;
    for (std::size_t b = 0; b < n; ++b) {
      const double predicted = model[b] + floor * width[b];
      if (!(measured[b] > 0.0) || !(predicted > 0.0))
        return std::numeric_limits<double>::infinity();
      (*d)[b] = std::log(measured[b]) - std::log(predicted);
      sum += weight[b] * (*d)[b];
      total += weight[b];
    }
    *level = sum / total;
    double j = 0.0;
    for (std::size_t b = 0; b < n; ++b) j += weight[b] * std::pow((*d)[b] - *level, 2);
    return j;
  };
  std::vector<double> d(n);
  double level = 0.0;
  double best_floor = 0.0;
  double best = residuals(0.0, &d, &level);
  if (!(per_bin_hi > 0.0)) {
    per_bin_lo = per_bin_hi = 1.0;
  }
  // The floor on a log grid from a millionth of the model's weakest bin to a hundred times its
  // strongest, then golden-section between the best grid point's neighbours.
  const double lo = std::log(1e-6 * per_bin_lo);
  const double hi = std::log(1e2 * per_bin_hi);
  constexpr int kGrid = 80;
  int best_i = -1;
  for (int i = 0; i <= kGrid; ++i) {
    const double f = std::exp(lo + (hi - lo) * i / kGrid);
    const double j = residuals(f, &d, &level);
    if (j < best) {
      best = j;
      best_floor = f;
      best_i = i;
    }
  }
  if (best_i >= 0) {
    double a = lo + (hi - lo) * std::max(0, best_i - 1) / kGrid;
    double c = lo + (hi - lo) * std::min(kGrid, best_i + 1) / kGrid;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 40; ++it) {
      const double x1 = c - g * (c - a);
      const double x2 = a + g * (c - a);
      if (residuals(std::exp(x1), &d, &level) < residuals(std::exp(x2), &d, &level)) {
        c = x2;
      } else {
        a = x1;
      }
    }
    const double f = std::exp(0.5 * (a + c));
    const double j = residuals(f, &d, &level);
    if (j < best) {
      best = j;
      best_floor = f;
    }
  }
  if (!std::isfinite(residuals(best_floor, &d, &level))) return m;
  m.level = level;
  m.floor = best_floor;
  m.z.resize(n);
  for (std::size_t b = 0; b < n; ++b) m.z[b] = (d[b] - level) * std::sqrt(weight[b]);
  return m;
}

}  // namespace ambdrop
