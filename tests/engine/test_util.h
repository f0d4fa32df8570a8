// Helpers shared by the engine tests.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/image.h"

namespace penumbra::engine::test {

// The visible pixels' bytes, RGBA, row by row: compare frames byte for byte.
inline std::vector<uint8_t> bytes(const raster::ImageRgba8& img) {
  std::vector<uint8_t> b;
  for (const raster::Rgba8& p : img.packed()) b.insert(b.end(), {p.r, p.g, p.b, p.a});
  return b;
}

}  // namespace penumbra::engine::test
