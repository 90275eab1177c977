// Beard–Maxwell first-surface tables (models/beard_maxwell.h); a table that parses is interpolated
// across [0, 90] degrees and past its ends.
#include <cmath>
#include <numbers>

#include "fuzz/fuzz_support.h"
#include "models/beard_maxwell.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ganzfeld;
  fuzz::expect_clean([&] {
    FirstSurfaceTable table = parse_first_surface_table(fuzz::text(data, size), "fuzz.txt");
    const FirstSurface surface = FirstSurface::table("fuzz.txt", std::move(table), "");
    for (double degrees = -1.0; degrees <= 91.0; degrees += 0.5) {
      const double theta_N = degrees * std::numbers::pi / 180.0;
      (void)surface.rho_fs_cos2(theta_N, std::cos(theta_N));
    }
  });
  return 0;
}
