// Fragment stage: the user functor for every pixel a tile's triangles drew (after coverage and
// the early depth test of the tile stage), in submission order within the tile, with the depth,
// the facing, perspective-correct barycentrics of the submitted triangle and its varyings.
//
// Interpolation (conventions.h): the set-up planes give 1/w and the ordered vertices' screen
// barycentrics over w at the pixel (orderedBarycentrics); varyings are their weighted sum; a
// clipped triangle's vertices carry, after their varyings, the barycentrics of the submitted
// triangle, interpolated the same way.
//
// Thread-safety: shadeTileFragments runs concurrently for distinct tiles; the functor is called
// from those threads and must tolerate it (each tile's pixels are its own).
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "raster/assemble.h"
#include "raster/clip.h"
#include "raster/setup.h"
#include "raster/tile.h"

namespace penumbra::raster {

// What the fragment functor receives for one pixel.
struct Fragment {
  int x, y;
  uint32_t tile;         // the tile of the pass's TileGrid holding (x, y): per-tile outputs need no grid math
  float depth;           // z / w, as written to the depth target
  uint32_t primitive;    // triangle index in the draw
  bool frontFacing;
  float b0, b1, b2;      // perspective-correct barycentrics of the submitted vertices 0, 1, 2
  const float* varyings; // DrawDesc::varyings floats, perspective-correct
  int sample = 0;        // multisampled draws (Rasterizer::drawSamples): the sample, at whose
                         // position coverage, depth, barycentrics and varyings are evaluated
};

// One tile's work as the tile stage leaves it: the tile's triangles in submission order (and the
// chunk each came from) and, per triangle and 8x8 block, the pixels it drew.
struct TileWork {
  std::vector<const SetupTri*> tris;
  std::vector<uint32_t> chunkOf;
  std::vector<BlockHit> hits;
};

// Calls fs(const Fragment&) for every pixel of `work.hits`. vary: the vertex stage's varyings (nv
// per vertex); chunks: the draw's assembled chunks that work.chunkOf indexes.
template <class FS>
void shadeTileFragments(FS& fs, uint32_t tile, const TileWork& work, std::span<const AssembledChunk> chunks,
                        const float* vary, int nv) {
  float interp[kMaxVaryings + 3];
  for (const BlockHit& h : work.hits) {
    const SetupTri& t = *work.tris[h.tri];
    const AssembledChunk& ch = chunks[work.chunkOf[h.tri]];
    // Attributes are stored one to one with the chunk's triangles.
    const SetupAttr& a = ch.attrs[static_cast<size_t>(&t - ch.tris.data())];
    // Clipped triangles carry, after their varyings, the barycentrics of the submitted triangle.
    const size_t stride = static_cast<size_t>(nv) + (a.clipped ? 3 : 0);
    const float* v[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t ref = a.vary[k];
      v[k] = (ref & kChunkLocalVarying) ? ch.clipVary.data() + static_cast<size_t>(ref & ~kChunkLocalVarying) * stride
                                        : vary + static_cast<size_t>(ref) * stride;
    }
    const int nInterp = static_cast<int>(stride);
    Fragment f;
    f.tile = tile;
    f.primitive = t.primitive;
    f.frontFacing = a.frontFacing;
    f.varyings = interp;
    uint64_t m = h.mask;
    while (m) {
      const int bit = std::countr_zero(m);
      m &= m - 1;
      f.x = h.bx * kBlockSize + (bit & (kBlockSize - 1));
      f.y = h.by * kBlockSize + (bit >> kBlockLog2);
      float bc[3];
      orderedBarycentrics(t, a, f.x, f.y, bc);
      const float b0 = bc[0], b1 = bc[1], b2 = bc[2];
      for (int c = 0; c < nInterp; ++c) interp[c] = v[0][c] * b0 + v[1][c] * b1 + v[2][c] * b2;
      f.depth = depthAt(t, f.x, f.y);
      if (a.clipped) {
        f.b0 = interp[nv];
        f.b1 = interp[nv + 1];
        f.b2 = interp[nv + 2];
      } else {
        // The planes are in setup (ordered) vertex order; a.order maps back to submission order.
        float sb[3];
        sb[a.order[0]] = b0;
        sb[a.order[1]] = b1;
        sb[a.order[2]] = b2;
        f.b0 = sb[0];
        f.b1 = sb[1];
        f.b2 = sb[2];
      }
      fs(f);
    }
  }
}

}  // namespace penumbra::raster
