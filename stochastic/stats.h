// StochasticStats: what one stochastic pass did and what it saved. Counters are integers summed
// from per-tile records in tile order (the same at any thread count); times are wall clock.
//
// Thread-safety: a plain value type, no shared state (one writer at a time).
#pragma once

#include <cstdint>
#include <string>

namespace penumbra::stochastic {

struct StochasticStats {
  uint64_t triangles = 0, trianglesStatic = 0, trianglesDropped = 0, trianglesNoSample = 0;
  uint64_t bounds = 0;             // rectangles set up (strata for the interval method)
  uint64_t blocksCulled = 0;       // dual space: pixel blocks whose (t, u, v) bound was empty
  uint64_t samplesScanned = 0;     // samples whose (t, u, v) was compared with a bound
  uint64_t tests = 0;              // exact coverage tests
  uint64_t hits = 0;               // tests that found the sample covered
  uint64_t staticShared = 0;       // samples decided by a test shared with the pixel's others
  uint64_t depthPassed = 0;
  uint64_t pixelsMerged = 0;
  int spp = 0;
  uint64_t samples = 0;            // width * height * spp
  // Per triangle (those tested at least once): STE quantiles, nearest rank.
  double steTriangleP10 = 0, steTriangleMedian = 0, steTriangleP90 = 0;
  double msSetup = 0, msRaster = 0, msTotal = 0;
  double ste() const { return tests ? static_cast<double>(hits) / static_cast<double>(tests) : 0.0; }
  // Adds the per-tile counters of `tile` (blocks culled, scanned, tests, hits, shared, depth
  // passed, merged pixels).
  void addTile(const StochasticStats& tile);
  std::string report(const std::string& method) const;
};

}  // namespace penumbra::stochastic
