#include "tools/fit/start_state_shift.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "tools/fit/effect_selection.hpp"
#include "tools/fit/parallel_for.hpp"
#include "tools/fit/trigger_state_probes.hpp"

namespace ambdrop {

namespace {

// The upper quantile of chi-square with `dof` degrees of freedom at the normal quantile
// `normal_z` (Wilson and Hilferty 1931): a shift's squared size over the directions the
// residual determines is that distributed on a record whose only error is the estimate's.
double ChiSquareQuantile(double dof, double normal_z) {
  if (!(dof > 0.0)) return 0.0;
  const double c = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - c + normal_z * std::sqrt(c), 3);
}

// The least shift (in the prior's norm) that the chord model `r(z) = r0 + J (z - z0)` predicts to
// leave a squared residual of `sse_target`: Morozov's discrepancy principle (Engl, Hanke &
// Neubauer 1996, Sec. 4.3), the Tikhonov weight mu chosen where the predicted residual meets the
// target. Empty where no shift is predicted to reach it.
std::optional<Eigen::VectorXd> LeastShiftPredictedWithin(const Eigen::MatrixXd& jacobian,
                                                         const Eigen::VectorXd& z0,
                                                         const Eigen::VectorXd& r0,
                                                         double sse_target) {
  const Eigen::VectorXd b = jacobian * z0 - r0;  // r(z) = J z - b
  if (b.squaredNorm() <= sse_target) return Eigen::VectorXd::Zero(z0.size());
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (!(sv.size() > 0 && sv(0) > 0.0)) return std::nullopt;
  const Eigen::VectorXd ub = svd.matrixU().transpose() * b;
  const double outside = std::max(0.0, b.squaredNorm() - ub.squaredNorm());
  const auto predicted_sse = [&](double mu) {
    double sse = outside;
    for (Eigen::Index i = 0; i < sv.size(); ++i) {
      sse += std::pow(mu / (sv(i) * sv(i) + mu) * ub(i), 2);
    }
    return sse;
  };
  const auto shift = [&](double mu) -> Eigen::VectorXd {
    Eigen::VectorXd w(sv.size());
    for (Eigen::Index i = 0; i < sv.size(); ++i) w(i) = sv(i) / (sv(i) * sv(i) + mu) * ub(i);
    return svd.matrixV() * w;
  };
  const double s2 = sv(0) * sv(0);
  double lo = std::log(1e-12 * s2), hi = std::log(1e12 * s2);
  if (predicted_sse(std::exp(lo)) > sse_target) return std::nullopt;
  // The predicted residual grows with mu, the shift shrinks: the largest mu within the target.
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (predicted_sse(std::exp(mid)) <= sse_target ? lo : hi) = mid;
  }
  const Eigen::VectorXd z = shift(std::exp(lo));
  if (!z.allFinite()) return std::nullopt;
  return z;
}

}  // namespace

StartStateShift FitStartStateShift(const RecordCost& cost, const Eigen::VectorXd& residual_before,
                                   int threads, double target_rms) {
  StartStateShift out;
  out.rms_before = OverallRms(cost, residual_before.squaredNorm());
  out.rms_after = out.rms_before;
  if (!cost.measurement().trigger_state_from_record || cost.size() == 0) return out;
  const SimulatedRecord base = cost.Simulate(cost.declared());
  const std::vector<RecordRunOptions> probes =
      TriggerStateProbes(cost, base, TriggerStateAxes::kAll);
  const Eigen::Index k = static_cast<Eigen::Index>(probes.size() / 2);
  if (k == 0) return out;
  std::vector<Eigen::VectorXd> moved(probes.size());
  ParallelFor(probes.size(), threads, [&](std::size_t i) {
    moved[i] = cost.Residual(
        SimulateOnRecord(cost.declared(), cost.measurement(), cost.record(), probes[i]));
  });
  out.runs = static_cast<int>(probes.size());
  const Eigen::Index m = residual_before.size();
  Eigen::MatrixXd jacobian(m, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const std::size_t i = static_cast<std::size_t>(2 * j);
    jacobian.col(j) = 0.5 * (moved[i] - moved[i + 1]);
  }
  if (!jacobian.allFinite() || !residual_before.allFinite()) return out;
  // The samples' variance: the record's noise floor spread over the cost's entries (OverallRms
  // divides the sum of squares by the channels).
  const double noise = cost.NoiseFloor();
  const double variance =
      noise * noise * cost.channels() / static_cast<double>(std::max<Eigen::Index>(m, 1));
  if (!(variance > 0.0)) return out;
  const Eigen::MatrixXd normal = jacobian.transpose() * jacobian / variance;
  const Eigen::MatrixXd system = normal + Eigen::MatrixXd::Identity(k, k);
  const Eigen::LDLT<Eigen::MatrixXd> solve(system);
  if (solve.info() != Eigen::Success) return out;
  // The number of directions the residual determines: the trace of the data's share of the
  // posterior precision.
  out.directions = (solve.solve(normal)).trace();
  out.plausible_sigmas = std::sqrt(ChiSquareQuantile(std::max(out.directions, 1.0), 2.576));
  const auto objective = [&](const Eigen::VectorXd& r, const Eigen::VectorXd& z) {
    return r.squaredNorm() / variance + z.squaredNorm();
  };
  Eigen::VectorXd z = Eigen::VectorXd::Zero(k);
  Eigen::VectorXd r = residual_before;
  double best = objective(r, z);
  // Gauss-Newton with the probes' Jacobian held (a chord method), each step checked by a run
  // and halved where the objective rose. The start ends just after the first impact, whose
  // timing makes the residual curve: on the clean seed 8 the first step alone stopped at 16
  // standard deviations and 0.019, the steps after it reach 3.9 and 0.0038; secant updates of
  // the Jacobian wandered off to 14-18 standard deviations on records that needed none.
  constexpr int kRuns = 8;
  double length = 1.0;
  for (int run = 0; run < kRuns; ++run) {
    const Eigen::VectorXd step = -solve.solve(jacobian.transpose() * r / variance + z);
    if (!step.allFinite()) break;
    const Eigen::VectorXd trial = z + length * step;
    const SimulatedRecord sim = SimulateOnRecord(cost.declared(), cost.measurement(), cost.record(),
                                                 ShiftedAlong(cost, probes, trial));
    ++out.runs;
    const Eigen::VectorXd r_trial =
        sim.status == StepStatus::kOk ? cost.Residual(sim) : Eigen::VectorXd();
    const double value = r_trial.size() > 0 && r_trial.allFinite()
                             ? objective(r_trial, trial)
                             : std::numeric_limits<double>::infinity();
    if (value < best) {
      best = value;
      z = trial;
      r = r_trial;
      length = std::min(1.0, 2.0 * length);
    } else {
      length *= 0.5;
    }
  }
  out.fitted = true;
  out.sigmas = z.norm();
  out.rms_after = OverallRms(cost, r.squaredNorm());
  // On the flexible truth rig's clean seed 102 the maximum a posteriori shift took the start
  // from 0.036 to 0.0042 at 6.1 standard deviations (5.2 plausible over 11 directions), its
  // noise allowing 0.0047; drawn back along its ray, 5.8; the least shift within the noise, 1.2
  // (seed 8: 3.7 and 2.4): the maximum a posteriori one spends most of its size fitting the
  // noise's wiggles.
  if (target_rms > 0.0 && out.rms_after <= target_rms && z.norm() > 0.0) {
    // The least shift the chord model predicts within a share of the target, linearised where
    // the last run was (each run's own residual, the probes' Jacobian), kept where a run
    // confirms it within the target; where none is confirmed, the boundary between the last
    // confirmed shift and the nearest unconfirmed one (a bisection). Then drawn back along its
    // ray.
    const double channels = static_cast<double>(std::max(cost.channels(), 1));
    const auto run_at = [&](const Eigen::VectorXd& at) {
      const SimulatedRecord sim = SimulateOnRecord(cost.declared(), cost.measurement(),
                                                   cost.record(), ShiftedAlong(cost, probes, at));
      ++out.runs;
      const Eigen::VectorXd res =
          sim.status == StepStatus::kOk ? cost.Residual(sim) : Eigen::VectorXd();
      return res.size() > 0 && res.allFinite() ? res : Eigen::VectorXd();
    };
    Eigen::VectorXd at = z, at_r = r;
    std::vector<Eigen::VectorXd> unconfirmed;
    constexpr int kLeastShiftRuns = 4;
    for (int i = 0; i < kLeastShiftRuns; ++i) {
      std::optional<Eigen::VectorXd> least;
      for (const double share : {0.9, 0.75, 0.55}) {
        least = LeastShiftPredictedWithin(jacobian, at, at_r,
                                          std::pow(share * target_rms, 2) * channels);
        if (least && least->norm() < 0.98 * z.norm()) break;
        least.reset();
      }
      if (!least) break;
      const Eigen::VectorXd r_least = run_at(*least);
      if (r_least.size() == 0) break;
      const double rms = OverallRms(cost, r_least.squaredNorm());
      if (rms <= target_rms) {
        z = *least;
        out.rms_after = rms;
      } else {
        unconfirmed.push_back(*least);
      }
      at = *least;
      at_r = r_least;
    }
    const Eigen::VectorXd* nearest = nullptr;  // the largest unconfirmed shift below z
    for (const Eigen::VectorXd& u : unconfirmed) {
      if (u.norm() < z.norm() && (!nearest || u.norm() > nearest->norm())) nearest = &u;
    }
    if (nearest) {
      Eigen::VectorXd inside_z = z;
      Eigen::VectorXd outside_z = *nearest;
      constexpr int kSegmentBisections = 4;
      for (int i = 0; i < kSegmentBisections; ++i) {
        const Eigen::VectorXd mid = 0.5 * (inside_z + outside_z);
        const Eigen::VectorXd r_mid = run_at(mid);
        const double rms = r_mid.size() > 0 ? OverallRms(cost, r_mid.squaredNorm())
                                            : std::numeric_limits<double>::infinity();
        if (rms <= target_rms) {
          inside_z = mid;
          out.rms_after = rms;
        } else {
          outside_z = mid;
        }
      }
      z = inside_z;
    }
    double inside = 1.0, outside = 0.0;
    double rms_inside = out.rms_after;
    constexpr int kBisections = 6;
    for (int i = 0; i < kBisections; ++i) {
      const double t = 0.5 * (inside + outside);
      const Eigen::VectorXd r_t = run_at(t * z);
      const double rms = r_t.size() > 0 ? OverallRms(cost, r_t.squaredNorm())
                                        : std::numeric_limits<double>::infinity();
      if (rms <= target_rms) {
        inside = t;
        rms_inside = rms;
      } else {
        outside = t;
      }
    }
    out.sigmas = inside * z.norm();
    out.rms_after = rms_inside;
  }
  return out;
}

}  // namespace ambdrop
