// The stochastic stress suite of `penumbra stress --suite stochastic`: motion across the whole
// screen (and far beyond) in one shutter, circles of confusion larger than the screen, zero-length
// motion, degenerate triangles, vertices crossing the camera plane, huge coordinates. Every case
// runs each bounding method and, as the reference, every sample tested against every triangle.
// Judged: each method's samples (what covers them, their depth) equal the reference's bit for bit;
// no depth outside [0, 1] or NaN; tests never exceed samples x triangles. Reported: time, tests,
// STE per method.
// Thread-safety: runs in the given rasterizer's arena; one suite at a time per rasterizer.
#pragma once

#include <string>
#include <vector>

#include "raster/pipeline.h"

namespace penumbra::apps {

struct StochasticStressRow {
  std::string name, param, method;
  uint64_t tests = 0, hits = 0, samples = 0, triangles = 0;
  double ms = 0;
  size_t mismatches = 0;  // samples that differ from testing everything
  size_t badDepth = 0;    // NaN or outside [0, 1]
  bool ok() const { return mismatches == 0 && badDepth == 0 && tests <= samples * triangles; }
  std::string json() const;
};

std::vector<StochasticStressRow> runStochasticStress(raster::Rasterizer& rast);

}  // namespace penumbra::apps
