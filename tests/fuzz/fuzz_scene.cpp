// Fuzz target: a JSON scene file's text (shapes capped at 2^20 triangles so that one input cannot
// take seconds; the cap itself is checked as it is with the real one).
#include "engine/scene_file.h"
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  penumbra::engine::parseSceneFile(text, "/nonexistent-fuzz-folder/scene.json", {.maxTriangles = size_t{1} << 20});
  return 0;
}
