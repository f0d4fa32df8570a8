// Fuzz target: an .xyz point file's text.
#include "apps/point_cloud.h"
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  penumbra::apps::parseXyz(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.xyz");
  return 0;
}
