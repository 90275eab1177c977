// KTX2 textures (export/texture_file.h: read_ktx2).
#include "export/texture_file.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ganzfeld::fuzz::scratch_file(data, size, ".ktx2");
  ganzfeld::fuzz::expect_clean([&] { ganzfeld::exporting::read_ktx2(path); });
  return 0;
}
