#pragma once
#include <cstdint>

namespace ambdrop::testing {

/// Counts heap allocations (malloc, calloc, realloc, aligned_alloc, posix_memalign; operator new
/// goes through malloc) made by this thread while alive. Eigen allocates with std::malloc, so
/// hooking malloc catches it too.
class MallocGuard {
 public:
  MallocGuard();
  ~MallocGuard();
  MallocGuard(const MallocGuard&) = delete;
  MallocGuard& operator=(const MallocGuard&) = delete;
  std::int64_t allocations() const;
  /// False in sanitizer builds, whose runtimes own malloc: the guard then counts nothing.
  static bool Available();

 private:
  std::int64_t start_;
};

}  // namespace ambdrop::testing
