#pragma once
// A fit builds thousands of models of one rig that differ only in an effect's parameters; the
// pseudo-modal reduction of a flexible rotor (FE assembly and eigensolution, ~17 ms for the
// 72-element rotor of configs/chen_itri_flexible.toml) is the same for all of them, and cost
// more than a short run's simulation. This cache reduces each distinct rotor once.
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "rt_core/modal_reduction.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

class ReducedRotorCache {
 public:
  /// BuildReducedRotor(params), built on the first request with its ReductionInputs and shared
  /// after that. Safe to call from several threads.
  std::shared_ptr<const ReducedRotor> Get(const ModelParams& params);

  /// BuildModel(params) with the reduced rotor from the cache.
  Model BuildModel(const ModelParams& params);

 private:
  /// The entry for `key`, or null; the caller holds the mutex.
  std::shared_ptr<const ReducedRotor> Find(const ReductionInputs& key) const;

  // Few distinct rotors occur in one fit (the declared one; with an unbalance plane, one
  // more): a short list, searched linearly, the most recent last.
  static constexpr std::size_t kCapacity = 8;
  std::mutex mutex_;
  std::vector<std::pair<ReductionInputs, std::shared_ptr<const ReducedRotor>>> entries_;
};

}  // namespace ambdrop
