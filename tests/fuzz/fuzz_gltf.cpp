// Fuzz target: a glTF file's bytes (.gltf text or .glb), loaded as if from a folder holding
// nothing else (every external URI is then missing, outside or refused).
#include <vector>

#include "engine/gltf_loader.h"
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  penumbra::engine::parseGltf(std::vector<unsigned char>(data, data + size), "/nonexistent-fuzz-folder/model.gltf");
  return 0;
}
