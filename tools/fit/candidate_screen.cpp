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
  if (valid < 3) return out;
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
  return out;
}

}  // namespace ambdrop
