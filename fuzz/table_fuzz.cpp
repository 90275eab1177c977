// Table files (tables/exr_io.h: OpenEXR through read_table, and the size guard before it; and
// format version 3 through read_param_table, tables/param_table.h); a table that reads is
// sampled at its corners and centre.
#include "fuzz/fuzz_support.h"
#include "tables/exr_io.h"
#include "tables/param_table.h"
#include "tables/sample.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ganzfeld;
  const std::string path = fuzz::scratch_file(data, size, ".exr");
  fuzz::expect_clean([&] {
    const tables::Table table = tables::read_table(path);
    for (const Vec3& i : {Vec3{0, 0, 1}, Vec3{0.6, 0, 0.8}, Vec3{1, 0, 0}})
      for (const Vec3& j : {Vec3{0, 0, 1}, Vec3{-0.28, 0.48, 0.83}, Vec3{0, 1, 0}}) (void)tables::sample(table, i, j);
  });
  fuzz::expect_clean([&] {
    const tables::ParamTable table = tables::read_param_table(path);
    for (std::size_t c = 0; c < table.channels.size(); ++c)
      for (double x : {0.0, 0.37, 1.0})
        for (double mu : {0.0, 0.5, 1.0}) (void)tables::sample_param(table, c, x, mu);
  });
  return 0;
}
