// Bin stage: the screen cut into square tiles, and lists of what reaches each tile.
//
// TileGrid is the one description of the tiles that every tile-parallel pass uses (the pipeline's
// tile stage, the stochastic rasterizer, fragment stages that keep per-tile lists): tile side
// 2^log2 pixels (64 by default: 4 KiB of float depth, 64 blocks of 8x8), tiles numbered row by
// row from the top-left, the last row and column clipped to the target.
//
// binRects: the pixel rectangles of a sequence of items (set-up triangles, footprints) into
// per-tile lists, CSR (a count per tile, a prefix sum, a fill in item order), so every tile's
// list keeps the submission order of the items. One call bins one chunk; a tile that reads the
// chunks in index order sees all items in submission order, whatever the scheduling.
//
// Thread-safety: pure functions; TileGrid and TileBins are plain values (one writer at a time).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::raster {

// Inclusive pixel rectangle [x0, x1] x [y0, y1]; empty when x0 > x1 or y0 > y1.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
};
inline PixelRect intersect(const PixelRect& a, const PixelRect& b) {
  return {a.x0 > b.x0 ? a.x0 : b.x0, a.y0 > b.y0 ? a.y0 : b.y0, a.x1 < b.x1 ? a.x1 : b.x1, a.y1 < b.y1 ? a.y1 : b.y1};
}

struct TileGrid {
  int width = 0, height = 0;  // the target, pixels
  int log2 = 6;               // tile side 2^log2 pixels
  int tilesX = 0, tilesY = 0;

  TileGrid() = default;
  TileGrid(int width, int height, int log2);
  int side() const { return 1 << log2; }
  uint32_t count() const { return static_cast<uint32_t>(tilesX) * static_cast<uint32_t>(tilesY); }
  // The tile holding pixel (x, y) of the target.
  uint32_t tileOf(int x, int y) const {
    return static_cast<uint32_t>(y >> log2) * static_cast<uint32_t>(tilesX) + static_cast<uint32_t>(x >> log2);
  }
  // The pixels of tile t, clipped to the target.
  PixelRect rect(uint32_t t) const;
};

// Per-tile lists of item indices: the items of tile t are entries[offsets[t] .. offsets[t + 1]).
struct TileBins {
  std::vector<uint64_t> offsets;  // count() + 1 (64-bit: n items times many tiles can pass 2^32)
  std::vector<uint32_t> entries;  // item indices, in item order within a tile
  std::vector<uint64_t> packed;   // scratch: each item's tile rectangle
  std::span<const uint32_t> tile(uint32_t t) const {
    return {entries.data() + offsets[t], entries.data() + offsets[t + 1]};
  }
};

// Bins items 0 .. n-1 whose pixel rectangles rect(i) lie inside the target (empty rectangles reach
// no tile). Reuses `bins`' storage.
template <class RectOf>
void binRects(const TileGrid& grid, uint32_t n, RectOf&& rect, TileBins& bins);

// ---------------------------------------------------------------------------------------------

template <class RectOf>
void binRects(const TileGrid& grid, uint32_t n, RectOf&& rect, TileBins& bins) {
  const uint32_t tiles = grid.count();
  const int s = grid.log2;
  const uint32_t tx = static_cast<uint32_t>(grid.tilesX);
  // packed[i]: ~0 (empty), kOneTile | tile, or the tile rectangle tx0 | tx1 << 16 | ty0 << 32 | ty1 << 48
  // (tile coordinates stay below 2^15, kMaxTargetSize, so bit 63 marks the one-tile form).
  constexpr uint64_t kOneTile = uint64_t{1} << 63;
  bins.offsets.assign(tiles + 1, 0);
  bins.packed.resize(n);
  // Count per tile (shifted by one, for the prefix sum).
  for (uint32_t i = 0; i < n; ++i) {
    const PixelRect r = rect(i);
    if (r.empty()) {
      bins.packed[i] = ~uint64_t{0};
      continue;
    }
    const uint32_t tx0 = static_cast<uint32_t>(r.x0) >> s, tx1 = static_cast<uint32_t>(r.x1) >> s;
    const uint32_t ty0 = static_cast<uint32_t>(r.y0) >> s, ty1 = static_cast<uint32_t>(r.y1) >> s;
    if (tx0 == tx1 && ty0 == ty1) {  // one tile: the common case for small items, without the loops
      const uint32_t t = ty0 * tx + tx0;
      bins.packed[i] = kOneTile | t;
      ++bins.offsets[t + 1];
      continue;
    }
    bins.packed[i] = uint64_t{tx0} | (uint64_t{tx1} << 16) | (uint64_t{ty0} << 32) | (uint64_t{ty1} << 48);
    for (uint32_t ty = ty0; ty <= ty1; ++ty)
      for (uint32_t x = tx0; x <= tx1; ++x) ++bins.offsets[ty * tx + x + 1];
  }
  for (uint32_t t = 0; t < tiles; ++t) bins.offsets[t + 1] += bins.offsets[t];
  bins.entries.resize(bins.offsets[tiles]);
  // Fill: offsets[t] serves as the cursor of tile t, then is shifted back to the start.
  for (uint32_t i = 0; i < n; ++i) {
    const uint64_t p = bins.packed[i];
    if (p == ~uint64_t{0}) continue;
    if (p & kOneTile) {
      bins.entries[bins.offsets[static_cast<uint32_t>(p)]++] = i;
      continue;
    }
    const auto tx0 = static_cast<uint32_t>(p & 0xffff), tx1 = static_cast<uint32_t>((p >> 16) & 0xffff);
    const auto ty0 = static_cast<uint32_t>((p >> 32) & 0xffff), ty1 = static_cast<uint32_t>(p >> 48);
    for (uint32_t ty = ty0; ty <= ty1; ++ty)
      for (uint32_t x = tx0; x <= tx1; ++x) bins.entries[bins.offsets[ty * tx + x]++] = i;
  }
  for (uint32_t t = tiles; t > 0; --t) bins.offsets[t] = bins.offsets[t - 1];
  bins.offsets[0] = 0;
}

}  // namespace penumbra::raster
