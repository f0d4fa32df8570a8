// The raster stress suite of `penumbra stress`: numerically hard cases, each checked on the fly
// against what must hold (a closed tessellation covers every pixel exactly once; the nearer of two
// surfaces wins; nothing non-finite is produced).
// Thread-safety: runs in the given rasterizer's arena; one suite at a time per rasterizer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raster/pipeline.h"

namespace penumbra::apps {

struct StressRow {
  std::string name, param;
  uint64_t pixels = 0;       // pixels checked
  uint64_t cracks = 0;       // pixels a closed tessellation left uncovered
  uint64_t doubles = 0;      // pixels covered more than once (or drawn where nothing should be)
  uint64_t nonFinite = 0;    // NaN/Inf depths or varyings produced
  uint64_t depthErrors = 0;  // pixels where the farther surface won
  uint64_t clipped = 0;      // triangles that went through clipping
  bool judged = true;        // false: reported only (a documented precision limit, not a defect)
  std::string note;
  bool ok() const { return !judged || (cracks == 0 && doubles == 0 && nonFinite == 0 && depthErrors == 0); }
  std::string json() const;
};

std::vector<StressRow> runRasterStress(raster::Rasterizer& rast);

}  // namespace penumbra::apps
