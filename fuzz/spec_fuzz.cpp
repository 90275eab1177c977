// Model spec strings, mixtures included (models/spec.h). A spec that parses must be canonical in a
// round trip (the canonical spec is a material's identity: parse(spec()).spec() == spec()); its f
// is evaluated at a few directions, grazing ones included, for the sanitizers.
#include <cstdlib>

#include "fuzz/fuzz_support.h"
#include "models/spec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ganzfeld;
  const std::string spec = fuzz::text(data, size);
  fuzz::expect_clean([&] { spec_without_paths(spec); });
  fuzz::expect_clean([&] {
    const ModelPtr model = parse_model(spec);
    const std::string canonical = model->spec();
    if (parse_model(canonical)->spec() != canonical) {
      std::fprintf(stderr, "canonical spec does not round-trip: %s\n", canonical.c_str());
      std::abort();
    }
    const Vec3 n{0, 0, 1}, oblique{0.6, 0, 0.8}, grazing{1, 0, 0}, other{-0.28, 0.48, 0.83};
    for (const Vec3& i : {n, oblique, grazing})
      for (const Vec3& j : {n, other, grazing}) (void)model->f(i, j);
    parse_lobes(spec);
  });
  return 0;
}
