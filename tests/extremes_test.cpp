// The extremes grid (reports/extremes.h, issue #20): a slice that ctest can afford — the grid's
// corners for the models whose reference is quick — must be finite and honest against the
// independent reference (reference/). The whole grid is docs/reliability.md (scripts/docs
// --reliability, tens of minutes).
#include <string>

#include <gtest/gtest.h>

#include "laws/spec.h"
#include "reports/extremes.h"

namespace ganzfeld {
namespace {

/// The engine's tolerance in the grid (docs/reliability.md).
constexpr double kEngineTol = 1e-8;

/// Every flagged case, one per line, for the failure message.
std::string describe(const ExtremesRow& row) {
  std::string out;
  for (const ExtremesCase& c : row.flagged)
    out += c.spec + " " + to_string(c.law) + " " + c.where + ": engine " + std::to_string(c.engine.value) + " ± " +
           std::to_string(c.engine.error) + ", reference " + std::to_string(c.reference) + " ± " +
           std::to_string(c.reference_error) + "\n";
  return out;
}

TEST(Extremes, CornersOfTheGridAreFiniteAndHonest) {
  ExtremesOptions options;
  options.engine_tolerance = kEngineTol;
  options.quick = true;
  options.models = {"lambert", "minnaert", "asperity", "hvd-fit", "phong-lewis", "blinn-phong", "lafortune",
                    "lafortune-paint"};
  const auto rows = extremes_report(options);
  ASSERT_EQ(rows.size(), options.models.size());
  for (const ExtremesRow& row : rows) {
    EXPECT_GT(row.cases, 0) << row.model;
    EXPECT_EQ(row.non_finite, 0) << describe(row);
    EXPECT_EQ(row.not_converged, 0) << describe(row);
    EXPECT_EQ(row.dishonest, 0) << describe(row);
    EXPECT_EQ(row.unresolved, 0) << describe(row);
  }
}

}  // namespace
}  // namespace ganzfeld
