// The largest single allocation a piece of code asks for, measured by replacing the global
// operator new of the test binary (OpenEXR's allocations go through it too). Include in exactly
// one .cpp of a test binary.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace ganzfeld::testing_support {

inline std::atomic<std::size_t> largest_allocation{0};

/// Largest single operator new request while `run` runs.
template <class F>
std::size_t largest_allocation_during(F&& run) {
  largest_allocation = 0;
  run();
  return largest_allocation.load();
}

}  // namespace ganzfeld::testing_support

void* operator new(std::size_t size) {
  std::size_t seen = ganzfeld::testing_support::largest_allocation.load(std::memory_order_relaxed);
  while (size > seen && !ganzfeld::testing_support::largest_allocation.compare_exchange_weak(seen, size)) {
  }
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
