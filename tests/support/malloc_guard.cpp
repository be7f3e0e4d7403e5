#include "malloc_guard.hpp"

#include <cstddef>

// glibc's own entry points, to which the interposed functions forward.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
}

namespace {
thread_local int armed = 0;
thread_local std::int64_t count = 0;
[[maybe_unused]] void Note() {
  if (armed > 0) ++count;
}
}  // namespace

#ifndef AMBDROP_NO_MALLOC_HOOKS
extern "C" {
void* malloc(std::size_t size) {
  Note();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  Note();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  Note();
  return __libc_realloc(p, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  Note();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  Note();
  *out = __libc_memalign(alignment, size);
  return *out ? 0 : 12;  // ENOMEM
}
}
#endif

namespace ambdrop::testing {

bool MallocGuard::Available() {
#ifdef AMBDROP_NO_MALLOC_HOOKS
  return false;
#else
  return true;
#endif
}

MallocGuard::MallocGuard() : start_(count) {
  ++armed;
}
MallocGuard::~MallocGuard() {
  --armed;
}
std::int64_t MallocGuard::allocations() const {
  return count - start_;
}

}  // namespace ambdrop::testing
