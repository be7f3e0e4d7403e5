#include "tools/fit/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tools/fit/not_a_number.hpp"

namespace ambdrop {
namespace {

struct Accumulator {
  double sum_sq = 0.0;
  std::size_t n = 0;
  void Add(double e) {
    sum_sq += e * e;
    ++n;
  }
  double Rms() const { return n == 0 ? kNaN : std::sqrt(sum_sq / static_cast<double>(n)); }
};

}  // namespace

FitWindows WindowsOf(const MeasuredRecord& r, const SimulatedRecord& sim, double start_s) {
  FitWindows w;
  w.trigger_s = sim.trigger_time_s;
  w.start_s = start_s;
  w.end_s = r.time_s.back();
  const double after = w.end_s - w.trigger_s;
  const double phase = std::min(after / 3.0, 0.1);
  w.impact_end_s = w.trigger_s + phase;
  w.settled_start_s = w.end_s - phase;
  return w;
}

std::vector<double> ResidualSeries(const MeasurementParams& m, const MeasuredRecord& r,
                                   const SimulatedRecord& sim, std::size_t c) {
  const MeasurementChannel& ch = m.channels[c];
  const std::vector<double>& measured = r.values[r.Column(ch.column)];
  std::vector<double> e(r.time_s.size(), kNaN);
  const bool current = ch.quantity == MeasuredQuantity::kCurrent ||
                       ch.quantity == MeasuredQuantity::kControllerCommand;
  // from_record's coil currents are the model's input, never a residual.
  if (m.Drives(ch)) return e;
  for (std::size_t j = sim.first_row; j < sim.first_row + sim.rows; ++j) {
    if (!sim.closed_loop && current && r.time_s[j] < sim.trigger_time_s) continue;
    if (!ch.InWindow(r.time_s[j], sim.trigger_time_s)) continue;
    // NaN where the model predicts nothing (a command open loop).
    e[j] = measured[j] - sim.values[c][j];
  }
  return e;
}

ResidualReport ComputeResiduals(const ModelParams& params, const MeasurementParams& m,
                                const MeasuredRecord& r, const SimulatedRecord& sim,
                                double start_s) {
  ResidualReport report;
  report.windows = WindowsOf(r, sim, start_s);
  const FitWindows& w = report.windows;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const std::vector<double> e = ResidualSeries(m, r, sim, c);
    const std::vector<double>& measured = r.values[r.Column(m.channels[c].column)];
    ChannelResidual cr;
    cr.column = m.channels[c].column;
    cr.description = m.channels[c].Describe(params);
    Accumulator all, before, impact, settled;
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (std::size_t j = 0; j < e.size(); ++j) {
      if (std::isnan(e[j])) continue;
      const double t = r.time_s[j];
      all.Add(e[j]);
      if (t < w.trigger_s) before.Add(e[j]);
      if (t >= w.trigger_s && t < w.impact_end_s) impact.Add(e[j]);
      if (t >= w.settled_start_s) settled.Add(e[j]);
      lo = std::min(lo, measured[j]);
      hi = std::max(hi, measured[j]);
    }
    cr.samples = all.n;
    cr.rms = all.Rms();
    cr.rms_before = before.Rms();
    cr.rms_impact = impact.Rms();
    cr.rms_settled = settled.Rms();
    cr.scale = (all.n > 0 && hi > lo) ? hi - lo : 1.0;
    report.channels.push_back(cr);
  }
  report.overall = kNaN;
  report.features = CompareFeatures(params, m, r, sim);
  report.signatures = ResidualSignatures(params, m, r, sim);
  return report;
}

}  // namespace ambdrop
