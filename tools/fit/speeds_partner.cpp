#include "tools/fit/effect_selection_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/parallel_for.hpp"

namespace ambdrop {

// A second effect only the speeds show. The chosen effect explains the judged part (the drop's
// start), but the speeds still depart: what acts once the races spin (one TDB's friction, a
// race's drag or inertia) can leave the start as it is, so no pair fitted on the start finds it
// (an offset NDE TDB with the DE TDB's friction 60 % high: the offset alone explained the
// start, the friction was fitted at 0.190 against 0.192 but the speeds stayed at 0.055 against
// 0.044). Partners: the effects the speeds reveal. Each is tried beside the chosen one at its
// own starts on the speeds; the three best are fitted with it there. The best pair is taken if
// it cuts the speeds as a single effect must (SelectionRules::min_cut and the BIC margin for
// the partners tried) and leaves every other part within its limit, or within what the chosen
// effect alone leaves there, widened by the part's model floor.
void AddSpeedsPartner(const ConfigVariants& declared, const RecordCost& whole,
                      const RecordCost& judged, const RecordCost& speeds,
                      const std::vector<Effect>& library, const SelectionRules& rules,
                      const std::vector<PartView>& others, const std::string& judged_name,
                      Selection* s) {
  const std::vector<const Effect*> chosen = EffectsOf(s->chosen_fit, library);
  if (chosen.size() != 1) return;
  const Effect& first = *chosen.front();
  std::vector<const Effect*> partners;
  for (const Effect& e : library) {
    if (e.name == first.name) continue;
    const bool on_speeds =
        std::any_of(e.revealed_by.begin(), e.revealed_by.end(), [](MeasuredQuantity q) {
          return q == MeasuredQuantity::kTdbSpeed || q == MeasuredQuantity::kRotorSpeed;
        });
    if (on_speeds) partners.push_back(&e);
  }
  if (partners.empty()) return;
  const auto run = [&](const std::vector<const Effect*>& effects,
                       const std::vector<std::vector<double>>& values) {
    return whole.Simulate(WithEffects(declared, effects, values));
  };
  const SimulatedRecord alone = run(chosen, s->chosen_fit.values);
  const double sse_alone = speeds.Residual(alone).squaredNorm();
  // Stage 1: each partner at each of its starts (its first parameter's; the rest at theirs).
  std::vector<double> best_sse(partners.size(), std::numeric_limits<double>::infinity());
  std::vector<std::vector<double>> best_start(partners.size());
  ParallelFor(partners.size(), rules.threads, [&](std::size_t i) {
    const Effect& e = *partners[i];
    std::vector<double> start;
    for (const EffectParameter& p : e.parameters) start.push_back(p.starts.front());
    for (const double v : e.parameters.front().starts) {
      start.front() = v;
      try {
        const double sse =
            speeds.Residual(run({&first, &e}, {s->chosen_fit.values.front(), start})).squaredNorm();
        if (sse < best_sse[i]) {
          best_sse[i] = sse;
          best_start[i] = start;
        }
      } catch (const std::exception&) {
        // the config refuses this start: not a partner from here
      }
    }
  });
  std::vector<std::size_t> order(partners.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return best_sse[a] < best_sse[b]; });
  constexpr std::size_t kFitted = 3;
  order.resize(std::min(order.size(), kFitted));
  std::erase_if(order, [&](std::size_t i) { return !std::isfinite(best_sse[i]); });
  // Stage 2: the partner fitted on the speeds from its best start, the chosen effect held where
  // the judged part put it (fitted on the speeds too, it drifted and broke the start).
  std::vector<CandidateScore> pairs(order.size());
  const std::vector<double> held = s->chosen_fit.values.front();
  const Selection::Part& judged_part = PartNamed(*s, judged_name);
  const double judged_alone = OverallRms(judged, judged.Residual(alone).squaredNorm());
  const double judged_allowed =
      std::hypot(judged_alone, rules.model_floor_factor * judged_part.step_sensitivity);
  // An effect held at `at` beside another fitted on `values`.
  const auto held_beside = [](const Effect& fitted, const Effect& other, std::vector<double> at) {
    Effect beside = fitted;
    beside.overrides = [f = &fitted, o = &other, at](const std::vector<double>& v) {
      std::vector<std::string> lines = o->overrides(at);
      for (std::string& line : f->overrides(v)) lines.push_back(std::move(line));
      return lines;
    };
    return beside;
  };
  ParallelFor(order.size(), rules.threads, [&](std::size_t k) {
    const Effect& e = *partners[order[k]];
    CandidateScore& c = pairs[k];
    c.name = first.name + " + " + e.name + " (on the speeds)";
    c.family = first.family + " + " + e.family;
    c.description = first.description + "; " + e.description;
    c.tried = true;
    Effect beside = held_beside(e, first, held);
    EffectFit partner = FitEffects(declared, speeds, {&beside}, rules.max_runs_per_start, nullptr,
                                   {{best_start[order[k]], false}});
    c.fit = s->chosen_fit;
    int evaluations = partner.evaluations;
    // A partner that moves the judged part too (a TDB's friction turns the first bounce): the
    // chosen effect, fitted there without it, sat where the partner's absence put it (an offset
    // TDB fitted at (60.6, 15.3) um beside the declared friction, and the friction then 0.393 on
    // the speeds; truth (88.5, 12.2) um and 0.316). Fitting each on its own part in turn walks
    // down that valley the wrong way (to 104 um and 0.412). So with one parameter the partner is
    // profiled: held at values about its fit, the chosen effect fitted again on the judged part
    // beside each, the speeds then run; the lowest speeds whose judged part stays within what
    // the effect alone leaves there are kept, the partner refined there on the speeds.
    const auto judged_rms = [&](const std::vector<double>& f, const std::vector<double>& p) {
      try {
        return OverallRms(judged, judged.Residual(run({&first, &e}, {f, p})).squaredNorm());
      } catch (const std::exception&) {
        return std::numeric_limits<double>::infinity();
      }
    };
    const EffectParameter& q = e.parameters.front();
    const double p0 = partner.values.front().front();
    if (e.parameters.size() == 1 && !q.periodic && q.quantum == 0.0 && p0 != 0.0 &&
        !(judged_rms(held, partner.values.front()) <= judged_allowed)) {
      constexpr std::array<double, 5> kOffsets = {-0.35, -0.2, -0.1, 0.1, 0.2};
      std::vector<double> best_first;
      double best_p = 0.0;
      double best_speeds = std::numeric_limits<double>::infinity();
      for (const double o : kOffsets) {
        const double v = std::clamp(p0 * (1.0 + o), q.lower, q.upper);
        const Effect again = held_beside(first, e, {v});
        const EffectFit refit = FitEffects(declared, judged, {&again}, rules.max_runs_per_start,
                                           nullptr, {{held, true}});
        evaluations += refit.evaluations + 1;
        if (refit.values.empty() || !(judged_rms(refit.values.front(), {v}) <= judged_allowed)) {
          continue;
        }
        double sse = std::numeric_limits<double>::infinity();
        try {
          sse = speeds.Residual(run({&first, &e}, {refit.values.front(), {v}})).squaredNorm();
        } catch (const std::exception&) {
        }
        if (sse < best_speeds) {
          best_speeds = sse;
          best_first = refit.values.front();
          best_p = v;
          c.fit.parameters = refit.parameters;
        }
      }
      if (!best_first.empty()) {
        c.fit.values.front() = best_first;
        beside = held_beside(e, first, best_first);
        EffectFit refined = FitEffects(declared, speeds, {&beside}, rules.max_runs_per_start,
                                       nullptr, {{{best_p}, true}});
        evaluations += refined.evaluations;
        if (refined.values.empty() ||
            !(judged_rms(best_first, refined.values.front()) <= judged_allowed) ||
            !(refined.sse <= best_speeds)) {
          refined.values = {{best_p}};
          refined.sse = best_speeds;
          refined.parameters = partner.parameters;
          refined.parameters.front().value = best_p;
          refined.parameters.front().sigma = std::numeric_limits<double>::quiet_NaN();
        }
        partner = std::move(refined);
      }
    }
    c.fit.effects.push_back(e.name);
    c.fit.values.push_back(partner.values.front());
    c.fit.parameters.insert(c.fit.parameters.end(), partner.parameters.begin(),
                            partner.parameters.end());
    c.fit.sse = partner.sse;
    c.fit.evaluations = evaluations;
    c.rms_after = OverallRms(speeds, c.fit.sse);
    c.bic = Bic(c.fit.sse, speeds.size(), Parameters(c.fit));
    c.delta_bic = c.bic - Bic(sse_alone, speeds.size(), Parameters(s->chosen_fit));
  });
  const double rms_alone = OverallRms(speeds, sse_alone);
  const double margin =
      rules.min_delta_bic +
      2.0 * std::log(static_cast<double>(std::max<std::size_t>(partners.size(), 1)));
  std::size_t pick = pairs.size();
  std::string why_not;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    CandidateScore& c = pairs[k];
    const std::size_t added = Parameters(c.fit) - Parameters(s->chosen_fit);
    if (!(c.rms_after * rules.min_cut <= rms_alone) ||
        !(c.delta_bic <= -margin * static_cast<double>(std::max<std::size_t>(added, 1)))) {
      continue;
    }
    // Every other part stays within its limit, or within what the chosen effect leaves there.
    const SimulatedRecord with = run(EffectsOf(c.fit, library), c.fit.values);
    std::string harm;
    const auto check = [&](const RecordCost& part_cost, const Selection::Part& part,
                           const char* phrase) {
      if (!harm.empty()) return;
      const double after = OverallRms(part_cost, part_cost.Residual(with).squaredNorm());
      const double before = OverallRms(part_cost, part_cost.Residual(alone).squaredNorm());
      const double allowed = PartAllowance(
          part_cost, part, std::max(part.limit_after > 0.0 ? part.limit_after : part.limit, before),
          rules);
      if (after > allowed) {
        harm = fmt::format("{} takes the residual {} to {:.3g} (allowed {:.3g})", c.name, phrase,
                           after, allowed);
      }
    };
    // On the judged part, where the chosen effect was fitted, the partner (fitted on the speeds
    // with that effect held) must leave it as the effect alone does, within the part's step
    // sensitivity: an effect only the speeds show does not move it, and one that does was
    // not fitted there.
    {
      const double after = OverallRms(judged, judged.Residual(with).squaredNorm());
      if (after > judged_allowed) {
        harm = fmt::format(
            "{} takes the residual {} to {:.3g}, where the first effect alone "
            "leaves {:.3g} (allowed {:.3g})",
            c.name, PartPhrase(judged_name), after, judged_alone, judged_allowed);
      }
    }
    for (const PartView& o : others) {
      if (o.name != "speeds") check(*o.cost, *o.part, o.phrase);
    }
    if (!harm.empty()) {
      why_not += "; " + harm;
      continue;
    }
    if (pick == pairs.size() || c.bic < pairs[pick].bic) pick = k;
  }
  if (pick == pairs.size()) {
    s->reason += why_not;
    for (CandidateScore& c : pairs) s->candidates.push_back(std::move(c));
    return;
  }
  CandidateScore& c = pairs[pick];
  c.accepted = true;
  for (CandidateScore& other : s->candidates) other.accepted = false;
  s->chosen = c.fit.effects;
  s->chosen_fit = c.fit;
  const SimulatedRecord with = run(EffectsOf(c.fit, library), c.fit.values);
  // Every part again with the pair, against its limit (the judged part's as the fit set it).
  bool all_within = true;
  const auto again = [&](const RecordCost& part_cost, Selection::Part* part) {
    part->rms_after = OverallRms(part_cost, part_cost.Residual(with).squaredNorm());
    all_within &= part->rms_after <= std::max(part->limit, part->limit_after);
  };
  again(whole, &s->whole);
  if (judged_name != "whole") again(judged, &PartNamed(*s, judged_name));
  again(speeds, &s->speeds);
  s->rms_after = PartNamed(*s, judged_name).rms_after;
  const std::string pair_said =
      fmt::format("; {} then fitted on the speeds takes them from {:.3g} to {:.3g} (limit {:.3g})",
                  c.fit.effects.back(), rms_alone, s->speeds.rms_after, s->speeds.limit);
  if (all_within) {
    s->verdict = "explained";
    s->reason = fmt::format(
        "with the chosen effects the residual falls from {:.3g} to {:.3g}, within the "
        "agreement limit {:.3g}{}",
        s->rms_before, s->rms_after, s->limit_after, pair_said);
  } else {
    s->reason += pair_said;
  }
  for (CandidateScore& p : pairs) s->candidates.push_back(std::move(p));
}

}  // namespace ambdrop
