#include "tools/fit/declared_value_check.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

#include "tools/fit/effect_selection_internal.hpp"
#include "tools/fit/parallel_for.hpp"

namespace ambdrop {

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
  ParallelFor(items.size(), threads, [&](std::size_t k) {
    const Item& item = items[k];
    std::vector<std::vector<double>> values = fit->values;
    values[item.effect][item.index] = effects[item.effect]->parameters[item.index].declared;
    ModelParams params;
    try {
      params = WithEffects(declared, effects, values);
    } catch (const ConfigError&) {
      return;  // the config refuses the declared value in this company: it is needed
    }
    open[k] = explains(params, &rms[k]);
  });
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!open[k]) continue;
    ParameterEstimate& est = fit->parameters[items[k].estimate];
    est.decided = false;
    est.declared_rms = rms[k];
  }
}

}  // namespace ambdrop
