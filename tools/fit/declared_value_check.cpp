#include "tools/fit/declared_value_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "tools/fit/effect_selection_internal.hpp"
#include "tools/fit/not_a_number.hpp"
#include "tools/fit/parallel_for.hpp"

namespace ambdrop {
namespace {

// Two values correlated at least this much in the fit's covariance are tried along their valley.
constexpr double kTradeCorrelation = 0.8;

// Where along its range `p` makes `cost` least: a golden-section search (in the logarithm of a
// size known to its decade), 12 runs, ending within 0.5 % of the range of the least of a
// valley's cross-section.
double LeastAlong(const EffectParameter& p, const std::function<double(double)>& cost) {
  const bool log = p.log_scale && p.lower > 0.0;
  const auto value = [&](double u) { return log ? std::exp(u) : u; };
  double lo = log ? std::log(p.lower) : p.lower, hi = log ? std::log(p.upper) : p.upper;
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = hi - r * (hi - lo), b = lo + r * (hi - lo);
  double fa = cost(value(a)), fb = cost(value(b));
  for (int i = 0; i < 10; ++i) {
    if (fa <= fb) {
      hi = b, b = a, fb = fa;
      a = hi - r * (hi - lo);
      fa = cost(value(a));
    } else {
      lo = a, a = b, fa = fb;
      b = lo + r * (hi - lo);
      fb = cost(value(b));
    }
  }
  return value(fa <= fb ? a : b);
}

}  // namespace

void MarkValuesTheRecordDoesNotNeed(
    const ConfigVariants& declared, const std::vector<Effect>& library, int threads,
    const std::function<bool(const ModelParams& params, double* judged_rms)>& explains,
    EffectFit* fit) {
  const std::vector<const Effect*> effects = EffectsOf(*fit, library);
  struct Item {
    std::size_t effect, index, estimate;
  };
  std::vector<Item> items;
  std::size_t estimate = 0, count = 0;
  for (std::size_t e = 0; e < effects.size(); ++e) count += effects[e]->parameters.size();
  // One value alone set back is the declared model: the verdict has judged that already.
  if (count < 2 || fit->parameters.size() != count) return;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    for (std::size_t i = 0; i < effects[e]->parameters.size(); ++i, ++estimate) {
      const EffectParameter& p = effects[e]->parameters[i];
      if (!std::isfinite(p.declared) || p.periodic) continue;
      if (fit->values[e][i] == p.declared) continue;
      items.push_back({e, i, estimate});
    }
  }
  std::vector<char> open(items.size(), 0);
  std::vector<double> rms(items.size(), 0.0);
  const auto explained_at = [&](const std::vector<std::vector<double>>& values, double* judged) {
    ModelParams params;
    try {
      params = WithEffects(declared, effects, values);
    } catch (const ConfigError&) {
      return false;  // the config refuses the value in this company: it is needed
    }
    return explains(params, judged);
  };
  ParallelFor(items.size(), threads, [&](std::size_t k) {
    const Item& item = items[k];
    std::vector<std::vector<double>> values = fit->values;
    values[item.effect][item.index] = effects[item.effect]->parameters[item.index].declared;
    open[k] = explained_at(values, &rms[k]);
  });
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!open[k]) continue;
    ParameterEstimate& est = fit->parameters[items[k].estimate];
    est.decided = false;
    est.declared_rms = rms[k];
  }

  // A value set back alone is tested against the record with its partners where they were
  // fitted; where two values trade along a valley of the cost (a chain's delay against its
  // low-pass: a free fall through either differs only in a constant, d^2 against 2 tau^2), the
  // record decides their combination and each moves freely along it, yet set back alone either
  // one leaves the sum short and seems decided. So each value is set back with a partner moved
  // along the valley: as the fit's covariance gives it where the two are correlated, or, for a
  // partner of the same effect that the covariance leaves out (at a bound: a lag fitted all
  // delay and no filter), wherever along its range the record's judged part is least. Where
  // the model still explains the record there, the pair decides only its combination.
  const std::size_t n = fit->parameters.size();
  const bool have_covariance = fit->covariance.size() == n * n;
  const auto cov = [&](std::size_t a, std::size_t b) {
    return have_covariance ? fit->covariance[a * n + b] : kNaN;
  };
  // |rho| of two values, NaN where the covariance leaves either out.
  const auto correlation = [&](std::size_t a, std::size_t b) {
    const double caa = cov(a, a), cbb = cov(b, b), cab = cov(a, b);
    return caa > 0.0 && cbb > 0.0 && std::isfinite(cab) ? std::abs(cab) / std::sqrt(caa * cbb)
                                                        : kNaN;
  };
  std::vector<Item> all;  // every value, as (effect, index, estimate)
  for (std::size_t e = 0, k = 0; e < effects.size(); ++e) {
    for (std::size_t i = 0; i < effects[e]->parameters.size(); ++i, ++k) all.push_back({e, i, k});
  }
  struct Trade {
    std::size_t moved;  // index into items
    Item partner;
    double slope;  // d partner / d moved along the valley from the covariance; NaN: searched
  };
  std::vector<Trade> trades;
  for (std::size_t a = 0; a < items.size(); ++a) {
    if (open[a]) continue;
    for (const Item& b : all) {
      if (b.estimate == items[a].estimate) continue;
      const EffectParameter& pb = effects[b.effect]->parameters[b.index];
      if (pb.periodic || pb.quantum > 0.0 || !(pb.upper > pb.lower)) continue;
      const std::size_t ia = items[a].estimate, ib = b.estimate;
      const double rho = correlation(ia, ib);
      if (std::isfinite(rho)) {
        if (rho >= kTradeCorrelation) trades.push_back({a, b, cov(ia, ib) / cov(ia, ia)});
      } else if (b.effect == items[a].effect) {
        trades.push_back({a, b, kNaN});
      }
    }
  }
  std::vector<char> traded(trades.size(), 0);
  std::vector<double> trade_rms(trades.size(), 0.0), partner_at(trades.size(), kNaN);
  ParallelFor(trades.size(), threads, [&](std::size_t k) {
    const Trade& t = trades[k];
    const Item& moved = items[t.moved];
    const EffectParameter& pm = effects[moved.effect]->parameters[moved.index];
    const EffectParameter& pp = effects[t.partner.effect]->parameters[t.partner.index];
    std::vector<std::vector<double>> values = fit->values;
    const double from = values[t.partner.effect][t.partner.index];
    values[moved.effect][moved.index] = pm.declared;
    const auto judged_at = [&](double partner, double* rms) {
      values[t.partner.effect][t.partner.index] = partner;
      return explained_at(values, rms);
    };
    double along = kNaN;
    if (std::isfinite(t.slope)) {
      along = from + t.slope * (pm.declared - fit->values[moved.effect][moved.index]);
      // Past its bounds the valley leaves what the fit may take: that way is not tested.
      if (!(along >= pp.lower && along <= pp.upper)) return;
    } else {
      along = LeastAlong(pp, [&](double partner) {
        double rms = kNaN;
        judged_at(partner, &rms);
        return std::isfinite(rms) ? rms : std::numeric_limits<double>::infinity();
      });
    }
    partner_at[k] = along;
    traded[k] = judged_at(along, &trade_rms[k]);
  });
  for (std::size_t k = 0; k < trades.size(); ++k) {
    if (!traded[k]) continue;
    const Item& moved = items[trades[k].moved];
    const Item& partner = trades[k].partner;
    const double shift = effects[moved.effect]->parameters[moved.index].declared -
                         fit->values[moved.effect][moved.index];
    // The valley through the fitted point and the point found: partner = slope * moved + c.
    const double slope = (partner_at[k] - fit->values[partner.effect][partner.index]) / shift;
    const std::size_t ia = moved.estimate, ib = partner.estimate;
    for (const auto& [self, other, self_slope] :
         {std::tuple{ia, ib, slope}, std::tuple{ib, ia, 1.0 / slope}}) {
      ParameterEstimate& est = fit->parameters[self];
      if (!est.traded_with.empty() || !std::isfinite(self_slope)) continue;
      const ParameterEstimate& with = fit->parameters[other];
      est.decided = false;
      est.traded_with = with.effect + "/" + with.name;
      est.trade_slope = self_slope;
      est.trade_combination = with.value - self_slope * est.value;
      // Its variance along the valley's normal, where the covariance knows both.
      const double c_oo = cov(other, other), c_so = cov(self, other), c_ss = cov(self, self);
      const double var = c_oo - 2.0 * self_slope * c_so + self_slope * self_slope * c_ss;
      est.trade_combination_sigma = std::isfinite(var) ? std::sqrt(std::max(0.0, var)) : kNaN;
      if (self == ia) est.declared_rms = trade_rms[k];
    }
  }

  // A value with no declared one (a law the model lacks: a Dahl ribbon's slipping stiffness)
  // cannot be set back; its sigma, a curvature, says it is known where the record is explained
  // as well far from it (the 4-DOF truth rig's Dahl record of seed 613: 8.8e5 +- 5.6e4 N/m,
  // truth 3e5). So it is moved to the edge of what ParameterDecided calls decided, each way,
  // its most correlated partner (|rho| >= kTradeCorrelation) following the valley.
  struct Edge {
    Item item;
    double to = 0.0;
    std::optional<Item> partner;
    double slope = 0.0;
  };
  std::vector<Edge> edges;
  for (const Item& a : all) {
    const EffectParameter& p = effects[a.effect]->parameters[a.index];
    ParameterEstimate& est = fit->parameters[a.estimate];
    if (std::isfinite(p.declared) || p.periodic || p.quantum > 0.0 || !est.decided) continue;
    const double v = fit->values[a.effect][a.index];
    std::optional<Item> partner;
    double slope = 0.0, best = kTradeCorrelation;
    for (const Item& b : all) {
      const EffectParameter& pb = effects[b.effect]->parameters[b.index];
      if (b.estimate == a.estimate || pb.periodic || pb.quantum > 0.0) continue;
      const double rho = correlation(a.estimate, b.estimate);
      if (rho >= best) {
        best = rho, partner = b;
        slope = cov(a.estimate, b.estimate) / cov(a.estimate, a.estimate);
      }
    }
    const double width = DecidedHalfWidth(p, v);
    for (const double to : {v - width, v + width}) {
      if (to >= p.lower && to <= p.upper && to != v) edges.push_back({a, to, partner, slope});
    }
  }
  std::vector<char> edge_explains(edges.size(), 0);
  ParallelFor(edges.size(), threads, [&](std::size_t k) {
    const Edge& g = edges[k];
    std::vector<std::vector<double>> values = fit->values;
    const double from = values[g.item.effect][g.item.index];
    values[g.item.effect][g.item.index] = g.to;
    if (g.partner) {
      const EffectParameter& pp = effects[g.partner->effect]->parameters[g.partner->index];
      double& w = values[g.partner->effect][g.partner->index];
      w = std::clamp(w + g.slope * (g.to - from), pp.lower, pp.upper);
    }
    double rms = kNaN;
    edge_explains[k] = explained_at(values, &rms);
  });
  for (std::size_t k = 0; k < edges.size(); ++k) {
    ParameterEstimate& est = fit->parameters[edges[k].item.estimate];
    if (!edge_explains[k] || std::isfinite(est.explained_at)) continue;
    est.decided = false;
    est.explained_at = edges[k].to;
  }
}

}  // namespace ambdrop
