#include "tools/fit/effect_selection_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "tools/fit/candidate_screen.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/parallel_for.hpp"

namespace ambdrop {
namespace {

// The config's message when it refuses the effect at its first start values, else "".
std::string RefusedAtStart(const ConfigVariants& declared, const Effect& e) {
  std::vector<double> start;
  for (const EffectParameter& p : e.parameters) {
    start.push_back(p.starts.empty() ? p.lower : p.starts.front());
  }
  try {
    declared.With(e.overrides(start));
  } catch (const ConfigError& error) {
    return error.what();
  }
  return {};
}

}  // namespace

double Bic(double sse, std::size_t n, std::size_t k) {
  const double N = static_cast<double>(std::max<std::size_t>(n, 1));
  return N * std::log(std::max(sse, 1e-300) / N) + static_cast<double>(k) * std::log(N);
}

std::size_t Parameters(const EffectFit& f) {
  return f.parameters.size();
}

namespace {

// A chosen pair whose second effect has one parameter, searched along it: two effects that
// trade along a shallow valley (a TDB's vertical offset and a friction coefficient: a lower
// TDB and more friction end the drop alike) with a floor that contact makes rough stop the
// pair's search in its first dip. The first effect is refitted with the second held at a few
// values around its pair optimum; from the lowest, if lower, both are fitted again. On the
// rigid rig's offset-and-friction record the pair had stopped at y -46.7 um and mu 0.3255
// (0.00504); held at the true mu 0.3198, the offset alone fitted -37.7 um (truth -37.6) at
// 0.00452.
template <typename Harmless>
void ProfilePair(const ConfigVariants& declared, const RecordCost& cost, const RecordCost* search,
                 const Effect& first, const Effect& second, const SelectionRules& rules,
                 const Harmless& harmless, CandidateScore* pair) {
  if (second.parameters.size() != 1 || pair->fit.values.size() != 2) return;
  const EffectParameter& q = second.parameters.front();
  if (q.periodic || q.quantum > 0.0) return;
  const double at = pair->fit.values[1][0];
  // A few hundredths of the value (of the range for one at 0): the valley's dips are that apart.
  const double step = at != 0.0 ? 0.03 * std::abs(at) : 0.03 * (q.upper - q.lower);
  if (!(step > 0.0)) return;
  const std::vector<double> first_values = pair->fit.values[0];
  std::vector<double> held_values(4);
  const std::array<double, 4> offsets = {-2.0, -1.0, 1.0, 2.0};
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    held_values[i] = std::clamp(at + offsets[i] * step, q.lower, q.upper);
  }
  std::vector<EffectFit> held(held_values.size());
  ParallelFor(held_values.size(), rules.threads, [&](std::size_t i) {
    Effect e = first;
    const double v = held_values[i];
    e.overrides = [&first, &second, v](const std::vector<double>& x) {
      std::vector<std::string> lines = first.overrides(x);
      const std::vector<std::string> more = second.overrides({v});
      lines.insert(lines.end(), more.begin(), more.end());
      return lines;
    };
    held[i] =
        FitEffects(declared, cost, {&e}, rules.max_runs_per_start, search, {{first_values, true}});
  });
  std::size_t lowest = held.size();
  for (std::size_t i = 0; i < held.size(); ++i) {
    if (held[i].values.empty() || !(held[i].sse < pair->fit.sse)) continue;
    if (lowest == held.size() || held[i].sse < held[lowest].sse) lowest = i;
  }
  if (lowest == held.size()) return;
  EffectFit again = FitEffects(declared, cost, {&first, &second}, rules.max_runs_per_start, search,
                               {{held[lowest].values[0], true}, {{held_values[lowest]}, true}});
  if (again.values.empty() || !(again.sse < pair->fit.sse)) return;
  CandidateScore trial = *pair;
  trial.fit = std::move(again);
  trial.rms_after = OverallRms(cost, trial.fit.sse);
  trial.bic = Bic(trial.fit.sse, cost.size(), Parameters(trial.fit));
  trial.delta_bic = pair->delta_bic - (pair->bic - trial.bic);
  if (!harmless(trial)) return;
  *pair = std::move(trial);
}

}  // namespace

CandidateScore ListedCandidate(const Effect& e, const MeasurementParams& measurement) {
  CandidateScore c;
  c.name = e.name;
  c.family = e.family;
  c.description = e.description;
  c.decidable = Decidable(e, measurement);
  return c;
}

// The selection on one cost (the part the verdict judges): `s` comes with that part's numbers
// (rms_before, noise and model floors, limit); `search` is where starts are searched first.
// `harm`, if given, says why a fitted pair makes a part of the record not judged here depart
// further than the best single effect alone does ("" if it does not); `refuted`, why a single
// effect makes such a part depart further than the declared model does; `against_the_rest`, why
// the rest of the record says the chosen effects are no partial explanation ("" if it does not).
Selection SelectOn(const ConfigVariants& declared, const RecordCost& cost, const RecordCost* search,
                   const Eigen::VectorXd& residual_before, const std::vector<Effect>& library,
                   Selection s, bool at_floor, const SelectionRules& rules,
                   const std::function<std::string(const EffectFit&, const EffectFit&)>& harm,
                   const std::function<std::string(const EffectFit&)>& refuted,
                   const std::function<std::string(const EffectFit&)>& against_the_rest,
                   const std::function<std::string(const EffectFit&)>& breaks_start) {
  const double sse_before = residual_before.squaredNorm();
  s.bic_before = Bic(sse_before, cost.size(), 0);
  s.rms_after = s.rms_before;
  s.limit_after = s.limit;

  // How far a candidate must move the prediction for the record to tell it from its absence:
  // beyond the model's own sensitivity (twice the model floor, as in the limit) and beyond half
  // the noise floor. Not the whole limit: the noise is in the record and in neither prediction,
  // and a move of half its RMS, over thousands of samples, is plain (a sensor's x gain 40 % low
  // moved the start by 0.0055 against its noise floor of 0.0045 and explained the record as well
  // as the TDB offset chosen; judged against the whole limit, 0.0066, it was never fitted).
  const double resolvable =
      std::max(std::sqrt(std::pow(rules.model_floor_factor * s.model_floor, 2) +
                         rules.tolerance * rules.tolerance),
               0.5 * s.noise_floor);
  // Singles: the hand-made families each fitted; the registry's many candidates screened
  // first (three runs each) and only the most promising fitted.
  std::vector<CandidateScore> singles(library.size());
  std::vector<Screening> screenings(library.size());
  const auto fit_single = [&](std::size_t i, const std::vector<KnownStart>& known) {
    CandidateScore& c = singles[i];
    c.tried = true;
    c.fit = FitEffects(declared, cost, {&library[i]}, rules.max_runs_per_start, search, known);
    c.rms_after = OverallRms(cost, c.fit.sse);
    c.bic = Bic(c.fit.sse, cost.size(), Parameters(c.fit));
    c.delta_bic = c.bic - s.bic_before;
  };
  ParallelFor(library.size(), rules.threads, [&](std::size_t i) {
    const Effect& e = library[i];
    CandidateScore& c = singles[i];
    c = ListedCandidate(e, cost.measurement());
    if (!c.decidable) return;
    c.refused = RefusedAtStart(declared, e);
    if (!c.refused.empty()) {
      c.decidable = false;
      return;
    }
    if (e.screened && e.parameters.size() == 1) {
      c.screened = true;
      // At the floor nothing could be chosen: the screening's runs would be wasted.
      if (at_floor) return;
      screenings[i] = ScreenCandidate(declared, cost, e, residual_before);
      c.reach = screenings[i].reach;
      c.decidable = c.reach > resolvable;
      c.screened_rms = OverallRms(cost, screenings[i].predicted_sse);
      return;
    }
    if (!e.probe.empty()) {
      const Eigen::VectorXd probed = ResidualWithEffects(declared, cost, {&e}, {e.probe});
      c.reach = OverallRms(cost, (probed - residual_before).squaredNorm());
      // Even strong, it would stay within the limit: no fit could tell it from its absence.
      c.decidable = c.reach > resolvable;
      if (!c.decidable) return;
    }
    // At the floor no candidate could be chosen: its fit would only cost runs (minutes for
    // the full library on a flexible rotor).
    if (at_floor) return;
    fit_single(i, {});
  });
  // Fits the screened candidates that pass `wanted`, best predicted first, at most
  // SelectionRules::screened_fits of them, each searched from its screened best value too.
  // Returns their indices.
  const auto fit_best_screened = [&](const auto& wanted) {
    std::vector<std::size_t> picked;
    for (std::size_t i = 0; i < singles.size(); ++i) {
      if (singles[i].screened && singles[i].decidable && !singles[i].tried && wanted(i)) {
        picked.push_back(i);
      }
    }
    std::stable_sort(picked.begin(), picked.end(), [&](std::size_t a, std::size_t b) {
      return screenings[a].predicted_sse < screenings[b].predicted_sse;
    });
    const std::size_t most = static_cast<std::size_t>(std::max(rules.screened_fits, 0));
    if (picked.size() > most) picked.resize(most);
    ParallelFor(picked.size(), rules.threads, [&](std::size_t k) {
      const std::size_t i = picked[k];
      fit_single(i, {{{screenings[i].best_value}, false}});
    });
    return picked;
  };
  // Those whose predicted cut could be accepted at all.
  if (!at_floor) {
    fit_best_screened([&](std::size_t i) {
      return screenings[i].predicted_sse * rules.min_cut * rules.min_cut <= sse_before;
    });
  }
  s.decidable_candidates = static_cast<int>(std::count_if(
      singles.begin(), singles.end(), [](const CandidateScore& c) { return c.decidable; }));
  // The best of M tries beats noise by about 2 ln M per parameter (SelectionRules).
  const double per_parameter = 2.0 * std::log(std::max(s.decidable_candidates, 1));
  const auto material = [&](double before, double after, double delta_bic, std::size_t parameters) {
    return after * rules.min_cut <= before &&
           delta_bic <= -(rules.min_delta_bic + per_parameter * static_cast<double>(parameters));
  };
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < singles.size(); ++i) {
    if (singles[i].tried && std::isfinite(singles[i].fit.sse)) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return singles[a].bic < singles[b].bic; });
  // An explanation of the drop after its start must leave the start as the declared model had
  // it (and the levitated time before the trigger, where the declared model agrees there):
  // there the drop is deterministic, after the first impacts it may not be. On clean
  // records of the independent rigid rig the drop went into backward whirl after a start the
  // declared model matched, where the model's own drop rocked; a centre of mass 4 % off, a
  // sensor's offset or one TDB's friction flipped the model into whirl too and cut the speeds
  // 3-11x, taking the start from 0.0046 to 0.0095-0.056 against limits of 0.0065. A best
  // candidate that does that is set aside, and the next one considered.
  std::string broke;
  std::vector<std::string> breaking;
  if (breaks_start && !at_floor) {
    while (!order.empty()) {
      const CandidateScore& c = singles[order.front()];
      if (!material(s.rms_before, c.rms_after, c.delta_bic, Parameters(c.fit))) break;
      const std::string why = breaks_start(c.fit);
      if (why.empty()) break;
      broke += fmt::format("; {} was set aside: {}", c.name, why);
      breaking.push_back(c.name);
      order.erase(order.begin());
    }
  }
  // Look-alikes on the judged part (another family within the equivalence margin of the best)
  // are told apart by the rest of the record where one of them sends it far beyond what the
  // declared model leaves there and another does not: the record refutes the first. On the
  // flexible rig a race's Palmgren load torque and its inertia fitted a drop's start alike
  // (0.00378 each), but the load torque took the speeds from 0.044 to 7.2 (limit 0.015). Only
  // between look-alikes: a single effect that fits the start best and has no look-alike is kept
  // whatever it does to a chaotic rest (the verdict's check of every part reports it).
  std::string refutations;
  std::string set_aside;  // the refuted look-alike: no longer one that fits "as well"
  if (refuted && order.size() > 1 && !at_floor) {
    const CandidateScore& top = singles[order.front()];
    const std::string why = refuted(top.fit);
    if (!why.empty()) {
      for (std::size_t k = 1; k < order.size(); ++k) {
        const CandidateScore& c = singles[order[k]];
        if (c.family == top.family || c.rms_after > top.rms_after * rules.equivalent_margin) {
          continue;
        }
        if (!material(s.rms_before, c.rms_after, c.delta_bic, Parameters(c.fit)) ||
            !refuted(c.fit).empty()) {
          continue;
        }
        refutations =
            fmt::format("; {} fitted the judged part as well ({:.3g}) but was set aside: {}",
                        top.name, top.rms_after, why);
        set_aside = top.name;
        std::rotate(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k),
                    order.begin() + static_cast<std::ptrdiff_t>(k) + 1);
        break;
      }
    }
  }
  // Among explanations the record cannot tell apart (within the equivalence margin of the best
  // on the judged part, and on no other part worse than the best beyond that part's limit and
  // floor: `harm`), the one with the fewest parameters is named first. The
  // BIC counts every sample as independent evidence, but a residual left by model-form error is
  // correlated over many samples, so a second parameter that only soaks up that error wins the
  // BIC by far: on the flexible rig one sensor's scale error and offset on both axes (offset
  // fitted at 9 nm, i.e. nothing) beat the y-axis gain alone that the record held by 0.00405
  // to 0.00424. A TDB's larger clearance fits an offset TDB's drop start as well (0.000353
  // against 0.000348) but not the rest (0.00413, limit 0.00194): the offset stays.
  std::string simpler;
  if (order.size() > 1 && !at_floor) {
    const CandidateScore& top = singles[order.front()];
    std::size_t pick = 0;
    for (std::size_t k = 1; k < order.size(); ++k) {
      const CandidateScore& c = singles[order[k]];
      const std::size_t fewest = Parameters(singles[order[pick]].fit);
      if (Parameters(c.fit) >= fewest || c.name == set_aside ||
          c.rms_after > top.rms_after * rules.equivalent_margin ||
          !material(s.rms_before, c.rms_after, c.delta_bic, Parameters(c.fit)) ||
          (harm && !harm(c.fit, top.fit).empty())) {
        continue;
      }
      pick = k;
    }
    if (pick != 0) {
      simpler =
          fmt::format("; the simpler of the look-alikes is named first ({} has {} parameters)",
                      top.name, Parameters(top.fit));
      std::rotate(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(pick),
                  order.begin() + static_cast<std::ptrdiff_t>(pick) + 1);
    }
  }
  s.candidates = singles;

  // The limit with a fitted model's own sensitivity (ModelFloorAfter).
  const auto floor_limit = [&](const EffectFit& f) {
    s.model_floor_after = ModelFloorAfter(declared, cost, library, f);
    s.limit_after = AgreementLimitAfter(s, rules, &s.limit_after_capped);
    return s.limit_after;
  };
  double limit_after = s.limit;
  // Pairs set aside because their second effect makes another part of the record depart
  // (`harm`).
  std::string harmed;
  if (!order.empty() && !at_floor) {
    CandidateScore& best = s.candidates[order.front()];
    const auto harmless = [&](const CandidateScore& c) {
      const std::string why = harm ? harm(c.fit, best.fit) : std::string();
      if (!why.empty()) harmed += fmt::format("; {} was set aside: {}", c.name, why);
      return why.empty();
    };
    if (material(s.rms_before, best.rms_after, best.delta_bic, Parameters(best.fit))) {
      best.accepted = true;
      s.chosen = {best.name};
      s.chosen_fit = best.fit;
      s.rms_after = best.rms_after;
      limit_after = floor_limit(best.fit);
      // A structured residual left: the best with a partner. Also within the limit where the
      // best leaves more than the noise: the limit lets the drop's sensitivity to its start
      // excuse that rest, but a partner that takes it down to the noise, removing more than
      // that sensitivity could (twice the model floor, as in the limit), shows the record held
      // it. On the rigid truth rig one TDB's friction (truth 0.293, declared 0.2), fitted at
      // 0.306, left the start at 0.00795 against a limit of 0.0082 (noise 0.0044, start
      // sensitivity 0.0031), and the other TDB's offset of 48 um went unnamed; fitted beside
      // it, it takes the start to 0.0044 (0.0066 removed). A couple unbalance fitted at its
      // truth left 0.0063 there, its rotor's jitter at the trigger (the start taken from the
      // record agrees); a DE hold-then-fade law took it to 0.0043, removing 0.0046 against the
      // 0.0055 the start's sensitivity moves: not named.
      Selection quiet = s;
      quiet.model_floor = 0.0;
      const double at_noise = AgreementLimit(quiet, rules);
      if (best.rms_after > limit_after || best.rms_after > at_noise) {
        // Every other fitted effect is a partner: one that does little alone may be what the
        // best leaves (two offset TDBs: the second offset alone fits the first one's drop
        // badly). The best few alone are searched widely, the rest from where each fitted
        // alone only.
        const std::size_t partners = order.size() - 1;
        std::vector<CandidateScore> pairs(partners);
        const Effect& first = library[order.front()];
        ParallelFor(partners, rules.threads, [&](std::size_t p) {
          const Effect& second = library[order[p + 1]];
          CandidateScore& c = pairs[p];
          c.name = first.name + " + " + second.name;
          c.family = first.family + " + " + second.family;
          c.description = first.description + "; " + second.description;
          c.tried = true;
          // From where each fitted best alone: the first there only, the second (if among the
          // best few) also from its own starts: alone it may have settled for what the first
          // explains better.
          const CandidateScore& alone = singles[order[p + 1]];
          const bool wide = p < static_cast<std::size_t>(rules.pair_partners);
          c.fit = FitEffects(declared, cost, {&first, &second}, rules.max_runs_per_start, search,
                             {{best.fit.values.front(), true}, {alone.fit.values.front(), !wide}});
          c.rms_after = OverallRms(cost, c.fit.sse);
          c.bic = Bic(c.fit.sse, cost.size(), Parameters(c.fit));
          c.delta_bic = c.bic - best.bic;
        });
        // The first effect alone again, from where the pair that fits best put it: a pair may
        // only move it out of a dip its own search stopped in, and a second effect must explain
        // what the first cannot wherever the first sits. On the rigid truth rig a DE TDB offset
        // fitted alone at (-72.8, -28.3) um (truth (-76.2, -45.5)), the start's cost rough along
        // y; beside the NDE TDB's clearance it went to (-75.7, -45.2) and the start to its
        // noise, the clearance 250.3 um against 250 declared: no effect.
        const auto closest = std::min_element(
            pairs.begin(), pairs.end(),
            [](const CandidateScore& a, const CandidateScore& b) { return a.fit.sse < b.fit.sse; });
        if (closest != pairs.end() && std::isfinite(closest->fit.sse)) {
          CandidateScore again = best;
          again.fit = FitEffects(declared, cost, {&first}, rules.max_runs_per_start, search,
                                 {{closest->fit.values.front(), true}});
          if (again.fit.sse < best.fit.sse) {
            again.rms_after = OverallRms(cost, again.fit.sse);
            again.bic = Bic(again.fit.sse, cost.size(), Parameters(again.fit));
            again.delta_bic = again.bic - s.bic_before;
            best = again;
            s.chosen_fit = best.fit;
            s.rms_after = best.rms_after;
            limit_after = floor_limit(best.fit);
            for (CandidateScore& c : pairs) c.delta_bic = c.bic - best.bic;
          }
        }
        // Whether a pair's second effect is held by the record beside the best as it now
        // stands (s.model_floor_after and limit_after are the best's). It must explain more than
        // the best's own sensitivity moves: where the best makes the drop chaotic, any added
        // parameter nudges the bouncing, and some nudge lands closer to the record by chance.
        const auto holds = [&](const CandidateScore& pair) {
          const double removed = std::sqrt(
              std::max(0.0, best.rms_after * best.rms_after - pair.rms_after * pair.rms_after));
          const double start_allowance =
              rules.model_floor_factor * std::max(s.model_floor, s.model_floor_after);
          return material(best.rms_after, pair.rms_after, pair.bic - best.bic,
                          Parameters(pair.fit) - Parameters(best.fit)) &&
                 removed > s.model_floor_after &&
                 (best.rms_after > limit_after ||
                  (pair.rms_after <= at_noise && removed > start_allowance));
        };
        std::vector<std::size_t> eligible;
        for (std::size_t p = 0; p < pairs.size(); ++p) {
          if (holds(pairs[p])) eligible.push_back(p);
        }
        std::stable_sort(eligible.begin(), eligible.end(),
                         [&](std::size_t a, std::size_t b) { return pairs[a].bic < pairs[b].bic; });
        std::size_t pick = pairs.size();
        for (const std::size_t p : eligible) {
          if (harmless(pairs[p])) {
            pick = p;
            break;
          }
        }
        if (pick < pairs.size()) {
          ProfilePair(declared, cost, search, first, library[order[pick + 1]], rules, harmless,
                      &pairs[pick]);
          pairs[pick].accepted = true;
          best.accepted = false;
          s.chosen = pairs[pick].fit.effects;
          s.chosen_fit = pairs[pick].fit;
          s.rms_after = pairs[pick].rms_after;
          limit_after = floor_limit(s.chosen_fit);
        }
        for (CandidateScore& p : pairs) s.candidates.push_back(std::move(p));
      }
    }
  }

  // Look-alikes among the screened keys: where a chosen effect leaves about what a key's
  // screening predicts, the key is fitted too, so that the record's inability to tell them apart
  // is found and said (a sensor's x gain or a TDB's station that a TDB offset mimics). The
  // screening's quadratic is rough: within twice the equivalence margin. The other numbers of
  // a chosen key's own table (one part's law) are fitted whatever their screening said: it is
  // roughest where that law is steep. On the 4-DOF truth rig an AMB's air gap 23.5 % wide
  // (force as 1/g^2) screened at 0.054 where its fit leaves 0.0123, as its bias current did
  // (0.0119, the one named), and the truth went unlisted.
  if (!s.chosen.empty()) {
    const auto table = [](const std::string& key) {
      const std::size_t dot = key.rfind('.');
      return dot == std::string::npos ? std::string() : key.substr(0, dot);
    };
    const std::string chosen_table = table(s.chosen.front());
    const std::vector<std::size_t> alike_keys = fit_best_screened([&](std::size_t i) {
      return singles[i].screened_rms <= s.rms_after * 2.0 * rules.equivalent_margin ||
             (!chosen_table.empty() && table(singles[i].name) == chosen_table);
    });
    for (const std::size_t i : alike_keys) s.candidates[i] = singles[i];
  }

  // What the record could not have shown: a verdict of agreement says nothing about these.
  std::string unseen, refused;
  for (const CandidateScore& c : singles) {
    if (!c.refused.empty()) {
      refused += (refused.empty() ? "" : ", ") + c.name;
    } else if (!c.decidable) {
      unseen += (unseen.empty() ? "" : ", ") + c.name;
    }
  }
  if (!unseen.empty()) unseen = "; the record cannot reveal " + unseen;
  if (!refused.empty()) unseen += "; the config refuses " + refused + " (report.md says why)";

  // Other explanations as good as the chosen one: named, so no one takes the choice as proof.
  // As good: within the equivalence margin of the chosen effects' residual, or, where those
  // agree with the record (within the agreement limit), agreeing too. The limit is what the
  // record can resolve; the margin alone let a model-form difference between two simulators
  // decide: on the rigid truth rig's heavier race (seed 215) a Palmgren load torque left the
  // speeds at 0.0142, a drag torque at 0.0150, and the race's inertia, the truth, at 0.0195,
  // all three within the limit of 0.022 (the truth's own value leaves 0.0224: the generator's
  // spin law is not ambdrop's to the last digit), and only the first two were named.
  const bool chosen_agree = !s.chosen.empty() && s.rms_after <= limit_after;
  std::string alike;
  if (!s.chosen.empty()) {
    for (const CandidateScore& c : singles) {
      // Of any family, the chosen effect's own included: another item of it is an alternative
      // where the record cannot tell them apart. On the rigid truth rig (its centre of mass
      // midway between its AMBs) the DE AMB's station 14 mm off was named as the NDE AMB's, the
      // two fitting every part of the record alike to five digits, and the truth went unlisted.
      const bool chosen = std::find(s.chosen.begin(), s.chosen.end(), c.name) != s.chosen.end();
      if (!c.tried || !std::isfinite(c.fit.sse) || chosen || c.name == set_aside ||
          std::find(breaking.begin(), breaking.end(), c.name) != breaking.end()) {
        continue;
      }
      const bool agrees_too = chosen_agree && c.rms_after <= limit_after &&
                              material(s.rms_before, c.rms_after, c.delta_bic, Parameters(c.fit));
      if (c.rms_after <= s.rms_after * rules.equivalent_margin || agrees_too) {
        s.equivalent.push_back({c.name, c.family, c.fit, c.rms_after, "", 0.0});
        alike += fmt::format("{}{} ({:.3g})", alike.empty() ? "" : ", ", c.name, c.rms_after);
      }
    }
    if (!alike.empty()) {
      alike = "; " + alike + " fit" + (s.equivalent.size() == 1 ? "s" : "") +
              " the record as well: it cannot tell them apart";
    }
  }
  // The closest candidate is named (fit.json `closest`) and not applied: it does not describe
  // the error. `why` ends the reason's sentence.
  const auto not_described = [&](const std::string& why) {
    std::string best;
    for (const std::string& name : s.chosen) best += (best.empty() ? "" : " + ") + name;
    s.verdict = "unexplained";
    s.reason = fmt::format(
        "the residual ({:.3g}, agreement limit {:.3g}) is not described by any effect of the "
        "library: the closest, {}, takes it only to {:.3g}, {}{}",
        s.rms_before, limit_after, best, s.rms_after, why, unseen);
    s.closest = s.chosen;
    s.closest_rms = s.rms_after;
    s.chosen.clear();
    s.chosen_fit = EffectFit{};
    s.equivalent.clear();
    s.rms_after = s.rms_before;
    s.limit_after = s.limit;
    s.model_floor_after = 0.0;
    for (CandidateScore& c : s.candidates) c.accepted = false;
  };
  if (at_floor) {
    s.verdict = "no_effect_needed";
    s.reason = fmt::format(
        "the declared model is already within {:.3g} of the record (relative RMS), inside the "
        "agreement limit {:.3g}{}",
        s.rms_before, s.limit, unseen);
  } else if (s.chosen.empty()) {
    s.verdict = "unexplained";
    s.reason = fmt::format(
        "the residual ({:.3g}, agreement limit {:.3g}) is not cut by {:.0f} % or more by any "
        "effect of the library{}",
        s.rms_before, s.limit, 100.0 * (1.0 - 1.0 / rules.min_cut), unseen);
  } else if (s.rms_after <= limit_after && s.limit_after_capped &&
             s.model_floor_after > rules.confirmable_chaos * s.limit) {
    // The chosen model's own chaos is several agreement limits, and more than the cap lets it
    // widen the limit by: whether what is left falls inside the cap is then a matter of chance (a
    // wider TDB, outside the library, came out at 0.0151 or 0.0192 against a cap of 0.0175 as the
    // search's path changed). The record cannot confirm the model, only that the effect cuts.
    // Inside the declared limit too: on the flexible rotor a 2 um offset of one TDB took the
    // record of an AMB gain error (outside the library) from 0.0212 to 0.0064 against 0.0087.
    s.verdict = "partly_explained";
    s.reason = fmt::format(
        "the chosen effects cut the residual from {:.3g} to {:.3g}, but the model they make is "
        "chaotic: its own prediction moves by {:.3g} (step halved, parameters nudged), "
        "several times the agreement limit {:.3g}, so the record cannot confirm it{}",
        s.rms_before, s.rms_after, s.model_floor_after, s.limit, alike);
  } else if (s.rms_after <= limit_after) {
    s.verdict = "explained";
    s.reason = fmt::format(
        "with the chosen effects the residual falls from {:.3g} to {:.3g}, within the agreement "
        "limit {:.3g}{}",
        s.rms_before, s.rms_after, s.rms_after <= s.limit ? s.limit : limit_after, alike);
  } else if ((s.rms_after - limit_after) * rules.explained_cut > s.rms_before - limit_after) {
    // What an effect explains must be most of the error: it must close at least two thirds
    // (1 - 1/SelectionRules::explained_cut) of the way from the residual to the agreement
    // limit; a candidate that takes a little off an error it does not describe is no partial
    // explanation. A constant side pull on the rigid rig, outside every candidate, was taken
    // from 0.019 to 0.0114 by a y offset on both sensors against a limit of 0.006 (58 % of the
    // way), and `partly_explained` sent the user to the wrong table; the friction of one TDB,
    // in the candidates, closed 90 % of the way on the same rig (0.0131 to 0.0071 against
    // 0.0064).
    not_described(
        fmt::format("less than two thirds of the way to the limit, so most of the "
                    "error is something else{}",
                    alike));
  } else if (const std::string why =
                 against_the_rest ? against_the_rest(s.chosen_fit) : std::string();
             !why.empty()) {
    // Nor is a partial explanation that the rest of the record contradicts: short of the limit
    // on the part it was fitted on, and either beyond both its limit and the declared model's
    // residual on another part, or less than two thirds of the way on another part that
    // departed too (most of the error is the error on every part). On the 4-DOF rig a constant
    // side pull (outside the library) was taken 82 % of the way on the drop's start by the
    // magnets' fading law (0.065 to 0.024, limit 0.015), which took the speeds from 0.061 to
    // 0.085 (allowed 0.061); on the flexible rig a lower magnet bias took it 96 % of the way
    // on the start (0.14 to 0.043, limit 0.039) and the speeds only from 0.048 to 0.037 against
    // 0.0085 (28 %). A right effect falls within its limit on the part it was fitted on, where
    // this rule does not look.
    not_described("short of the limit, and " + why);
  } else {
    s.verdict = "partly_explained";
    s.reason = fmt::format(
        "the chosen effects cut the residual from {:.3g} to {:.3g}, still above the agreement "
        "limit {:.3g}{}",
        s.rms_before, s.rms_after, limit_after, alike);
  }
  if (!at_floor) s.reason += broke + refutations + simpler + harmed;
  return s;
}

}  // namespace ambdrop
