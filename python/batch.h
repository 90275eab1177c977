// Many values of one law in one call (the Python module's model.f/g/h/a), in parallel across
// cores with oneTBB. Every entry is the independent integral evaluate_law computes
// (integrate/laws.h), so its bits do not depend on the thread count, the order of work or the
// batch: entry m equals `ganzfeld eval` at (i[m], j[m]).
#pragma once

#include <atomic>
#include <cstdint>
#include <span>

#include "integrate/laws.h"

namespace ganzfeld::python {

/// Shared between the workers and the thread that waits for them: the waiting thread reads
/// `done` for progress and sets `cancel` (Ctrl-C, a progress callback that raised); workers then
/// skip the entries they have not started, and the batch's results are to be discarded.
struct BatchControl {
  std::atomic<bool> cancel{false};
  std::atomic<std::uint64_t> done{0};
};

/// out[m] = evaluate_law(model, law, i[m], j[m], options) for every m (i, j and out of one
/// length), unless control.cancel is set first.
void evaluate_batch(const Model& model, Law law, std::span<const Vec3> i, std::span<const Vec3> j,
                    const CubatureOptions& options, std::span<Estimate> out, BatchControl& control);

}  // namespace ganzfeld::python
