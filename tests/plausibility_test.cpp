// The plausibility report (reports/plausibility.h): every model's declared traits agree with
// what is measured, and the report finds what it must find — the known plausible models pass,
// the known violations show, and K&P's claim about Phong and Blinn-Phong comes out in the form
// the report states (intensity forms non-reciprocal, BRDF forms reciprocal).
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "models/spec.h"
#include "reports/plausibility.h"

namespace ganzfeld {
namespace {

const PlausibilityRow& row(const std::vector<PlausibilityRow>& rows, const std::string& prefix) {
  for (const auto& r : rows)
    if (r.spec.rfind(prefix, 0) == 0) return r;
  throw std::runtime_error("no row " + prefix);
}

TEST(Plausibility, DeclaredTraitsAgreeWithMeasurements) {
  const auto rows = plausibility_report(1e-6);
  ASSERT_GE(rows.size(), 30u);
  for (const auto& r : rows) {
    EXPECT_TRUE(r.traits_consistent()) << r.spec << ": declared "
                                       << (r.declared.reciprocal ? "reciprocal" : "not reciprocal") << "/"
                                       << to_string(r.declared.energy) << ", measured violation "
                                       << r.reciprocity_violation << ", max albedo " << r.max_albedo;
    EXPECT_TRUE(r.non_negative()) << r.spec << " min f " << r.min_f << " at " << r.min_f_at;
    EXPECT_TRUE(r.converged) << r.spec;
  }
  // The white reference surfaces vanish in a Ganzfeld; coloured ones do not.
  EXPECT_TRUE(row(rows, "lambert").ganzfeld_invisible());
  EXPECT_TRUE(row(rows, "oren-nayar:sigma=0,rho=1").ganzfeld_invisible());
  EXPECT_TRUE(row(rows, "hvd-empirical:cd=1,f0=0.04").ganzfeld_invisible());
  EXPECT_FALSE(row(rows, "oren-nayar:sigma=0.6,rho=1").ganzfeld_invisible());
  // Non-reciprocal HVD: energy conserved over incidence (h = 1) but its albedo exceeds 1.
  EXPECT_GT(row(rows, "hvd-empirical:cd=1,f0=0.04").max_albedo, 1.1);
}

TEST(Plausibility, PhongAndBlinnPhongViolateReciprocityOnlyInTheirIntensityForms) {
  const auto rows = plausibility_report(1e-6);
  EXPECT_GT(row(rows, "phong:kd=0.2").reciprocity_violation, 0.5);
  EXPECT_GT(row(rows, "blinn-phong, intensity form").reciprocity_violation, 0.5);
  EXPECT_LT(row(rows, "phong-lewis:kd=0,").reciprocity_violation, 1e-12);
  EXPECT_LT(row(rows, "blinn-phong:kd=0,").reciprocity_violation, 1e-12);
  EXPECT_GT(row(rows, "phong:kd=0.2").max_albedo, 1.0);  // and the 1/(i.n) breaks energy at grazing
}

TEST(Plausibility, ANonReciprocalModelIsDetected) {
  // A model that declares itself reciprocal but is not must be reported as inconsistent.
  class Liar final : public Model {
   public:
    std::string spec() const override { return "liar"; }
    Traits traits() const override { return {true, true, EnergyClass::plausible}; }
    double f(const Vec3& i, const Vec3& j) const noexcept override { return (i.z >= 0 && j.z >= 0) ? 0.3 * i.z : 0.0; }
  } liar;
  const PlausibilityRow r = measure_plausibility(liar, "test", 1e-6);
  EXPECT_FALSE(r.reciprocal());
  EXPECT_FALSE(r.traits_consistent());
}

}  // namespace
}  // namespace ganzfeld

namespace ganzfeld {
namespace {

TEST(Plausibility, CommittedReportIsUpToDate) {
  // docs/plausibility.md is generated; a model or formula change must regenerate it
  // (`ganzfeld plausibility --markdown docs/plausibility.md`).
  std::ifstream in(std::string(GANZFELD_SOURCE_DIR) + "/docs/plausibility.md");
  ASSERT_TRUE(in) << "docs/plausibility.md is missing";
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_EQ(committed.str(), plausibility_markdown(plausibility_report(1e-6), 1e-6,
                                                   "ganzfeld plausibility --markdown docs/plausibility.md"))
      << "regenerate with: build/ganzfeld plausibility --markdown docs/plausibility.md";
}

}  // namespace
}  // namespace ganzfeld
