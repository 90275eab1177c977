// Wavefront OBJ meshes (rasterizer/mesh.h: load_obj).
#include "fuzz/fuzz_support.h"
#include "rasterizer/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ganzfeld::fuzz::scratch_file(data, size, ".obj");
  ganzfeld::fuzz::expect_clean([&] { ganzfeld::raster::load_obj(path); });
  return 0;
}
