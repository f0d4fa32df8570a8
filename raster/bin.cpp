#include "raster/bin.h"

#include <algorithm>

namespace penumbra::raster {

TileGrid::TileGrid(int w, int h, int l2) : width(w), height(h), log2(l2) {
  tilesX = (w + (1 << l2) - 1) >> l2;
  tilesY = (h + (1 << l2) - 1) >> l2;
}

PixelRect TileGrid::rect(uint32_t t) const {
  const int tx = static_cast<int>(t % static_cast<uint32_t>(tilesX)), ty = static_cast<int>(t / static_cast<uint32_t>(tilesX));
  const int s = side();
  return {tx * s, ty * s, std::min(width, (tx + 1) * s) - 1, std::min(height, (ty + 1) * s) - 1};
}

}  // namespace penumbra::raster
