#include "batch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace ganzfeld::python {

void evaluate_batch(const Model& model, Law law, std::span<const Vec3> i, std::span<const Vec3> j,
                    const CubatureOptions& options, std::span<Estimate> out, BatchControl& control) {
  // Grain 1: integrals differ in cost by orders of magnitude (a lobe near the sky's edge), so
  // the scheduler balances entry by entry; an entry costs far more than the task around it.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t m = r.begin(); m != r.end(); ++m) {
      if (control.cancel.load(std::memory_order_relaxed)) return;
      out[m] = evaluate_law(model, law, i[m], j[m], options);
      control.done.fetch_add(1, std::memory_order_relaxed);
    }
  });
}

}  // namespace ganzfeld::python
