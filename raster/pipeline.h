// Rasterizer: the pipeline of raster/ (DESIGN.md "The pipeline"), stage by stage, each in its
// own file and callable on its own:
//
//   vertex   user functor per vertex -> clip position (+ varyings); projected and snapped in SIMD
//            lanes (setup.h projectVertices); non-finite positions flagged and counted.
//   assemble per triangle, in parallel fixed-size chunks (assemble.h): frustum reject, homogeneous
//            clipping for the triangles that need it (clip.h), then setup (setup.h): snapping,
//            facing and zero-area culling, exact edge functions.
//   bin      each chunk bins its set-up triangles to the tiles of the TileGrid (bin.h); a tile
//            reads the chunks in index order, so submission order is preserved per tile whatever
//            the scheduling.
//   tile     one TBB task per tile (tile.h): hierarchical block reject/accept, coarse depth, SIMD
//            coverage and early depth test.
//   fragment (draw only) the user functor per pixel that passed, with perspective-correct
//            barycentrics and varyings, in submission order within the tile (fragment.h).
//
// Thread-safety: a Rasterizer is not thread-safe (one draw at a time); it owns the TBB arena its
// passes run in and the scratch buffers they reuse. Functors are called concurrently from several
// threads: the vertex functor for distinct vertices, the fragment functor for distinct tiles. The
// fragment functor must not itself run TBB algorithms (the waiting thread could pick up another
// tile's task and reuse this thread's scratch).
// Invalid arguments (a configuration out of range, more than kMaxVaryings varyings, a target
// larger than kMaxTargetSize) throw std::invalid_argument: they are programming errors.
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdint>
#include <glm/vec4.hpp>
#include <span>
#include <stdexcept>
#include <vector>

#include "raster/assemble.h"
#include "raster/bin.h"
#include "raster/clip.h"
#include "raster/depth_target.h"
#include "raster/fragment.h"
#include "raster/setup.h"
#include "raster/simd.h"
#include "raster/stats.h"
#include "raster/tile.h"

namespace penumbra::raster {

struct RasterConfig {
  int threads = 0;             // worker threads, 0 = all hardware threads; [0, 1024]
  int tileLog2 = 6;            // tile side 2^tileLog2 pixels (default 64); [3, 10]
  int chunkTriangles = 2048;   // triangles per binning chunk (fixed: not derived from threads); [64, 2^20]
  // Triangles set up, binned and rasterized together, batch after batch: bounds the memory a draw
  // holds (64 bytes per set-up triangle). Small batches keep that data in cache but concentrate
  // a batch's work in few tiles (a batch of a spatially coherent mesh covers a small part of the
  // screen), which starves threads; measured, 1M triangles per batch is the better trade-off
  // (docs/performance.md). 0 = 512 chunks (1M triangles, 64 MiB). The image never depends on it.
  int batchChunks = 0;         // chunks per batch; 0 or [1, 2^20]
  SimdChoice simd{};           // SIMD target per kernel family (simd.h); 0s: the best this CPU supports
};

struct DrawDesc {
  uint32_t vertexCount = 0;
  std::span<const uint32_t> indices;  // 3 per triangle; empty: non-indexed, vertexCount / 3 triangles
  int varyings = 0;                   // floats per vertex for the fragment stage, [0, kMaxVaryings]
  CullMode cull = CullMode::None;
  DepthFunc depthFunc = DepthFunc::Less;
  bool depthWrite = true;
};

class Rasterizer {
 public:
  explicit Rasterizer(const RasterConfig& config = {});

  const RasterConfig& config() const { return config_; }
  // The tiles of this rasterizer's passes over a width x height target.
  TileGrid tileGrid(int width, int height) const { return TileGrid(width, height, config_.tileLog2); }
  int threads() const { return arena_.max_concurrency(); }
  // Runs f inside this rasterizer's arena (so TBB loops in f use its threads).
  template <class F>
  auto run(F&& f) {
    return arena_.execute(std::forward<F>(f));
  }

  // Clears depth and coarse depth, in parallel.
  void clear(DepthTarget& depth, float value);

  // Depth-only pass (shadow maps): vs(uint32_t vertex) -> glm::vec4 clip position. No varyings,
  // no fragment stage.
  template <class VS>
  PassStats drawDepth(const DrawDesc& desc, DepthTarget& depth, VS&& vs);

  // Full pass: vs(uint32_t vertex, float* varyings) -> glm::vec4 clip position, writing
  // desc.varyings floats; fs(const Fragment&) for every pixel that passes the depth test. The
  // fragment functor writes its own targets (any number, any pixel type) at (x, y).
  template <class VS, class FS>
  PassStats draw(const DrawDesc& desc, DepthTarget& depth, VS&& vs, FS&& fs);

  // Multisampled full pass: depth.size() samples per pixel (1, 2, 4 or 8, at samplePattern's
  // positions), one depth target per sample, all of one size. The vertex stage runs once; then each
  // sample's pass sets up, bins and rasterizes the triangles moved by minus its offset (Viewport::
  // sampleX), so its coverage, depth test and fragments are exact at the sample position. fs gets
  // Fragment::sample; for one sample this is draw(). The stats are those of every sample's pass
  // summed (triangles counted once per sample).
  template <class VS, class FS>
  PassStats drawSamples(const DrawDesc& desc, std::span<DepthTarget> depth, VS&& vs, FS&& fs);

 private:
  using Clock = std::chrono::steady_clock;
  using FragmentSink = void (*)(void* user, uint32_t tile, const TileWork& work, const Rasterizer& self);

  template <class VS, bool kVary>
  void vertexStage(uint32_t count, int nv, VS& vs, const Viewport& vp, PassStats& stats);
  void checkDraw(const DrawDesc& desc, const DepthTarget& depth) const;
  // Assembly, setup and binning of triangles [first, last) of the draw into chunks_.
  void frontEnd(const DrawDesc& desc, const Viewport& vp, bool wantAttrs, uint64_t first, uint64_t last,
                PassStats& stats);
  // Tile stage of what frontEnd binned; per-tile counters accumulate in tileStats_.
  void tileStage(const DrawDesc& desc, DepthTarget& depth, FragmentSink sink, void* user);
  // Front end and tile stage, batch after batch, and the stats of both.
  void runBatches(const DrawDesc& desc, DepthTarget& depth, const Viewport& vp, bool wantAttrs, FragmentSink sink,
                  void* user, PassStats& stats);
  // The vertex stage's screen positions again for another sample's viewport (same flags).
  void reproject(const Viewport& vp);
  template <class FS>
  static void shadeTile(void* user, uint32_t tile, const TileWork& work, const Rasterizer& self);
  static double ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  }

  RasterConfig config_;
  tbb::task_arena arena_;
  int nv_ = 0;
  std::vector<glm::vec4> clip_;
  std::vector<ScreenVert> screen_;
  std::vector<float> vary_;
  // Per chunk of the current batch: its set-up triangles and their per-tile lists.
  std::vector<AssembledChunk> chunks_;
  std::vector<TileBins> bins_;
  size_t chunkCount_ = 0;
  TileGrid grid_;
  tbb::enumerable_thread_specific<TileWork> scratch_;
  std::vector<PassStats> tileStats_;
};

// ---------------------------------------------------------------------------------------------
// Templates.

// projectVertices reads the clip positions as 4 floats each.
static_assert(sizeof(glm::vec4) == 4 * sizeof(float));

template <class VS, bool kVary>
void Rasterizer::vertexStage(uint32_t count, int nv, VS& vs, const Viewport& vp, PassStats& stats) {
  clip_.resize(count);
  screen_.resize(count);
  vary_.resize(static_cast<size_t>(count) * static_cast<size_t>(nv));
  stats.verticesIn = count;
  const GuardPlanes guard = guardPlanes(vp);
  stats.verticesNonFinite = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, count, 4096), uint64_t{0},
      [&](const tbb::blocked_range<uint32_t>& r, uint64_t bad) {
        for (uint32_t i = r.begin(); i != r.end(); ++i) {
          if constexpr (kVary) {
            clip_[i] = vs(i, vary_.data() + static_cast<size_t>(i) * static_cast<size_t>(nv));
          } else {
            clip_[i] = vs(i);
          }
        }
        return bad + projectVertices(&clip_[r.begin()].x, r.size(), vp, guard, &screen_[r.begin()], config_.simd.setup);
      },
      [](uint64_t a, uint64_t b) { return a + b; });
}

template <class VS>
PassStats Rasterizer::drawDepth(const DrawDesc& desc, DepthTarget& depth, VS&& vs) {
  checkDraw(desc, depth);
  PassStats stats;
  arena_.execute([&] {
    const auto t0 = Clock::now();
    const Viewport vp{depth.width(), depth.height()};
    nv_ = 0;
    vertexStage<VS, false>(desc.vertexCount, 0, vs, vp, stats);
    const auto t1 = Clock::now();
    runBatches(desc, depth, vp, false, nullptr, nullptr, stats);
    stats.msVertex = ms(t0, t1);
    stats.msTotal = ms(t0, Clock::now());
  });
  return stats;
}

template <class VS, class FS>
PassStats Rasterizer::draw(const DrawDesc& desc, DepthTarget& depth, VS&& vs, FS&& fs) {
  checkDraw(desc, depth);
  PassStats stats;
  arena_.execute([&] {
    const auto t0 = Clock::now();
    const Viewport vp{depth.width(), depth.height()};
    nv_ = desc.varyings;
    vertexStage<VS, true>(desc.vertexCount, nv_, vs, vp, stats);
    const auto t1 = Clock::now();
    using F = std::remove_reference_t<FS>;
    runBatches(desc, depth, vp, true, &Rasterizer::shadeTile<F>, const_cast<void*>(static_cast<const void*>(&fs)),
               stats);
    stats.msVertex = ms(t0, t1);
    stats.msTotal = ms(t0, Clock::now());
  });
  return stats;
}

template <class VS, class FS>
PassStats Rasterizer::drawSamples(const DrawDesc& desc, std::span<DepthTarget> depth, VS&& vs, FS&& fs) {
  const int n = static_cast<int>(depth.size());
  if (!isSampleCount(n)) throw std::invalid_argument("drawSamples: 1, 2, 4 or 8 depth targets (one per sample)");
  for (const DepthTarget& d : depth) {
    checkDraw(desc, d);
    if (d.width() != depth[0].width() || d.height() != depth[0].height())
      throw std::invalid_argument("drawSamples: the sample targets differ in size");
  }
  if (n == 1) return draw(desc, depth[0], std::forward<VS>(vs), std::forward<FS>(fs));
  PassStats stats;
  arena_.execute([&] {
    const auto t0 = Clock::now();
    const std::span<const SampleOffset> pattern = samplePattern(n);
    const auto viewport = [&](int s) {
      const SampleOffset o = pattern[static_cast<size_t>(s)];
      return Viewport{depth[0].width(), depth[0].height(), o.dx * (kSubpixelOne / 16), o.dy * (kSubpixelOne / 16)};
    };
    nv_ = desc.varyings;
    vertexStage<VS, true>(desc.vertexCount, nv_, vs, viewport(0), stats);
    stats.msVertex = ms(t0, Clock::now());
    for (int s = 0; s < n; ++s) {
      if (s > 0) reproject(viewport(s));
      const auto withSample = [&fs, s](const Fragment& f) {
        Fragment g = f;
        g.sample = s;
        fs(g);
      };
      using W = decltype(withSample);
      runBatches(desc, depth[static_cast<size_t>(s)], viewport(s), true, &Rasterizer::shadeTile<const W>,
                 const_cast<void*>(static_cast<const void*>(&withSample)), stats);
    }
    stats.msTotal = ms(t0, Clock::now());
  });
  return stats;
}

template <class FS>
void Rasterizer::shadeTile(void* user, uint32_t tile, const TileWork& work, const Rasterizer& self) {
  FS& fs = *static_cast<FS*>(user);
  shadeTileFragments(fs, tile, work, std::span<const AssembledChunk>(self.chunks_.data(), self.chunkCount_),
                     self.vary_.data(), self.nv_);
}

}  // namespace penumbra::raster
