#pragma once
// The fit's one form of parallelism: independent model runs (candidates, pairs, perturbations)
// spread over the machine's cores.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace ambdrop {

// Runs job(i) for i in [0, count) on `threads` threads; results land by index, so the outcome
// does not depend on which thread ran what. A job that throws stops the rest from starting, and
// the first exception (by index) is rethrown here once every thread has joined: an exception
// leaving a std::thread would end the process without a message.
template <typename Job>
void ParallelFor(std::size_t count, int threads, const Job& job) {
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> failed(count);
  std::atomic<bool> stop{false};
  const auto worker = [&] {
    for (std::size_t i = next++; i < count && !stop; i = next++) {
      try {
        job(i);
      } catch (...) {
        failed[i] = std::current_exception();
        stop = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(threads, 1); ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace ambdrop
