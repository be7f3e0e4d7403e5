#pragma once
// What the files of the effect selection share (it was one file); not for other callers.
#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/jitter_draws.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

// A part of the record not judged: its name, how a reason says where, its cost and the
// declared model's numbers there.
struct PartView {
  std::string name;
  const char* phrase;
  const RecordCost* cost;
  const Selection::Part* part;
};

// effect_selection.cpp
std::vector<const Effect*> EffectsOf(const EffectFit& f, const std::vector<Effect>& library);
/// The declared model with the effects `f` names at its values.
ModelParams FittedParams(const ConfigVariants& declared, const std::vector<Effect>& library,
                         const EffectFit& f);
/// The part of `s` named "whole", "early", "speeds" or "levitated" (Selection::judged_on), and
/// how a reason says where it is.
Selection::Part& PartNamed(Selection& s, const std::string& name);
const Selection::Part& PartNamed(const Selection& s, const std::string& name);
const char* PartPhrase(const std::string& name);

// agreement_limit.cpp
double ModelFloorAfter(const ConfigVariants& declared, const RecordCost& cost,
                       const std::vector<Effect>& library, const EffectFit& f);
Selection::Part JudgePart(const ConfigVariants& declared, const RecordCost& cost,
                          const Eigen::VectorXd& residual_before, double noise_floor,
                          const SelectionRules& rules, const ModelFloors::Part& known);
double ChaosAllowance(const RecordCost& part_cost, const Selection::Part& part);
/// How far a part not judged may go under a change of the model: `level` (its limit, or what
/// something else leaves there if larger) widened in quadrature by twice its chaos allowance
/// (SelectionRules::model_floor_factor).
double PartAllowance(const RecordCost& part_cost, const Selection::Part& part, double level,
                     const SelectionRules& rules);

// judged_part_selection.cpp
/// `e` as a candidate not yet screened or fitted: its names, and whether these channels could
/// reveal it (Decidable).
CandidateScore ListedCandidate(const Effect& e, const MeasurementParams& measurement);
double Bic(double sse, std::size_t n, std::size_t k);
std::size_t Parameters(const EffectFit& f);
Selection SelectOn(const ConfigVariants& declared, const RecordCost& cost, const RecordCost* search,
                   const Eigen::VectorXd& residual_before, const std::vector<Effect>& library,
                   Selection s, bool at_floor, const SelectionRules& rules,
                   const std::function<std::string(const EffectFit&, const EffectFit&)>& harm,
                   const std::function<std::string(const EffectFit&)>& refuted,
                   const std::function<std::string(const EffectFit&)>& against_the_rest,
                   const std::function<std::string(const EffectFit&)>& breaks_start);

// verdict_revisions.cpp: each revises `s` after the choice; the caller checks where it applies.
void TakeNoEffect(Selection* s);
std::string NoDrawAgreed(const JitterDraws& j, const char* which, const char* where);
/// Where the declared model agrees with the drop's start and a later part is judged.
/// `drawn`, if given: the draws already made on `judged` at s->limit.
void TakeJitterDraws(const RecordCost& cost, const RecordCost& judged, const std::string& on,
                     const Selection::Part& early, const SelectionRules& rules, Selection* s,
                     const JitterDraws* drawn = nullptr);
/// Where the drop's start itself departs and `drawn` (runs of the declared model with the
/// rotor's jitter drawn, judged on the start) has one that agrees there: no effect is needed.
void TakeStartJitterDraw(const JitterDraws& drawn, Selection* s);
/// Where the declared model's draws (s->jitter) never reached the record's drop mode: an effect
/// chosen after the start whose model does not reach it either is set aside (`unexplained`).
void SetAsideEffectOutsideTheRecordsMode(const ConfigVariants& declared, const RecordCost& cost,
                                         const RecordCost& judged,
                                         const std::vector<Effect>& library,
                                         const SelectionRules& rules, const std::string& on,
                                         Selection* s);
/// Where that start agrees and the partial explanation's model is chaotic.
void SetAsideChaoticExplanation(const Selection::Part& early, Selection* s);
/// Where the start judges and the state at the trigger is an estimate.
void TakeStartStateShift(const RecordCost& early_cost, const Eigen::VectorXd& early_before,
                         const Selection::Part& early, const SelectionRules& rules, Selection* s);
/// Where effects were chosen beside look-alikes.
void SayWhatTellsLookAlikesApart(const ConfigVariants& declared, const RecordCost& cost,
                                 const std::vector<Effect>& library, Selection* s);

// speeds_partner.cpp
void AddSpeedsPartner(const ConfigVariants& declared, const RecordCost& whole,
                      const RecordCost& judged, const RecordCost& speeds,
                      const std::vector<Effect>& library, const SelectionRules& rules,
                      const std::vector<PartView>& others, const std::string& judged_name,
                      Selection* s);

// look_alike_partners.cpp: AddSpeedsPartner for the chosen effect and for its closest
// look-alikes on the judged part, keeping the pair that agrees better with the record.
void AddSpeedsPartnerWithLookAlikes(const ConfigVariants& declared, const RecordCost& whole,
                                    const RecordCost& judged, const RecordCost& speeds,
                                    const std::vector<Effect>& library, const SelectionRules& rules,
                                    const std::vector<PartView>& others,
                                    const std::string& judged_name, Selection* s);

}  // namespace ambdrop
