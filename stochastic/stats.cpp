#include "stochastic/stats.h"

#include <cstdio>

#include "stochastic/resolve.h"

namespace penumbra::stochastic {

void StochasticStats::addTile(const StochasticStats& s) {
  blocksCulled += s.blocksCulled;
  samplesScanned += s.samplesScanned;
  tests += s.tests;
  hits += s.hits;
  staticShared += s.staticShared;
  depthPassed += s.depthPassed;
  pixelsMerged += s.pixelsMerged;
}

std::string StochasticStats::report(const std::string& method) const {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "  stochastic pass (%s bounds, %d spp): %.2f ms (setup and bin %.2f, tiles %.2f)\n"
                "    triangles %llu: static through a pinhole %llu (one test per pixel for all its samples), "
                "dropped (non-finite) %llu, no pixel centre in reach (off screen or between samples) %llu; bounds %llu\n"
                "    samples %llu; scanned %llu, exact tests %llu, hits %llu: STE %.3f (per triangle: p10 %.3f, median "
                "%.3f, p90 %.3f); shared static tests decided %llu samples; depth passed %llu; dual-space blocks culled "
                "%llu; pixels with > %d surfaces %llu\n",
                method.c_str(), spp, msTotal, msSetup, msRaster, static_cast<unsigned long long>(triangles),
                static_cast<unsigned long long>(trianglesStatic), static_cast<unsigned long long>(trianglesDropped),
                static_cast<unsigned long long>(trianglesNoSample), static_cast<unsigned long long>(bounds),
                static_cast<unsigned long long>(samples), static_cast<unsigned long long>(samplesScanned),
                static_cast<unsigned long long>(tests), static_cast<unsigned long long>(hits), ste(), steTriangleP10,
                steTriangleMedian, steTriangleP90,
                static_cast<unsigned long long>(staticShared), static_cast<unsigned long long>(depthPassed),
                static_cast<unsigned long long>(blocksCulled), kMaxLayers,
                static_cast<unsigned long long>(pixelsMerged));
  return buf;
}

}  // namespace penumbra::stochastic
