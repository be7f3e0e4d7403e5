#include "tools/fit/candidate_screen.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_selection.hpp"

namespace ambdrop {
namespace {

// Grid over the range on which the quadratic's squared norm is minimised: its cost is a 3x3
// quadratic form per point, nothing beside a run.
constexpr int kGrid = 201;

// A size declared above 0 is searched by its logarithm: a factor of 2 either way is symmetric.
struct Axis {
  bool log = false;
  double To(double x) const { return log ? std::log(x) : x; }
  double From(double u) const { return log ? std::exp(u) : u; }
};

struct Span {
  double u0, lo, hi;  // declared, lower and upper end, on the search axis
};

// One run a sixteenth of the range from the declared value, toward the wider side, and the
// Gauss-Newton step its slope predicts. The halfway runs see a key whose true value lies near
// the declared one only through a quadratic over a span where a drop's response is far from
// quadratic: on the magnet-biased flexible rig a sensor's 23 um y offset, screened at +-50 um,
// was predicted to take the drop's start from 0.078 to 0.069 only and was never fitted, where
// the true offset takes it to 0.0055. The slope near the declared value sees it. A whole-sample
// key (a delay) has no slope.
void NearRun(const ConfigVariants& declared, const RecordCost& cost, const Effect& effect,
             const Axis& axis, const Span& span, const Eigen::VectorXd& r0, Screening* out) {
  constexpr double kNearFraction = 1.0 / 16.0;
  const EffectParameter& p = effect.parameters.front();
  if (p.quantum > 0.0 || !(span.hi > span.lo)) return;
  const double sign = span.hi - span.u0 >= span.u0 - span.lo ? 1.0 : -1.0;
  const double du = sign * kNearFraction * (span.hi - span.lo);
  bool refused = false;
  const Eigen::VectorXd near =
      ResidualWithEffects(declared, cost, {&effect}, {{axis.From(span.u0 + du)}}, &refused);
  ++out->runs;
  if (refused || !near.allFinite() || near.size() != r0.size()) return;
  const Eigen::VectorXd slope = near - r0;  // per du
  const double moved = slope.squaredNorm();
  out->reach = std::max(out->reach, OverallRms(cost, moved));
  if (near.squaredNorm() < out->predicted_sse) {
    out->predicted_sse = near.squaredNorm();
    out->best_value = axis.From(span.u0 + du);
  }
  if (!(moved > 0.0)) return;
  // r(t) = r0 + t slope, t in units of du, inside the range and within a quarter of it of the
  // declared value: farther out the halfway runs are the better guide.
  constexpr double kTrust = 4.0;
  const double to_lo = (span.lo - span.u0) / du, to_hi = (span.hi - span.u0) / du;
  const double t = std::clamp(-r0.dot(slope) / moved, std::max(-kTrust, std::min(to_lo, to_hi)),
                              std::min(kTrust, std::max(to_lo, to_hi)));
  const double sse = (r0 + t * slope).squaredNorm();
  if (sse < out->predicted_sse) {
    out->predicted_sse = sse;
    out->best_value = std::clamp(axis.From(span.u0 + t * du), p.lower, p.upper);
  }
}

}  // namespace

Screening ScreenCandidate(const ConfigVariants& declared, const RecordCost& cost,
                          const Effect& effect, const Eigen::VectorXd& residual_before) {
  Screening out;
  const EffectParameter& p = effect.parameters.front();
  const double x0 = std::clamp(p.starts.empty() ? p.lower : p.starts.front(), p.lower, p.upper);
  const Axis axis{p.lower > 0.0 && x0 > 0.0};
  const double u0 = axis.To(x0), lo = axis.To(p.lower), hi = axis.To(p.upper);
  const double below = u0 - lo, above = hi - u0;
  const double tiny = 1e-9 * (hi - lo);
  // Halfway to either end; at an end (a key declared 0), a quarter and half the way in.
  std::array<double, 2> u{};
  if (below > tiny && above > tiny) {
    u = {u0 - 0.5 * below, u0 + 0.5 * above};
  } else if (above > tiny) {
    u = {u0 + 0.25 * above, u0 + 0.5 * above};
  } else {
    u = {u0 - 0.25 * below, u0 - 0.5 * below};
  }
  std::array<double, 3> nodes = {u0, u[0], u[1]};
  std::array<Eigen::VectorXd, 3> r = {residual_before, {}, {}};
  int valid = 1;
  std::array<bool, 3> ok = {true, false, false};
  for (int i = 1; i < 3; ++i) {
    bool refused = false;
    r[i] = ResidualWithEffects(declared, cost, {&effect}, {{axis.From(nodes[i])}}, &refused);
    ++out.runs;
    if (refused) continue;
    ok[i] = true;
    ++valid;
    out.reach = std::max(out.reach, OverallRms(cost, (r[i] - residual_before).squaredNorm()));
  }
  for (int i = 0; i < 3; ++i) {
    if (!ok[i]) continue;
    const double sse = r[i].squaredNorm();
    if (sse < out.predicted_sse) {
      out.predicted_sse = sse;
      out.best_value = axis.From(nodes[i]);
    }
  }
  if (valid < 3) {
    NearRun(declared, cost, effect, axis, {u0, lo, hi}, residual_before, &out);
    return out;
  }
  // r(u) = sum_j L_j(u) r_j (Lagrange), so |r(u)|^2 = L^T G L with G the runs' Gram matrix, and
  // |r(u) - r_0|^2 = L^T G L - 2 L^T g + |r_0|^2 with g_j = r_j . r_0.
  Eigen::Matrix3d gram;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) gram(i, j) = r[i].dot(r[j]);
  }
  const Eigen::Vector3d to_declared = gram.col(0);
  double farthest = 0.0;
  for (int g = 0; g < kGrid; ++g) {
    const double at = lo + (hi - lo) * g / (kGrid - 1);
    Eigen::Vector3d basis;
    for (int j = 0; j < 3; ++j) {
      double l = 1.0;
      for (int m = 0; m < 3; ++m) {
        if (m != j) l *= (at - nodes[m]) / (nodes[j] - nodes[m]);
      }
      basis(j) = l;
    }
    const double sse = std::max(0.0, basis.dot(gram * basis));
    farthest =
        std::max(farthest, basis.dot(gram * basis) - 2.0 * basis.dot(to_declared) + gram(0, 0));
    if (sse < out.predicted_sse) {
      out.predicted_sse = sse;
      out.best_value = std::clamp(axis.From(at), p.lower, p.upper);
    }
  }
  // The reach anywhere in the range, as the quadratic carries the runs out to its ends: a key a
  // record shows at its true value, twice as far off as the runs went, is decidable.
  out.reach = std::max(out.reach, OverallRms(cost, std::max(0.0, farthest)));
  NearRun(declared, cost, effect, axis, {u0, lo, hi}, residual_before, &out);
  return out;
}

}  // namespace ambdrop
