// MERL binary BRDF files (models/measured.h: read_merl). A valid file is 34,992,012 bytes, so the
// fuzzer explores the header and size checks; the spec path (merl:file=...) is the spec target's.
#include "fuzz/fuzz_support.h"
#include "models/measured.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ganzfeld::fuzz::scratch_file(data, size, ".binary");
  ganzfeld::fuzz::expect_clean([&] { ganzfeld::read_merl(path); });
  return 0;
}
