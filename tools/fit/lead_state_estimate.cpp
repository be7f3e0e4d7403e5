#include "tools/fit/lead_state_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/SVD>
#include <fmt/format.h>

namespace ambdrop {

double TriggerStateLeadSeconds(const MeasuredRecord& record) {
  return std::max(6e-3, 40.0 * record.SampleInterval());
}

LeadStateFit FitLeadState(const ModelParams& declared, const MeasurementParams& m,
                          const MeasuredRecord& r, const RecordRunOptions& options,
                          const Model& model, const State& at_lead_start, double trigger_s,
                          double lead_s) {
  const int n = model.modes();
  const auto none = [n](std::string why) {
    return LeadStateFit{Eigen::VectorXd::Zero(2 * n), {}, "not fitted: " + std::move(why), false};
  };
  std::vector<std::size_t> channels;
  std::vector<Eigen::RowVectorXd> shape_rows;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    if (ch.quantity != MeasuredQuantity::kDisplacement) continue;
    channels.push_back(c);
    shape_rows.push_back(model.sensor_shapes[ch.index].row(ch.axis) *
                         model.params.sensors[ch.index].AxisGain(ch.axis));
  }
  if (channels.empty()) return none("the record has no displacement channel");
  // The directions the sensors see.
  Eigen::MatrixXd a(static_cast<Eigen::Index>(shape_rows.size()), n);
  for (std::size_t i = 0; i < shape_rows.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) = shape_rows[i];
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  std::vector<Eigen::VectorXd> directions;  // 2n each: a position or a velocity direction
  std::vector<double> steps;
  for (int part = 0; part < 2; ++part) {
    for (Eigen::Index j = 0; j < sv.size(); ++j) {
      if (!(sv(j) > 1e-9 * sv(0))) continue;
      Eigen::VectorXd d = Eigen::VectorXd::Zero(2 * n);
      d.segment(part * n, n) = svd.matrixV().col(j);
      directions.push_back(d);
      // 1 um at the sensors, or 1 mm/s: micrometres over the window either way.
      steps.push_back((part == 0 ? 1e-6 : 1e-3) / sv(j));
    }
  }

  RecordRunOptions o = options;
  o.pre_trigger = PreTrigger::kMeasuredCurrents;
  o.lead_s = lead_s;
  o.end_s = trigger_s;
  o.start_position_shift_m = 0.0;
  o.start_velocity_shift_m_s = 0.0;
  o.initial_state = std::make_shared<const State>(at_lead_start);
  o.state_correction = Eigen::VectorXd::Zero(2 * n);
  o.lead_state_shift = Eigen::VectorXd();
  const SimulatedRecord base = SimulateOnRecord(declared, m, r, o);
  if (base.status != StepStatus::kOk) {
    return none("the model driven by the record's currents stopped in the lead window (" +
                base.failure.substr(0, base.failure.find('\n')) + ")");
  }

  // The window's samples: displacement channels, record rows from the lead's start to the
  // trigger, where the base run predicts them.
  struct Sample {
    std::size_t channel = 0, row = 0;
  };
  std::vector<Sample> samples;
  for (const std::size_t c : channels) {
    for (std::size_t j = base.first_row; j < base.first_row + base.rows; ++j) {
      if (r.time_s[j] > trigger_s + 1e-12) break;
      if (std::isfinite(base.values[c][j])) samples.push_back({c, j});
    }
  }
  if (samples.size() < 2 * directions.size()) {
    return none(fmt::format("{} displacement samples in the {:.3g} ms lead window, fewer than "
                            "twice the {} state directions the sensors see",
                            samples.size(), lead_s * 1e3, directions.size()));
  }
  Eigen::VectorXd e(static_cast<Eigen::Index>(samples.size()));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    const double measured = r.values[r.Column(m.channels[s.channel].column)][s.row] +
                            options.start_position_shift_m +
                            options.start_velocity_shift_m_s * (r.time_s[s.row] - trigger_s);
    e(static_cast<Eigen::Index>(i)) = measured - base.values[s.channel][s.row];
  }
  Eigen::MatrixXd jacobian(e.size(), static_cast<Eigen::Index>(directions.size()));
  for (std::size_t k = 0; k < directions.size(); ++k) {
    o.state_correction = steps[k] * directions[k];
    const SimulatedRecord moved = SimulateOnRecord(declared, m, r, o);
    if (moved.status != StepStatus::kOk) {
      return none("a sensitivity run of the lead window stopped (" +
                  moved.failure.substr(0, moved.failure.find('\n')) + ")");
    }
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Sample& s = samples[i];
      jacobian(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) =
          (moved.values[s.channel][s.row] - base.values[s.channel][s.row]) / steps[k];
    }
  }
  if (!jacobian.allFinite() || !e.allFinite()) {
    return none("the lead window's samples or sensitivities are not finite");
  }
  // Columns scaled to unit norm, then the minimum-norm least-squares solution through the
  // pseudo-inverse: directions the window cannot tell apart (below 1e-6 of the best seen) are
  // left alone.
  Eigen::VectorXd scale = jacobian.colwise().norm().transpose();
  const double largest = scale.maxCoeff();
  if (!(largest > 0.0)) return none("the lead window's samples do not move with the state");
  for (Eigen::Index k = 0; k < scale.size(); ++k) scale(k) = std::max(scale(k), 1e-12 * largest);
  const Eigen::MatrixXd scaled = jacobian * scale.cwiseInverse().asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> jsvd(scaled, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& js = jsvd.singularValues();
  if (!(js.size() > 0 && js(0) > 0.0)) {
    return none("the lead window's samples do not move with the state");
  }
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(js.size());
  for (Eigen::Index k = 0; k < js.size(); ++k) {
    if (js(k) > 1e-6 * js(0)) inverse(k) = 1.0 / js(k);
  }
  const Eigen::VectorXd alpha =
      (jsvd.matrixV() * inverse.asDiagonal() * (jsvd.matrixU().transpose() * e))
          .cwiseQuotient(scale);
  Eigen::MatrixXd to_state(2 * n, static_cast<Eigen::Index>(directions.size()));
  for (std::size_t k = 0; k < directions.size(); ++k) {
    to_state.col(static_cast<Eigen::Index>(k)) = directions[k];
  }
  LeadStateFit fit;
  fit.correction = to_state * alpha;
  if (!fit.correction.allFinite()) return none("the least-squares correction is not finite");
  Eigen::Index used = 0;
  for (Eigen::Index k = 0; k < inverse.size(); ++k) used += inverse(k) > 0.0 ? 1 : 0;
  fit.fitted = true;
  fit.note = fmt::format("{} samples of {} displacement channels over the {:.3g} ms lead window, "
                         "{} of {} state directions fitted",
                         samples.size(), channels.size(), lead_s * 1e3, used, directions.size());
  // Its covariance: the residual variance per sample times (J^T J)^-1; in the scaled columns
  // that is V S^-2 V^T, so the principal axes are V's columns, one standard deviation being
  // sigma / s_k along each.
  const Eigen::VectorXd after = e - jacobian * alpha;
  const double dof = std::max(1.0, static_cast<double>(e.size() - alpha.size()));
  const double sigma = std::sqrt(after.squaredNorm() / dof);
  std::vector<std::pair<double, Eigen::Index>> spread;
  for (Eigen::Index k = 0; k < js.size(); ++k) {
    if (inverse(k) > 0.0) spread.emplace_back(sigma * inverse(k), k);
  }
  std::sort(spread.begin(), spread.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; i < spread.size() && i < 3; ++i) {
    const Eigen::VectorXd axis =
        (spread[i].first * jsvd.matrixV().col(spread[i].second)).cwiseQuotient(scale);
    fit.uncertainty.push_back(to_state * axis);
  }
  return fit;
}

}  // namespace ambdrop
