// Tabulated BRDF text (models/measured.h: parse_tabulated); a table that parses becomes a model
// whose f is evaluated with both lookups at a few directions, grazing ones included.
#include "fuzz/fuzz_support.h"
#include "models/measured.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ganzfeld;
  fuzz::expect_clean([&] {
    TabulatedBrdf table = parse_tabulated(fuzz::text(data, size), "fuzz.tab");
    for (int lookup : {0, 1}) {
      const TabulatedModel model("fuzz.tab", table, lookup, "");
      for (const Vec3& i : {Vec3{0, 0, 1}, Vec3{0.6, 0, 0.8}, Vec3{1, 0, 0}})
        for (const Vec3& j : {Vec3{0, 0, 1}, Vec3{-0.28, 0.48, 0.83}, Vec3{0, 1, 0}}) (void)model.f(i, j);
    }
  });
  return 0;
}
