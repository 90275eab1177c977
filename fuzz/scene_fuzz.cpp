// Scene JSON (scene/scene.h), parsed from memory; relative mesh paths resolve beside a scene
// file that does not exist, and only the scene is parsed (no mesh is loaded, no table planned).
#include "fuzz/fuzz_support.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ganzfeld::fuzz::expect_clean(
      [&] { ganzfeld::load_scene_text(ganzfeld::fuzz::text(data, size), "/nonexistent/fuzz.json"); });
  return 0;
}
