// Tile stage: rasterizes, in submission order, the triangles binned to one tile. Hierarchical:
// each 8x8 block of a triangle's bounding box is rejected or accepted whole from its exact edge
// values at the block's extreme pixel centres, rejected when coarse depth proves it hidden, and
// otherwise evaluated pixel by pixel in SIMD lanes (exact 32-bit edge values, see
// tile_kernels.cpp), depth-tested and written.
//
// The SIMD code is compiled for every x86 target Highway knows (SSE4, AVX2, AVX-512, ...) and runs
// the target TileJob::simd names (simd.h: 0 = the best the CPU supports); tests run each in turn.
//
// Thread-safety: rasterizeTile may run concurrently for distinct tiles of the same target.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/setup.h"
#include "raster/simd.h"
#include "raster/stats.h"

namespace penumbra::raster {

// Pixels of one block a triangle drew (passed coverage and the depth test), for the fragment path.
struct BlockHit {
  uint32_t tri;    // index into TileJob::tris
  uint16_t bx, by; // block coordinates in the image (pixel = 8 * b)
  uint64_t mask;   // bit (y * 8 + x) for pixel (8 bx + x, 8 by + y)
};

struct TileJob {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixel rectangle [x0, x1) x [y0, y1), 8-aligned x0/y0
  int width = 0, height = 0;           // viewport
  float* depth = nullptr;              // depth image (padded, see Image)
  int depthStride = 0;
  float* blockMin = nullptr;           // coarse depth, one per 8x8 block of the image
  float* blockMax = nullptr;
  int blocksX = 0;
  DepthFunc func = DepthFunc::Less;
  bool depthWrite = true;
  const SetupTri* const* tris = nullptr;
  uint32_t count = 0;
  std::vector<BlockHit>* hits = nullptr;  // null: depth only
  int64_t simd = 0;                       // SIMD target (simd.h), 0: the best
};

// Runs job.simd's SIMD target.
void rasterizeTile(const TileJob& job, PassStats& stats);

}  // namespace penumbra::raster
