// Uses the installed library the way a C++ user would: a model from its spec, a law by cubature,
// a small table baked and looked up. Prints "ok" when both agree with Lambert's closed forms.
#include <cmath>
#include <cstdio>

#include "integrate/laws.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "tables/sample.h"

int main() {
  using namespace ganzfeld;
  const ModelPtr lambert = parse_model("lambert");
  const Vec3 j{0.6, 0.0, 0.8};
  CubatureOptions cubature;
  cubature.abs_tol = 1e-10;
  const Estimate h = darkening(*lambert, j, cubature);
  tables::BakeOptions options;
  options.resolution = {8};
  const tables::Table table = tables::bake(*lambert, Law::h, options);
  const double looked_up = tables::sample(table, Vec3{0, 0, 1}, j).value;
  const bool ok = std::abs(h.value - 1.0) < 1e-9 && std::abs(looked_up - 1.0) < 1e-6;
  std::printf("%s: h = %.12f (cubature), %.9f (table)\n", ok ? "ok" : "FAILED", h.value, looked_up);
  return ok ? 0 : 1;
}
