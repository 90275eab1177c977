// The replaced global operator new/delete of tests/largest_allocation.h (in a file of their own:
// g++ warns of mismatched new/free where it sees both inlined).
#include "tests/largest_allocation.h"

#include <cstdlib>
#include <new>

std::atomic<std::size_t> ganzfeld::testing_support::largest_allocation{0};

void* operator new(std::size_t size) {
  auto& largest = ganzfeld::testing_support::largest_allocation;
  std::size_t seen = largest.load(std::memory_order_relaxed);
  while (size > seen && !largest.compare_exchange_weak(seen, size)) {}
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
