// Tile stage of the stochastic rasterizer: one tile's samples and, per bounding method, the loop
// that decides which of them a triangle's exact test (coverage.h) sees. Every method tests a
// superset of the samples the triangle covers, so all give the same bits; they differ in how many
// tests they run (the sample test efficiency, hits / tests).
//
//   testStatic    a static triangle through a pinhole: one test at the pixel centre decides all
//                 the pixel's samples (they share it);
//   testBox       every sample of every pixel in the footprint over the whole shutter and lens;
//   testInterval  per stratum of time and lens, the pixels of its footprint, and there only the
//                 samples inside the stratum (a time stratum is an index range: the samples of a
//                 pixel are sorted by time);
//   testDual      per block of pixels, the (t, u, v) box at which the triangle may overlap it
//                 (bounds.h dualSpaceDomain), and the samples inside it.
//
// Thread-safety: a TileSamples belongs to one task; the functions write only it and the counters
// they are given.
#pragma once

#include <cstdint>
#include <glm/vec4.hpp>
#include <span>
#include <vector>

#include "stochastic/bounds.h"
#include "stochastic/coverage.h"
#include "stochastic/sample_pattern.h"
#include "stochastic/setup.h"
#include "stochastic/stats.h"

namespace penumbra::stochastic {

// The samples of one tile, pixel-major (spp per pixel): their (t, u, v), the nearest depth found
// so far and what covers them (a triangle, kStaticRef or kNoTriangle), and tests per pixel.
struct TileSamples {
  raster::PixelRect rect;
  int spp = 0;
  std::vector<Sample> samples;
  std::vector<uint16_t> stratum;  // interval method: each sample's stratum
  std::vector<float> depth;
  std::vector<uint32_t> ref;
  std::vector<uint32_t> tests;

  size_t pixel(int x, int y) const {
    return static_cast<size_t>(y - rect.y0) * static_cast<size_t>(rect.x1 - rect.x0 + 1) + static_cast<size_t>(x - rect.x0);
  }
};

// One triangle as the loops test it.
struct TestedTriangle {
  uint32_t index = 0;
  glm::vec4 a[3], b[3];      // clip positions at shutter open and close
  raster::PixelRect rect;    // its footprint, clipped to the tile
};

// What the loops need besides the triangle.
struct TestContext {
  const SampleTarget* target = nullptr;
  ThinLens lens;
  bool motion = true;
  bool stratified = true;  // sample k of a pixel has t in [k/S, (k+1)/S)
};

// Counters of one triangle in one tile (tests and hits also go to the per-triangle STE).
struct TestCounters {
  uint64_t tests = 0, hits = 0;
};

void testStatic(const TestedTriangle& tri, const TestContext& ctx, TileSamples& ts, TestCounters& c,
                StochasticStats& st);
void testBox(const TestedTriangle& tri, const TestContext& ctx, TileSamples& ts, TestCounters& c, StochasticStats& st);
void testInterval(const TestedTriangle& tri, const TestContext& ctx, const Strata& strata,
                  std::span<const raster::PixelRect> strataRects, TileSamples& ts, TestCounters& c, StochasticStats& st);
void testDual(const TestedTriangle& tri, const TestContext& ctx, int dualBlock, int width, int height, TileSamples& ts,
              TestCounters& c, StochasticStats& st);

}  // namespace penumbra::stochastic
