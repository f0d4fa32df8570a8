// SIMD targets. Each family of hot loops -- vertex projection and triangle setup
// (setup_lanes.cpp), the tile stage (tile_kernels.cpp), point splatting (splat.cpp), the
// shadow-map tap kernels (shadows/kernel_taps.cpp) -- is written once over Highway's lane types,
// compiled for every x86 target Highway knows (SSE2 to AVX-512 and a scalar fallback) and
// dispatched at run time.
//
// Which target a family runs is a value, SimdChoice, carried by whatever runs it (RasterConfig::simd
// for a Rasterizer's passes and the techniques that run in its arena): never process state, so a
// test can run every variant of one family while every other family keeps its own choice, and two
// rasterizers with different choices can run side by side. 0 means the best target this CPU
// supports; anything else must be one of supportedSimdTargets() (the Rasterizer checks). Every
// variant gives the same bits (-ffp-contract=off; tests compare them all).
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra::raster {

struct SimdChoice {
  int64_t tile = 0;   // the tile stage's coverage and depth test
  int64_t splat = 0;  // point projection of the splatter
  int64_t taps = 0;   // shadow-map tap kernels (PCF, PCSS)
  int64_t setup = 0;  // vertex projection and triangle setup in lanes (projectVertices, setupLanes)
  int64_t shade = 0;  // per-pixel shading kernels (shadows::irradianceFactors)
};

// The targets compiled in and supported by this CPU, best first, and their names.
std::vector<int64_t> supportedSimdTargets();
const char* simdTargetName(int64_t target);
bool isSupportedSimdTarget(int64_t target);  // 0 counts as supported (the best)

// For the kernels' own files: the entry of a Highway dispatch table (HWY_EXPORT) that runs
// `target`; for 0, the entry HWY_DYNAMIC_DISPATCH would use (the best target, detected once). Every
// kernel file is compiled for the same targets (HWY_TARGETS), so one index serves every table.
size_t simdDispatchIndex(int64_t target);
// The target a dispatch by simdDispatchIndex(target) runs (tests: it is `target`, or the best for 0).
int64_t simdTargetRun(int64_t target);

}  // namespace penumbra::raster
