// PassStats: what one pass did and what it skipped. Counters are integers summed from per-chunk and
// per-tile partial records in a fixed order, so they are identical whatever the thread count.
//
// Thread-safety: a plain value type; each pass fills its own records (per chunk, per tile) and
// sums them on one thread.
#pragma once

#include <cstdint>
#include <string>

namespace penumbra::raster {

struct PassStats {
  // Vertex stage.
  uint64_t verticesIn = 0;
  uint64_t verticesNonFinite = 0;  // dropped: NaN/Inf clip position
  // Triangle front end.
  uint64_t trianglesIn = 0;
  uint64_t trianglesDroppedInvalid = 0;    // used a non-finite vertex or an out-of-range index
  // The culling counters below also count the pieces of clipped triangles (trianglesFromClipping).
  uint64_t trianglesCulledFrustum = 0;     // all vertices outside one frustum plane, or clipped away
  uint64_t trianglesCulledFacing = 0;      // back/front-face culling
  uint64_t trianglesCulledDegenerate = 0;  // zero area after snapping
  uint64_t trianglesCulledNoSample = 0;    // bounding box holds no pixel centre
  uint64_t trianglesClipped = 0;           // went through homogeneous clipping (near/far/guard band)
  uint64_t trianglesFromClipping = 0;      // triangles the clipper emitted
  uint64_t trianglesBinned = 0;            // reached at least one tile
  uint64_t binEntries = 0;                 // (triangle, tile) pairs
  // Tiles and blocks.
  uint64_t tilesTotal = 0;
  uint64_t tilesTouched = 0;
  uint64_t tilesSkipped = 0;              // no triangle: cost nothing
  uint64_t blocksTested = 0;              // 8x8 blocks a triangle's bounding box touched
  uint64_t blocksRejectedEdge = 0;        // outside an edge
  uint64_t blocksRejectedDepth = 0;       // coarse depth: behind everything already in the block
  uint64_t blocksAccepted = 0;            // evaluated, fully inside all three edges
  uint64_t blocksPartial = 0;             // evaluated, crossed by an edge (tested = sum of these four)
  // Pixels.
  uint64_t pixelsTested = 0;              // pixel centres evaluated in SIMD lanes
  uint64_t pixelsCovered = 0;             // inside the triangle
  uint64_t pixelsDepthPassed = 0;         // passed the early depth test (= fragments shaded)
  // Time per stage, milliseconds (wall clock of the stage as a whole).
  double msVertex = 0, msSetupBin = 0, msRaster = 0, msTotal = 0;

  PassStats& operator+=(const PassStats& o);
  // Multi-line human readable report (the CLI's --stats).
  std::string report(const std::string& title) const;
};

}  // namespace penumbra::raster
