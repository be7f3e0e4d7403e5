#include "tools/fit/reduced_rotor_cache.hpp"

#include <algorithm>

namespace ambdrop {

std::shared_ptr<const ReducedRotor> ReducedRotorCache::Get(const ModelParams& params) {
  ReductionInputs key = ReductionInputsOf(params);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto hit = std::find_if(entries_.begin(), entries_.end(),
                                  [&](const auto& e) { return e.first == key; });
    if (hit != entries_.end()) return hit->second;
  }
  // Built outside the lock: two threads may both build a new rotor, and the later one's copy
  // is simply not kept.
  auto rotor = std::make_shared<const ReducedRotor>(BuildReducedRotor(params));
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto hit =
      std::find_if(entries_.begin(), entries_.end(), [&](const auto& e) { return e.first == key; });
  if (hit != entries_.end()) return hit->second;
  if (entries_.size() == kCapacity) entries_.erase(entries_.begin());
  entries_.emplace_back(std::move(key), rotor);
  return rotor;
}

Model ReducedRotorCache::BuildModel(const ModelParams& params) {
  return ambdrop::BuildModel(params, *Get(params));
}

}  // namespace ambdrop
