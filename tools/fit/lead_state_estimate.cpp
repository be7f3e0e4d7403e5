#include "tools/fit/lead_state_estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "tools/fit/noise_floor.hpp"

namespace ambdrop {

double TriggerStateLeadSeconds(const MeasuredRecord& record) {
  return std::max(6e-3, 40.0 * record.SampleInterval());
}

namespace {

// Corrections of the measured currents are knots this far apart (a hat function each, as the
// currents are interpolated): force content faster than that barely moves a rotor.
constexpr double kKnotSpacing_s = 2.5e-4;
// Principal axes of the state's scaled covariance below this share of the largest are not
// probed: their variance moves no drop by a measurable amount.
constexpr double kUncertaintyAxisFloor = 1e-6;

// A correction's unknowns: one AMB axis driven by a current column, its knots.
struct CurrentAxis {
  std::size_t amb = 0;
  int axis = 0;
  int column = -1;
  double sigma_A = 0.0;  // the column's white noise per sample (NoiseSigma before the trigger)
};

// A current channel's white noise per sample. Its second differences carry the levitated
// current's own fast changes too (a firmware's staircase through a current loop: 8 mA read for
// 5 mA of noise on the independent flexible rig), and after the trigger those of the
// power-loss law (a ramp has none): the smaller of the two windows' estimates (each at least
// 20 rows; the one after the trigger 5 ms long).
double CurrentNoiseSigma(const MeasuredRecord& r, int column, std::size_t trigger_row) {
  const std::vector<double>& v = r.values[static_cast<std::size_t>(column)];
  constexpr std::size_t kMinRows = 20;
  double sigma = std::numeric_limits<double>::infinity();
  if (trigger_row >= kMinRows) sigma = NoiseSigma(v, 0, trigger_row);
  const std::size_t after = static_cast<std::size_t>(
      std::max<long long>(kMinRows, std::llround(5e-3 / r.SampleInterval())));
  if (trigger_row + after <= v.size()) {
    sigma = std::min(sigma, NoiseSigma(v, trigger_row, trigger_row + after));
  }
  return std::isfinite(sigma) ? sigma : 0.0;
}

}  // namespace

LeadStateFit FitLeadState(const ModelParams& declared, const MeasurementParams& m,
                          const MeasuredRecord& r, const RecordRunOptions& options,
                          const Model& model, const State& at_lead_start, double trigger_s,
                          double lead_s) {
  const int n = model.modes();
  const auto none = [n](std::string why) {
    LeadStateFit f;
    f.correction = Eigen::VectorXd::Zero(2 * n);
    f.note = "not fitted: " + std::move(why);
    return f;
  };
  const std::size_t trigger_row = static_cast<std::size_t>(
      std::upper_bound(r.time_s.begin(), r.time_s.end(), trigger_s) - r.time_s.begin());
  std::vector<std::size_t> channels;
  std::vector<Eigen::RowVectorXd> shape_rows;
  std::vector<double> sigma_m;  // per displacement channel: its noise, from the levitated rows
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    if (ch.quantity != MeasuredQuantity::kDisplacement) continue;
    channels.push_back(c);
    shape_rows.push_back(model.sensor_shapes[ch.index].row(ch.axis) *
                         model.params.sensors[ch.index].AxisGain(ch.axis));
    sigma_m.push_back(std::max(1e-12, NoiseSigma(r.values[r.Column(ch.column)], 0, trigger_row)));
  }
  if (channels.empty()) return none("the record has no displacement channel");
  // The directions the sensors see.
  Eigen::MatrixXd a(static_cast<Eigen::Index>(shape_rows.size()), n);
  for (std::size_t i = 0; i < shape_rows.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) = shape_rows[i];
  }
  // Every modal coordinate and its velocity: over the window the modes' own frequencies tell
  // apart what the sensors' shapes alone cannot (a bending mode and a rigid one seen alike at
  // the sensors ring differently), and a mode's state left at the model's own closed-loop value
  // sends the drop elsewhere. A mode the sensors hardly see is stepped as far as makes a
  // micrometre at them.
  const double seen_most = a.cwiseAbs().maxCoeff();
  if (!(seen_most > 0.0)) return none("the displacement channels see no mode");
  std::vector<Eigen::VectorXd> directions;  // 2n each: a position or a velocity direction
  std::vector<double> steps;
  for (int part = 0; part < 2; ++part) {
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(2 * n);
      d(part * n + j) = 1.0;
      directions.push_back(d);
      const double seen = std::max(a.col(j).cwiseAbs().maxCoeff(), 1e-3 * seen_most);
      // 1 um at the sensors, or 1 mm/s: micrometres over the window either way.
      steps.push_back((part == 0 ? 1e-6 : 1e-3) / seen);
    }
  }
  // The AMB axes the record's currents drive in the window (a coil current before a command,
  // as SimulateOnRecord takes them).
  std::array<std::array<int, 2>, kMaxAmbs> column;
  for (auto& c : column) c = {-1, -1};
  for (const MeasuredQuantity q :
       {MeasuredQuantity::kControllerCommand, MeasuredQuantity::kCurrent}) {
    for (const MeasurementChannel& ch : m.channels) {
      if (ch.quantity == q) column[ch.index][ch.axis] = r.Column(ch.column);
    }
  }
  std::vector<CurrentAxis> axes;
  for (std::size_t amb = 0; amb < model.params.ambs.size(); ++amb) {
    for (int axis = 0; axis < 2; ++axis) {
      const int c = column[amb][axis];
      if (c < 0) continue;
      const double sigma = CurrentNoiseSigma(r, c, trigger_row);
      if (sigma > 0.0) axes.push_back({amb, axis, c, sigma});
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
  o.trigger_state_shift = Eigen::VectorXd();
  o.lead_current_correction = nullptr;
  o.keep_states = true;
  const SimulatedRecord base = SimulateOnRecord(declared, m, r, o);
  if (base.status != StepStatus::kOk) {
    return none("the model driven by the record's currents stopped in the lead window (" +
                base.failure.substr(0, base.failure.find('\n')) + ")");
  }

  // The window's samples: displacement channels, record rows from the lead's start to the
  // trigger, where the base run predicts them.
  struct Sample {
    std::size_t k = 0, row = 0;  // k: index into `channels`
  };
  std::vector<Sample> samples;
  std::size_t last_row = base.first_row;
  for (std::size_t k = 0; k < channels.size(); ++k) {
    for (std::size_t j = base.first_row; j < base.first_row + base.rows; ++j) {
      if (r.time_s[j] > trigger_s + 1e-12) break;
      if (std::isfinite(base.values[channels[k]][j])) samples.push_back({k, j});
      last_row = std::max(last_row, j);
    }
  }
  if (samples.size() < 2 * directions.size()) {
    return none(
        fmt::format("{} displacement samples in the {:.3g} ms lead window, fewer than "
                    "twice the {} state directions the sensors see",
                    samples.size(), lead_s * 1e3, directions.size()));
  }
  if (base.states.size() <= last_row || base.states[last_row].size() != 2 * n) {
    return none("the lead window's run kept no state at its last sample");
  }
  const Eigen::Index rows = static_cast<Eigen::Index>(samples.size());
  Eigen::VectorXd e(rows);  // in units of each channel's noise
  for (Eigen::Index i = 0; i < rows; ++i) {
    const Sample& s = samples[static_cast<std::size_t>(i)];
    const std::size_t c = channels[s.k];
    const double measured = r.values[r.Column(m.channels[c].column)][s.row] +
                            options.start_position_shift_m +
                            options.start_velocity_shift_m_s * (r.time_s[s.row] - trigger_s);
    e(i) = (measured - base.values[c][s.row]) / sigma_m[s.k];
  }

  // The unknowns: the state at the window's start along the seen directions (no prior), then
  // the corrections of the measured currents at their knots (prior: the currents' own noise).
  // J maps them to the samples (in noise units), G to the state at the trigger.
  const std::size_t spacing = static_cast<std::size_t>(
      std::max<long long>(1, std::llround(kKnotSpacing_s / r.SampleInterval())));
  const std::size_t first_knot = base.first_row + spacing;
  const std::size_t knots = first_knot <= last_row ? (last_row - first_knot) / spacing + 1 : 0;
  const Eigen::Index n_state = static_cast<Eigen::Index>(directions.size());
  const Eigen::Index n_unknown = n_state + static_cast<Eigen::Index>(axes.size() * knots);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(rows, n_unknown);
  Eigen::MatrixXd to_trigger = Eigen::MatrixXd::Zero(2 * n, n_unknown);
  Eigen::VectorXd prior_sd = Eigen::VectorXd::Zero(n_unknown);  // 0: no prior
  const auto moved_by = [&](const SimulatedRecord& moved, double step, Eigen::Index col,
                            std::size_t shift_rows) {
    for (Eigen::Index i = 0; i < rows; ++i) {
      const Sample& s = samples[static_cast<std::size_t>(i)];
      if (s.row < base.first_row + shift_rows) continue;
      const std::size_t j = s.row - shift_rows;
      const std::size_t c = channels[s.k];
      jacobian(i, col) = (moved.values[c][j] - base.values[c][j]) / step / sigma_m[s.k];
    }
    if (last_row >= base.first_row + shift_rows) {
      const std::size_t j = last_row - shift_rows;
      if (moved.states[j].size() == 2 * n && base.states[j].size() == 2 * n) {
        to_trigger.col(col) = (moved.states[j] - base.states[j]) / step;
      }
    }
  };
  for (std::size_t k = 0; k < directions.size(); ++k) {
    o.state_correction = steps[k] * directions[k];
    const SimulatedRecord moved = SimulateOnRecord(declared, m, r, o);
    if (moved.status != StepStatus::kOk) {
      return none("a sensitivity run of the lead window stopped (" +
                  moved.failure.substr(0, moved.failure.find('\n')) + ")");
    }
    moved_by(moved, steps[k], static_cast<Eigen::Index>(k), 0);
  }
  o.state_correction = Eigen::VectorXd::Zero(2 * n);
  // A knot's response is the first knot's, later by whole knots: in the levitated window the
  // plant is linear and does not change (a magnet-biased AMB's force is linear in its control
  // current, the spin steady over milliseconds).
  constexpr double kPulse_A = 1e-3;
  const std::size_t window_rows = last_row - base.first_row + 1;
  const auto hat = [&](std::size_t knot_row, double height) {
    std::vector<double> v(window_rows, 0.0);
    for (std::size_t j = base.first_row; j <= last_row; ++j) {
      const double d = std::abs(static_cast<double>(j) - static_cast<double>(knot_row));
      if (d < static_cast<double>(spacing)) {
        v[j - base.first_row] = height * (1.0 - d / static_cast<double>(spacing));
      }
    }
    return v;
  };
  for (std::size_t q = 0; q < axes.size() && knots > 0; ++q) {
    auto pulse = std::make_shared<LeadCurrentCorrection>();
    pulse->first_row = base.first_row;
    pulse->A[axes[q].amb][static_cast<std::size_t>(axes[q].axis)] = hat(first_knot, kPulse_A);
    o.lead_current_correction = pulse;
    const SimulatedRecord moved = SimulateOnRecord(declared, m, r, o);
    if (moved.status != StepStatus::kOk) {
      return none("a current-sensitivity run of the lead window stopped (" +
                  moved.failure.substr(0, moved.failure.find('\n')) + ")");
    }
    for (std::size_t kn = 0; kn < knots; ++kn) {
      const Eigen::Index col = n_state + static_cast<Eigen::Index>(q * knots + kn);
      moved_by(moved, kPulse_A, col, kn * spacing);
      // White noise of sigma per sample, seen through hats `spacing` rows apart: its slow part,
      // which is what moves the rotor, has that variance over `spacing` per knot.
      prior_sd(col) = axes[q].sigma_A / std::sqrt(static_cast<double>(spacing));
    }
  }
  if (!jacobian.allFinite() || !e.allFinite() || !to_trigger.allFinite()) {
    return none("the lead window's samples or sensitivities are not finite");
  }

  // Columns scaled to unit norm (the state's) or to their prior (the currents'), then the
  // minimum-norm least-squares solution of the samples and the priors together: state
  // directions the window cannot tell apart (below 1e-6 of the best seen) are left alone.
  Eigen::VectorXd scale(n_unknown);
  const Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  const double largest = norms.head(n_state).maxCoeff();
  if (!(largest > 0.0)) return none("the lead window's samples do not move with the state");
  for (Eigen::Index k = 0; k < n_unknown; ++k) {
    scale(k) = k < n_state ? std::max(norms(k), 1e-12 * largest) : 1.0 / prior_sd(k);
  }
  const Eigen::Index n_prior = n_unknown - n_state;
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(rows + n_prior, n_unknown);
  system.topRows(rows) = jacobian * scale.cwiseInverse().asDiagonal();
  system.bottomRightCorner(n_prior, n_prior).setIdentity();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows + n_prior);
  rhs.head(rows) = e;
  const Eigen::BDCSVD<Eigen::MatrixXd> jsvd(system, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& js = jsvd.singularValues();
  if (!(js.size() > 0 && js(0) > 0.0)) {
    return none("the lead window's samples do not move with the state");
  }
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(js.size());
  for (Eigen::Index k = 0; k < js.size(); ++k) {
    if (js(k) > 1e-6 * js(0)) inverse(k) = 1.0 / js(k);
  }
  const Eigen::VectorXd theta =
      (jsvd.matrixV() * inverse.asDiagonal() * (jsvd.matrixU().transpose() * rhs))
          .cwiseQuotient(scale);
  Eigen::MatrixXd to_state(2 * n, n_state);
  for (std::size_t k = 0; k < directions.size(); ++k) {
    to_state.col(static_cast<Eigen::Index>(k)) = directions[k];
  }
  LeadStateFit fit;
  fit.correction = to_state * theta.head(n_state);
  fit.misfit = (e - jacobian * theta).norm() /
               std::sqrt(static_cast<double>(std::max<Eigen::Index>(rows, 1)));
  if (!fit.correction.allFinite() || !theta.allFinite()) {
    return none("the least-squares correction is not finite");
  }
  if (knots > 0 && !axes.empty()) {
    auto corrected = std::make_shared<LeadCurrentCorrection>();
    corrected->first_row = base.first_row;
    for (std::size_t q = 0; q < axes.size(); ++q) {
      std::vector<double> v(window_rows, 0.0);
      for (std::size_t kn = 0; kn < knots; ++kn) {
        const std::vector<double> h = hat(
            first_knot + kn * spacing, theta(n_state + static_cast<Eigen::Index>(q * knots + kn)));
        for (std::size_t j = 0; j < window_rows; ++j) v[j] += h[j];
      }
      corrected->A[axes[q].amb][static_cast<std::size_t>(axes[q].axis)] = std::move(v);
    }
    fit.current_correction = corrected;
  }

  // How uncertain the state at the trigger is: the unknowns' covariance (the samples are in
  // units of their noise, the priors in theirs) is V S^-2 V^T in the scaled columns; mapped to
  // the state at the trigger it is G P G^T. Two sets of axes of it:
  const Eigen::MatrixXd g_scaled = to_trigger * scale.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd gv = g_scaled * jsvd.matrixV() * inverse.asDiagonal();
  const Eigen::MatrixXd cov_state = gv * gv.transpose();
  // - its principal axes where the sensors see them (positions, and velocities over a
  //   millisecond, at the displacement channels), each the state shift that the covariance
  //   makes most likely to go with it, the three largest: the spread of most records' starts
  //   (twelve redraws of the noise of the flexible rig's clean seed 8: their departures' RMS
  //   1.04 times what these predict, 0.52 times what all axes predict);
  constexpr double kSeenOver_s = 1e-3;
  Eigen::MatrixXd seen = Eigen::MatrixXd::Zero(2 * a.rows(), 2 * n);
  seen.topLeftCorner(a.rows(), n) = a;
  seen.bottomRightCorner(a.rows(), n) = kSeenOver_s * a;
  const Eigen::MatrixXd cov_seen = seen * cov_state * seen.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> seen_axes(cov_seen);
  if (seen_axes.info() == Eigen::Success) {
    const Eigen::VectorXd& lambda = seen_axes.eigenvalues();  // ascending
    for (Eigen::Index k = lambda.size() - 1; k >= 0 && lambda.size() - k <= 3; --k) {
      if (!(lambda(k) > 1e-12 * lambda(lambda.size() - 1)) || !(lambda(k) > 0.0)) break;
      const Eigen::VectorXd shift =
          cov_state * seen.transpose() * seen_axes.eigenvectors().col(k) / std::sqrt(lambda(k));
      if (shift.allFinite()) fit.uncertainty.push_back(shift);
    }
  }
  // - every principal axis of it, scaled to unit variances (scale-free across positions and
  //   velocities): a rotor that the power loss leaves unstable grows along its own unstable
  //   directions whatever share of the covariance they hold, and a record whose noise drew the
  //   estimate off along them departs far beyond the bulk (that seed's own record: 0.046,
  //   against 0.006 from the seen axes; its exact copy 0.0008). A shift of the state along
  //   these finds such a record's start (start_state_shift.hpp).
  Eigen::VectorXd sd = cov_state.diagonal().cwiseMax(0.0).cwiseSqrt();
  const double sd_max = sd.maxCoeff();
  if (sd_max > 0.0 && std::isfinite(sd_max)) {
    for (Eigen::Index k = 0; k < sd.size(); ++k) sd(k) = std::max(sd(k), 1e-12 * sd_max);
    const Eigen::MatrixXd correlation =
        sd.cwiseInverse().asDiagonal() * cov_state * sd.cwiseInverse().asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(correlation);
    if (eig.info() == Eigen::Success) {
      const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
      const double top = lambda(lambda.size() - 1);
      for (Eigen::Index k = lambda.size() - 1; k >= 0; --k) {
        if (!(lambda(k) > kUncertaintyAxisFloor * top)) break;
        const Eigen::VectorXd shift =
            sd.asDiagonal() * eig.eigenvectors().col(k) * std::sqrt(lambda(k));
        if (shift.allFinite()) fit.uncertainty_all.push_back(shift);
      }
    }
  }
  Eigen::Index used = 0;
  for (Eigen::Index k = 0; k < inverse.size(); ++k) used += inverse(k) > 0.0 ? 1 : 0;
  fit.fitted = true;
  fit.note = fmt::format(
      "{} samples of {} displacement channels over the {:.3g} ms lead window; the state at its "
      "start along {} seen directions and the measured currents of {} AMB axes at {} knots "
      "each ({} of {} unknowns resolved); the samples left at {:.2g} times their noise",
      samples.size(), channels.size(), lead_s * 1e3, directions.size(), axes.size(), knots, used,
      n_unknown, fit.misfit);
  return fit;
}

}  // namespace ambdrop
