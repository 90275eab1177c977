// The largest single allocation a piece of code asks for, measured by replacing the global
// operator new of the test binary (tests/largest_allocation.cpp; OpenEXR's allocations go through
// it too). Link that file into exactly the test binaries that use this.
#pragma once

#include <atomic>
#include <cstddef>

namespace ganzfeld::testing_support {

extern std::atomic<std::size_t> largest_allocation;

/// Largest single operator new request while `run` runs.
template <class F>
std::size_t largest_allocation_during(F&& run) {
  largest_allocation = 0;
  run();
  return largest_allocation.load();
}

}  // namespace ganzfeld::testing_support
