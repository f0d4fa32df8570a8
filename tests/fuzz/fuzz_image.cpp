// Fuzz target: a texture's encoded bytes, with no declared type and with each one glTF allows.
#include "engine/image_io.h"
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const char* mime = size > 0 ? (data[0] & 1 ? "image/png" : data[0] & 2 ? "image/jpeg" : "") : "";
  penumbra::engine::decodeTexture(data, size, mime, "fuzz");
  return 0;
}
