#include "tools/fit/effect_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unsupported/Eigen/LevenbergMarquardt>

#include "tools/fit/not_a_number.hpp"

namespace ambdrop {
namespace {

struct Flat {
  const Effect* effect;
  std::size_t effect_index;
  const EffectParameter* parameter;
};

// Bounded parameters are searched through p = lo + (hi - lo) (1 + sin z) / 2, so that the
// unconstrained Levenberg-Marquardt never leaves the bounds (a log-scaled one the same in its
// logarithm); angles are searched as they are.
double ToValue(const EffectParameter& p, double z) {
  if (p.periodic) return z;
  if (p.log_scale) {
    const double lo = std::log(p.lower), hi = std::log(p.upper);
    return std::clamp(std::exp(lo + (hi - lo) * 0.5 * (1.0 + std::sin(z))), p.lower, p.upper);
  }
  return p.lower + (p.upper - p.lower) * 0.5 * (1.0 + std::sin(z));
}
double ToSearch(const EffectParameter& p, double v) {
  if (p.periodic) return v;
  if (p.log_scale) {
    const double lo = std::log(p.lower), hi = std::log(p.upper);
    const double at = std::log(std::clamp(v, p.lower, p.upper));
    return std::asin(std::clamp(2.0 * (at - lo) / (hi - lo) - 1.0, -1.0, 1.0));
  }
  const double u = std::clamp(2.0 * (v - p.lower) / (p.upper - p.lower) - 1.0, -1.0, 1.0);
  return std::asin(u);
}
double Slope(const EffectParameter& p, double z) {
  if (p.periodic) return 1.0;
  if (p.log_scale) {
    return ToValue(p, z) * 0.5 * (std::log(p.upper) - std::log(p.lower)) * std::cos(z);
  }
  return 0.5 * (p.upper - p.lower) * std::cos(z);
}

// Searches from every combination of starts up to this many (9: two parameters of three).
constexpr std::size_t kMaxStartCombinations = 9;

// Searched from the best this many of the starts, ranked by their cost.
constexpr std::size_t kSearchedStarts = 3;

// ~1 % of the range: contact makes the cost rough at finer scales.
constexpr double kStep = 0.02;

// The residuals one fit has already run, by search point: the runs are deterministic, and
// Levenberg-Marquardt asks again for points it has (each Jacobian starts with the residual at
// the point its last accepted step computed; each search, with its start, which the ranking of
// starts ran; the uncertainty's Jacobian, with the optimum). A third of a one-parameter
// search's runs were such repeats.
class RunMemo {
 public:
  const Eigen::VectorXd* Find(const RecordCost* cost, const Eigen::VectorXd& z) const {
    for (const Entry& e : entries_) {
      if (e.cost == cost && e.z.size() == z.size() && (e.z.array() == z.array()).all()) {
        return &e.residual;
      }
    }
    return nullptr;
  }
  void Add(const RecordCost* cost, const Eigen::VectorXd& z, const Eigen::VectorXd& residual) {
    if (entries_.size() >= kEntries) entries_.erase(entries_.begin());
    entries_.push_back({cost, z, residual});
  }

 private:
  // A search revisits only its latest points; the starts are few.
  static constexpr std::size_t kEntries = 12;
  struct Entry {
    const RecordCost* cost;
    Eigen::VectorXd z;
    Eigen::VectorXd residual;
  };
  std::vector<Entry> entries_;
};

struct Problem : Eigen::DenseFunctor<double> {
  Problem(const ConfigVariants& d, const RecordCost& c, const std::vector<const Effect*>& e,
          const std::vector<Flat>& f, int budget, RunMemo* m)
      : DenseFunctor<double>(static_cast<int>(f.size()), static_cast<int>(c.size())),
        declared(d),
        cost(c),
        effects(e),
        flat(f),
        runs_left(budget),
        memo(m) {}

  std::vector<std::vector<double>> Values(const Eigen::VectorXd& z) const {
    std::vector<std::vector<double>> v(effects.size());
    for (std::size_t i = 0; i < flat.size(); ++i) {
      v[flat[i].effect_index].push_back(
          ToValue(*flat[i].parameter, z(static_cast<Eigen::Index>(i))));
    }
    return v;
  }
  // The budget counts every residual asked for, repeated or not, so that a search takes the
  // same path as it would without the memo; `runs` counts the model runs made.
  Eigen::VectorXd Run(const Eigen::VectorXd& z) {
    --runs_left;
    if (const Eigen::VectorXd* known = memo->Find(&cost, z)) return *known;
    ++runs;
    Eigen::VectorXd r = ResidualWithEffects(declared, cost, effects, Values(z));
    memo->Add(&cost, z, r);
    return r;
  }
  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& fvec) {
    if (runs_left <= 0) return -1;  // out of budget: LM stops and keeps the best so far
    fvec = Run(z);
    const double sse = fvec.squaredNorm();
    if (sse < best_sse) {
      best_sse = sse;
      best_z = z;
    }
    return 0;
  }
  int df(const Eigen::VectorXd& z, Eigen::MatrixXd& jac) {
    if (runs_left < inputs() + 1) return -1;
    const Eigen::VectorXd f0 = Run(z);
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      Eigen::VectorXd zi = z;
      zi(i) += kStep;
      jac.col(i) = (Run(zi) - f0) / kStep;
    }
    return 0;
  }

  const ConfigVariants& declared;
  const RecordCost& cost;
  const std::vector<const Effect*>& effects;
  const std::vector<Flat>& flat;
  int runs_left;
  RunMemo* memo;
  int runs = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_z;
};

// A size from zero and its phase (an unbalance, a runout harmonic): what the rotor does is
// nearly linear in the size's two components, so Gauss-Newton steps in them (a trial size at
// phase 0 and a quarter turn: the influence coefficients a balancing engineer measures with
// trial weights) lead to the best size and phase in a few runs. The bounded search's grid of
// sizes decades apart left a couple unbalance five times smaller than its smallest start on
// the magnet-biased flexible rig at nothing (its drop's start at 0.072); from this start, 0.038.
bool IsSizeAndPhase(const Effect& e) {
  return e.parameters.size() == 2 && !e.parameters[0].periodic && e.parameters[0].lower == 0.0 &&
         e.parameters[1].periodic;
}

std::vector<double> InfluenceStart(const ConfigVariants& declared, const RecordCost& cost,
                                   const Effect& e, int* runs) {
  constexpr int kSteps = 4;
  const EffectParameter& size = e.parameters[0];
  double smallest = size.upper;
  for (const double v : size.starts) {
    if (v > 0.0) smallest = std::min(smallest, v);
  }
  // A tenth of the smallest start: small enough for the response to be linear in it.
  const double trial = 0.1 * smallest;
  if (!(trial > 0.0)) return {};
  const auto residual = [&](const Eigen::Vector2d& c) {
    ++*runs;
    return ResidualWithEffects(declared, cost, {&e},
                               {{std::min(std::hypot(c(0), c(1)), size.upper),
                                 c.squaredNorm() > 0.0 ? std::atan2(c(1), c(0)) : 0.0}});
  };
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  Eigen::VectorXd r = residual(c);
  double best_sse = r.squaredNorm();
  Eigen::Vector2d best = c;
  for (int k = 0; k < kSteps && r.allFinite(); ++k) {
    const double h = std::max(trial, 0.05 * c.norm());
    Eigen::MatrixXd influence(r.size(), 2);
    for (int axis = 0; axis < 2; ++axis) {
      Eigen::Vector2d moved = c;
      moved(axis) += h;
      influence.col(axis) = (residual(moved) - r) / h;
    }
    if (!influence.allFinite() || influence.norm() == 0.0) break;
    const Eigen::Vector2d next = c + influence.colPivHouseholderQr().solve(-r);
    if (!next.allFinite()) break;
    const Eigen::VectorXd r_next = residual(next);
    if (!(r_next.squaredNorm() < best_sse)) break;
    best_sse = r_next.squaredNorm();
    best = c = next;
    r = r_next;
  }
  if (best.squaredNorm() == 0.0) return {};
  return {std::min(best.norm(), size.upper), std::atan2(best(1), best(0))};
}

}  // namespace

double DecidedHalfWidth(const EffectParameter& p, double value) {
  if (p.log_scale || p.magnitude) return 0.5 * std::abs(value);
  const double range = p.periodic ? 2.0 * std::numbers::pi : p.upper - p.lower;
  return 0.25 * range;
}

bool ParameterDecided(const EffectParameter& p, double value, double sigma, bool at_bound) {
  if (at_bound) return true;
  if (!std::isfinite(sigma)) return p.quantum > 0.0;
  const double width = DecidedHalfWidth(p, value);
  if (p.log_scale || p.magnitude) return sigma < width;
  return !(width > 0.0) || sigma < width;
}

std::vector<std::string> EffectOverrides(const std::vector<const Effect*>& effects,
                                         const std::vector<std::vector<double>>& values) {
  std::vector<std::string> out;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    const std::vector<std::string> o = effects[e]->overrides(values[e]);
    out.insert(out.end(), o.begin(), o.end());
  }
  return out;
}

ModelParams WithEffects(const ConfigVariants& declared, const std::vector<const Effect*>& effects,
                        const std::vector<std::vector<double>>& values) {
  return declared.With(EffectOverrides(effects, values)).params;
}

Eigen::VectorXd ResidualWithEffects(const ConfigVariants& declared, const RecordCost& cost,
                                    const std::vector<const Effect*>& effects,
                                    const std::vector<std::vector<double>>& values, bool* refused) {
  ModelParams params;
  try {
    params = WithEffects(declared, effects, values);
  } catch (const ConfigError&) {
    if (refused != nullptr) *refused = true;
    return cost.Unreached();
  }
  if (refused != nullptr) *refused = false;
  return cost.Residual(params);
}

EffectFit FitEffects(const ConfigVariants& declared, const RecordCost& cost,
                     const std::vector<const Effect*>& effects, int max_runs_per_start,
                     const RecordCost* screen, const std::vector<KnownStart>& known) {
  std::vector<Flat> flat;
  EffectFit fit;
  RunMemo memo;
  const RecordCost& search_cost = screen != nullptr ? *screen : cost;
  // Each parameter's starts: what is known of it first, then its own.
  std::vector<std::vector<double>> start_lists;
  std::size_t starts = 1;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    const KnownStart* k = e < known.size() && !known[e].values.empty() ? &known[e] : nullptr;
    KnownStart influence;
    if (k == nullptr && IsSizeAndPhase(*effects[e])) {
      influence.values = InfluenceStart(declared, search_cost, *effects[e], &fit.evaluations);
      if (!influence.values.empty()) k = &influence;
    }
    for (std::size_t i = 0; i < effects[e]->parameters.size(); ++i) {
      const EffectParameter& p = effects[e]->parameters[i];
      flat.push_back({effects[e], e, &p});
      std::vector<double> list;
      if (k != nullptr) list.push_back(k->values[i]);
      if (k == nullptr || !k->only) list.insert(list.end(), p.starts.begin(), p.starts.end());
      start_lists.push_back(std::move(list));
      starts = std::max(starts, start_lists.back().size());
    }
  }
  for (const Effect* e : effects) fit.effects.push_back(e->name);
  fit.sse = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_z;
  // One Levenberg-Marquardt search from z; keeps its best point if it beats the best so far.
  const auto search_from = [&](Eigen::VectorXd z) {
    Problem problem(declared, search_cost, effects, flat, max_runs_per_start, &memo);
    Eigen::LevenbergMarquardt<Problem> lm(problem);
    lm.setXtol(1e-4);
    lm.setFtol(1e-4);
    lm.minimize(z);
    fit.evaluations += problem.runs;
    if (!(problem.best_sse < fit.sse)) return false;
    fit.sse = problem.best_sse;
    best_z = problem.best_z;
    return true;
  };
  // Every combination of the parameters' starts while there are few (a TDB offset's x and y
  // take opposite signs as often as equal ones, and a diagonal of starts misses that quadrant);
  // otherwise start s takes each parameter's start s, cycling through shorter lists.
  std::size_t combinations = 1;
  for (const std::vector<double>& list : start_lists) {
    combinations *= std::max<std::size_t>(1, list.size());
    if (combinations > kMaxStartCombinations) break;
  }
  const bool all = combinations <= kMaxStartCombinations;
  const std::size_t count = all ? combinations : starts;
  std::vector<Eigen::VectorXd> points;
  for (std::size_t s = 0; s < count; ++s) {
    Eigen::VectorXd z(static_cast<Eigen::Index>(flat.size()));
    std::size_t rest = s;
    for (std::size_t i = 0; i < flat.size(); ++i) {
      const EffectParameter& p = *flat[i].parameter;
      const std::vector<double>& list = start_lists[i];
      double v = p.log_scale ? std::sqrt(p.lower * p.upper) : 0.5 * (p.lower + p.upper);
      if (!list.empty()) {
        v = all ? list[rest % list.size()] : list[s % list.size()];
        rest /= list.size();
      }
      z(static_cast<Eigen::Index>(i)) = ToSearch(p, v);
    }
    points.push_back(z);
  }
  // Of many starts, the search runs from the few where the cost is least: one run each to
  // rank them costs far less than a search from each (some 25 runs), and a start in the right
  // quadrant of a TDB offset is already the closest.
  if (points.size() > kSearchedStarts) {
    std::vector<std::pair<double, std::size_t>> ranked;
    for (std::size_t s = 0; s < points.size(); ++s) {
      Problem probe(declared, search_cost, effects, flat, 1, &memo);
      Eigen::VectorXd f;
      probe(points[s], f);
      fit.evaluations += probe.runs;
      ranked.emplace_back(probe.best_sse, s);
      if (probe.best_sse < fit.sse) {
        fit.sse = probe.best_sse;
        best_z = points[s];
      }
    }
    std::stable_sort(ranked.begin(), ranked.end());
    std::vector<Eigen::VectorXd> kept;
    for (std::size_t k = 0; k < kSearchedStarts; ++k) kept.push_back(points[ranked[k].second]);
    points = std::move(kept);
  }
  for (const Eigen::VectorXd& z : points) search_from(z);
  if (best_z.size() == 0) return fit;

  // Quantised parameters: step to the neighbouring multiples while the cost falls, fitting
  // the others afresh at each.
  for (std::size_t i = 0; i < flat.size(); ++i) {
    const EffectParameter& p = *flat[i].parameter;
    if (p.quantum <= 0.0) continue;
    for (const double direction : {1.0, -1.0}) {
      for (int step = 0; step < 20; ++step) {
        const double value =
            ToValue(p, best_z(static_cast<Eigen::Index>(i))) + direction * p.quantum;
        if (value < p.lower || value > p.upper) break;
        Eigen::VectorXd z = best_z;
        z(static_cast<Eigen::Index>(i)) = ToSearch(p, value);
        if (!search_from(z)) break;
      }
    }
  }

  if (screen != nullptr) {
    // The screen's optimum refined on the whole cost, which is what the candidates are judged
    // by; the start point itself is the first run, so the refinement never ends worse.
    Problem problem(declared, cost, effects, flat, max_runs_per_start, &memo);
    Eigen::LevenbergMarquardt<Problem> lm(problem);
    lm.setXtol(1e-4);
    lm.setFtol(1e-4);
    Eigen::VectorXd z = best_z;
    lm.minimize(z);
    fit.evaluations += problem.runs;
    if (problem.best_z.size() == 0) {
      fit.sse = std::numeric_limits<double>::infinity();
      return fit;
    }
    fit.sse = problem.best_sse;
    best_z = problem.best_z;
  }

  // The Jacobian at the optimum, in the parameters' own units, for their uncertainty.
  Problem at(declared, cost, effects, flat, static_cast<int>(flat.size()) + 1, &memo);
  Eigen::MatrixXd jz(static_cast<Eigen::Index>(cost.size()),
                     static_cast<Eigen::Index>(flat.size()));
  at.df(best_z, jz);
  fit.evaluations += at.runs;
  const Eigen::Index n = static_cast<Eigen::Index>(flat.size());
  Eigen::VectorXd slopes(n);
  std::vector<bool> at_bound(flat.size(), false);
  for (Eigen::Index i = 0; i < n; ++i) {
    slopes(i) = Slope(*flat[static_cast<std::size_t>(i)].parameter, best_z(i));
    at_bound[static_cast<std::size_t>(i)] = std::abs(slopes(i)) < 1e-9;
  }
  // Parameters the record does not move (a bound, a delay between samples) are left out of
  // the covariance rather than making it singular. It is inverted in the search variables,
  // where every column is of the same order (a stiffness in N/m beside a travel in m would
  // leave the normal matrix unconditioned to the LU's rank test), and carried to the
  // parameters' units by their slopes.
  std::vector<Eigen::Index> live;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!at_bound[static_cast<std::size_t>(i)] && jz.col(i).norm() > 0.0) live.push_back(i);
  }
  const double dof =
      std::max<double>(1.0, static_cast<double>(cost.size()) - static_cast<double>(n));
  Eigen::MatrixXd cov = Eigen::MatrixXd::Constant(n, n, kNaN);
  if (!live.empty()) {
    const Eigen::Index m = static_cast<Eigen::Index>(live.size());
    Eigen::MatrixXd jl(jz.rows(), m);
    Eigen::VectorXd slope(m);
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index i = live[static_cast<std::size_t>(k)];
      jl.col(k) = jz.col(i);
      slope(k) = slopes(i);
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(jl.transpose() * jl);
    if (lu.isInvertible()) {
      const Eigen::MatrixXd c = lu.inverse() * (fit.sse / dof);
      for (Eigen::Index a = 0; a < m; ++a) {
        for (Eigen::Index b = 0; b < m; ++b) {
          cov(live[static_cast<std::size_t>(a)], live[static_cast<std::size_t>(b)]) =
              c(a, b) * slope(a) * slope(b);
        }
      }
    }
  }

  fit.values = at.Values(best_z);
  fit.covariance.assign(cov.data(), cov.data() + cov.size());  // symmetric: row-major as stored
  for (std::size_t i = 0; i < flat.size(); ++i) {
    ParameterEstimate est;
    est.effect = flat[i].effect->name;
    est.name = flat[i].parameter->name;
    est.value = ToValue(*flat[i].parameter, best_z(static_cast<Eigen::Index>(i)));
    const double var = cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i));
    est.sigma = at_bound[i] || !(var >= 0.0) ? kNaN : std::sqrt(var);
    est.at_bound = at_bound[i];
    est.decided = ParameterDecided(*flat[i].parameter, est.value, est.sigma, est.at_bound);
    fit.parameters.push_back(est);
  }
  return fit;
}

}  // namespace ambdrop
