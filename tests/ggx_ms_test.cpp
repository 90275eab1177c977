// ggx-ms (models/ggx_ms.h): the white furnace, E_avg and reciprocity. The compensation's E comes
// from models/ggx_energy's Gauss–Legendre rule; the albedos here are integrated by the cubature
// (integrate/), an independent integrator, so a white furnace that holds is two methods agreeing.
#include <cmath>

#include <gtest/gtest.h>

#include "integrate/laws.h"
#include "models/ggx_ms.h"
#include "models/spec.h"

namespace ganzfeld {
namespace {

// The cubature's tolerance for the albedos below; its error estimate is added to every bound.
constexpr double kTol = 1e-9;

TEST(GgxMs, WhiteFurnace) {
  for (const char* spec : {"ggx-ms:alpha=1", "ggx-ms:roughness=0.5,g2=separable"}) {
    const ModelPtr model = parse_model(spec);
    const auto& ms = dynamic_cast<const GgxMs&>(*model);
    // With f0 = 1 the albedo is E(mu) + (1 − E_table(mu)): 1 within the table's error.
    EXPECT_LE(ms.energy().error, 1e-5) << spec;  // the white-furnace target of docs/models.md
    for (double mu : {0.01, 0.2, 0.5, 0.8, 1.0}) {
      const Estimate a = albedo(*model, direction_from_cos(mu), {kTol});
      EXPECT_NEAR(a.value, 1.0, ms.energy().error + a.error) << spec << " mu " << mu;
    }
  }
}

TEST(GgxMs, PlainGgxLosesWhatTheCompensationAdds) {
  const ModelPtr plain = parse_model("ggx:alpha=1"), ms = parse_model("ggx-ms:alpha=1");
  // E(mu = 1, alpha = 1) = 1 − ln 2: plain GGX loses ln 2 at normal incidence.
  EXPECT_NEAR(albedo(*plain, direction_from_cos(1.0), {kTol}).value, 1.0 - std::log(2.0), 1e-8);
  const auto& table = dynamic_cast<const GgxMs&>(*ms).energy();
  EXPECT_NEAR(table.at(1.0), 1.0 - std::log(2.0), table.error);
}

TEST(GgxMs, EAvgAgreesWithTheCubaturesDoubleDiffuse) {
  const auto& table = dynamic_cast<const GgxMs&>(*parse_model("ggx-ms:alpha=1")).energy();
  // E_avg = 2 ∫ E mu dmu is the law r of ggx:f0=1 (integrate/laws.h), a different integrator.
  const Estimate r = double_diffuse(*parse_model("ggx:alpha=1,f0=1"), {1e-8});
  EXPECT_NEAR(table.E_avg, r.value, table.error + r.error);
}

TEST(GgxMs, ReciprocalAndAboveGgx) {
  const ModelPtr model = parse_model("ggx-ms:alpha=1,f0=0.04"), plain = parse_model("ggx:alpha=1,f0=0.04");
  const Vec3 i = direction_from_cos(0.3, 0.2), j = direction_from_cos(0.8, 2.0);
  EXPECT_DOUBLE_EQ(model->f(i, j), model->f(j, i));
  EXPECT_GT(model->f(i, j), plain->f(i, j));
  EXPECT_EQ(model->spec(), "ggx-ms:alpha=1,f0=0.04,g2=height-correlated");
  EXPECT_THROW(parse_model("ggx-ms:alpha_x=0.1,alpha_y=0.2"), std::exception);
  // Plausible with f0 < 1: the compensation never pushes the albedo above 1.
  EXPECT_LE(albedo(*model, direction_from_cos(0.5), {kTol}).value, 1.0);
}

}  // namespace
}  // namespace ganzfeld
