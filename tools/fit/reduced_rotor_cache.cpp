#include "tools/fit/reduced_rotor_cache.hpp"

#include <algorithm>

namespace ambdrop {

std::shared_ptr<const ReducedRotor> ReducedRotorCache::Find(const ReductionInputs& key) const {
  const auto hit =
      std::find_if(entries_.begin(), entries_.end(), [&](const auto& e) { return e.first == key; });
  return hit == entries_.end() ? nullptr : hit->second;
}

std::shared_ptr<const ReducedRotor> ReducedRotorCache::Get(const ModelParams& params) {
  ReductionInputs key = ReductionInputsOf(params);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (auto hit = Find(key)) return hit;
  }
  // Built outside the lock: two threads may both build a new rotor, and the later one's copy
  // is simply not kept.
  auto rotor = std::make_shared<const ReducedRotor>(BuildReducedRotor(params));
  const std::lock_guard<std::mutex> lock(mutex_);
  if (auto hit = Find(key)) return hit;
  if (entries_.size() == kCapacity) entries_.erase(entries_.begin());
  entries_.emplace_back(std::move(key), rotor);
  return rotor;
}

Model ReducedRotorCache::BuildModel(const ModelParams& params) {
  return ambdrop::BuildModel(params, *Get(params));
}

}  // namespace ambdrop
