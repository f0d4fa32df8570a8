// The stochastic rasterizer: time-continuous triangles seen through a thin lens, S samples per
// pixel, an exact test per sample (coverage.h), a per-sample depth test, and a resolve of each
// pixel's samples into at most kMaxLayers surfaces with their sample counts (resolve.h).
//
// Stages, like the main pipeline's (DESIGN.md "Stochastic rasterization"), one file each:
//   setup    per triangle, in parallel: validity and the bound of the chosen method (setup.h,
//            bounds.h); for the interval method one rectangle per stratum.
//   bin      triangles to the tiles of raster's TileGrid by their footprint, in submission order
//            (raster/bin.h, the pipeline's own binning).
//   tile     one TBB task per tile: the tile's samples (sample_pattern.h) in a tile-local buffer
//            (depth, what covers it), initialised from the static layer; each triangle tests the
//            samples its bound admits, in submission order (sample_tests.h: one loop per method);
//   resolve  each pixel's samples grouped by surface (resolve.h); statistics in stats.h.
// Bounding methods (BoundMethod): Box, the footprint over the whole shutter and lens; Interval,
// the shutter cut into T strata and the lens square into L x L cells, each with its own footprint,
// tested only against the samples inside it; DualSpace, per block of dualBlock x dualBlock pixels
// (default 4) the times and lens positions at which the triangle may overlap the block (Laine et
// al. 2011). All three give the same bits; only the number of tests differs (sample test
// efficiency, STE = hits / tests).
// A static triangle seen through a pinhole (c0 == c1, no lens) covers all or none of a pixel's
// samples (they share the pixel centre): one test serves them all (counted as one test).
//
// Determinism: a tile is owned by one task; triangles are visited in submission order; counters
// are integers summed in tile order: same bits and same counts at any thread count.
// Thread-safety: a StochasticRasterizer is not thread-safe (one render at a time). Invalid
// arguments throw std::invalid_argument.
#pragma once

#include <cstdint>
#include <functional>
#include <glm/vec4.hpp>
#include <span>
#include <string>
#include <vector>

#include "raster/depth_target.h"
#include "raster/image.h"
#include "raster/pipeline.h"
#include "stochastic/bounds.h"
#include "stochastic/coverage.h"
#include "stochastic/resolve.h"
#include "stochastic/sample_pattern.h"
#include "stochastic/stats.h"

namespace penumbra::stochastic {

enum class BoundMethod : uint8_t { Box, Interval, DualSpace };
const char* boundMethodName(BoundMethod m);
bool parseBoundMethod(const std::string& name, BoundMethod& m);  // "box", "interval", "dual"

struct StochasticInput {
  std::span<const glm::vec4> clip0, clip1;  // per vertex: clip position at shutter open and close
  std::span<const uint32_t> indices;        // 3 per triangle
  std::span<const uint32_t> surface;        // per triangle: what the resolve groups samples by
  raster::CullMode cull = raster::CullMode::None;
  ThinLens lens;
  bool motion = true;  // false: clip1 is ignored (defocus only)
};

// What was already drawn by the ordinary path (static geometry through a pinhole): per pixel its
// depth (all the pixel's samples share it) and whether a surface is there.
struct StaticLayer {
  const raster::DepthTarget* depth = nullptr;
  const raster::Image<uint8_t>* covered = nullptr;
};

// Limits of the sample settings below (the engine's option specs quote them, render_options.h).
inline constexpr int kMaxTimeStrata = 64;  // Strata::tEdge holds 65 boundaries
inline constexpr int kMaxLensStrata = 8;   // Strata::lEdge holds 9; 8 x 8 x 64 strata fit a uint16_t index
inline constexpr int kMaxDualBlock = 64;   // the default tile side (blocks are cut at tile borders)

struct StochasticConfig {
  BoundMethod method = BoundMethod::DualSpace;
  int timeStrata = 0;  // interval method: shutter strata, [1, kMaxTimeStrata]; 0: 8 (4 with a lens)
  int lensStrata = 0;  // interval method: lens cells per axis, [1, kMaxLensStrata]; 0: 3 (1 without a lens)
  bool staticShortcut = true;  // one test per pixel for static triangles seen through a pinhole
  int dualBlock = 4;           // dual space: side of the pixel blocks that get their own bound (power of 2, <= kMaxDualBlock)
  bool exhaustive = false;     // tests: every sample of every pixel for every triangle, no bound at all
  SamplePattern pattern;
};

// Optional outputs for tests, pictures and reports.
struct StochasticDebug {
  std::vector<uint32_t>* sampleTriangle = nullptr;  // per sample (pixel-major, S per pixel): what covers it
  std::vector<float>* sampleDepth = nullptr;        // per sample: its depth
  std::vector<uint32_t>* testsPerPixel = nullptr;   // per pixel: exact tests
  std::vector<uint64_t>* testsPerTriangle = nullptr;
  std::vector<uint64_t>* hitsPerTriangle = nullptr;
};

// Called once per pixel after its resolve, from the tile's task (concurrently for distinct tiles):
// the pixel, its layers, what covers each of its samples (a triangle index, kStaticSurface or
// kNoTriangle) and the samples themselves (null when no triangle reached the pixel's tile: then
// every sample is static or background). The engine turns each layer into a G-buffer texel here.
using PixelSink = std::function<void(int x, int y, const ResolvedPixel& pixel, const uint32_t* sampleRef,
                                     const Sample* samples)>;

class StochasticRasterizer {
 public:
  // Runs in the raster's TBB arena (its thread count).
  explicit StochasticRasterizer(raster::Rasterizer& raster) : raster_(raster) {}

  StochasticStats render(const StochasticInput& in, const StochasticConfig& config, const StaticLayer& base,
                         raster::Image<ResolvedPixel>& out, const StochasticDebug& debug = {},
                         const PixelSink* sink = nullptr);

 private:
  raster::Rasterizer& raster_;
};

}  // namespace penumbra::stochastic
