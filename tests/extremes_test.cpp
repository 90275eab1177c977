// The extremes grid (reports/extremes.h, issue #20): a slice that ctest can afford — the grid's
// corners for the models whose reference is quick — must be finite and honest against the
// independent reference (reference/). The whole grid is docs/reliability.md (scripts/docs
// --reliability, tens of minutes).
#include <numbers>
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

/// A sharp lobe at the tip of a thin lune: the sky pole 8° below the horizon (the lune of g is a
/// sliver along the horizon) and the view on the horizon at 90° azimuth, so the mirror lobe sits
/// on the coordinates' pole t = -pi/2. The engine's initial grid had no line near it (the lobe is
/// wider than its centre-line-only threshold) and converged on 900 evaluations, 2.07e-6 off with
/// 1.9e-11 estimated (found by the extremes grid, via 0.5*lambert + 0.5*specular:alpha=1000).
TEST(Extremes, SharpLobeAtTheTipOfAThinLuneIsHonest) {
  const ModelPtr model = parse_model("specular:alpha=1000");
  for (const double cos_i : {-0.99, -0.999}) {
    const ExtremesCase c = judge_case(*model, Law::g, direction_from_cos(cos_i, 0.0),
                                      direction_from_cos(0.0, std::numbers::pi / 2), kEngineTol);
    EXPECT_TRUE(c.converged && c.finite);
    EXPECT_FALSE(c.reference_unresolved);
    EXPECT_FALSE(c.dishonest) << cos_i << ": engine " << c.engine.value << " ± " << c.engine.error << ", reference "
                              << c.reference << " ± " << c.reference_error;
  }
}

/// Poulin–Fournier's cylinder shadowing jumps across half great circles through its crease axis
/// (laws/model.h MassHints::crease_axis). On the hemisphere the reference's coordinates have that
/// axis as their edge axis, so the jumps are lines psi = longitude, cut exactly; without the cuts
/// Boost bisected towards them until the grid's budget ran out (h at j = n: "0 ± inf").
TEST(Extremes, PoulinFournierCreasesAreCutInTheReference) {
  const ModelPtr model = parse_model("poulin-fournier");
  const ExtremesCase c = judge_case(*model, Law::h, Vec3{0, 0, 1}, Vec3{0, 0, 1}, kEngineTol);
  EXPECT_TRUE(c.converged && c.finite);
  EXPECT_FALSE(c.reference_unresolved) << "reference " << c.reference << " ± " << c.reference_error;
  EXPECT_FALSE(c.dishonest) << "engine " << c.engine.value << " ± " << c.engine.error << ", reference " << c.reference
                            << " ± " << c.reference_error;
}

}  // namespace
}  // namespace ganzfeld
