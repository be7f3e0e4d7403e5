#include "tools/fit/record_cost.hpp"

#include <algorithm>
#include <cmath>

#include "tools/fit/noise_floor.hpp"

namespace ambdrop {

RecordCost::RecordCost(const ModelParams& declared, const MeasurementParams& measurement,
                       const MeasuredRecord& record, const RecordRunOptions& run,
                       std::size_t max_samples_per_channel)
    : declared_(declared), measurement_(measurement), record_(record), run_(run) {
  trigger_s_ = RecordTriggerTime(measurement, record);
  const double start = std::max(record.time_s.front(), trigger_s_ - run.lead_s);
  for (std::size_t c = 0; c < measurement.channels.size(); ++c) {
    const MeasurementChannel& ch = measurement.channels[c];
    const int col = record.Column(ch.column);
    column_.push_back(col);
    range_.push_back(0.0);
    // Currents before the trigger drive the run: they are inputs, not predictions.
    const double from = ch.quantity == MeasuredQuantity::kCurrent ? trigger_s_ : start;
    std::vector<std::size_t> rows;
    for (std::size_t j = 0; j < record.time_s.size(); ++j) {
      if (record.time_s[j] >= from) rows.push_back(j);
    }
    if (rows.empty()) continue;
    double lo = record.values[col][rows.front()], hi = lo;
    for (const std::size_t j : rows) {
      lo = std::min(lo, record.values[col][j]);
      hi = std::max(hi, record.values[col][j]);
    }
    const double range = hi > lo ? hi - lo : 1.0;
    range_.back() = range;
    const std::size_t stride =
        (rows.size() + max_samples_per_channel - 1) / max_samples_per_channel;
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < rows.size(); i += std::max<std::size_t>(stride, 1)) {
      kept.push_back(rows[i]);
    }
    const double weight = 1.0 / (range * std::sqrt(static_cast<double>(kept.size())));
    for (const std::size_t j : kept) index_.push_back({c, j, weight, range});
    ++channels_;
  }
}

double RecordCost::NoiseFloor() const {
  double sum = 0.0;
  int n = 0;
  for (std::size_t c = 0; c < column_.size(); ++c) {
    if (range_[c] <= 0.0) continue;
    const std::vector<double>& v = record_.values[column_[c]];
    const double sigma = NoiseSigma(v, 0, v.size());
    sum += (sigma / range_[c]) * (sigma / range_[c]);
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

SimulatedRecord RecordCost::Simulate(const ModelParams& params) const {
  return SimulateOnRecord(params, measurement_, record_, run_);
}

Eigen::VectorXd RecordCost::Residual(const SimulatedRecord& sim) const {
  Eigen::VectorXd r(static_cast<Eigen::Index>(index_.size()));
  for (std::size_t i = 0; i < index_.size(); ++i) {
    const Sample& s = index_[i];
    const double model = sim.values[s.channel][s.row];
    const double measured = record_.values[column_[s.channel]][s.row];
    // Not reached (the run stopped): as far off as the channel's whole range.
    r(static_cast<Eigen::Index>(i)) =
        std::isfinite(model) ? (measured - model) * s.weight : s.range * s.weight;
  }
  return r;
}

Eigen::VectorXd RecordCost::Residual(const ModelParams& params) const {
  return Residual(Simulate(params));
}

}  // namespace ambdrop
