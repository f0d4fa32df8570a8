#include "stochastic/rasterizer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "raster/bin.h"
#include "raster/timing.h"
#include "stochastic/sample_tests.h"
#include "stochastic/setup.h"

namespace penumbra::stochastic {

const char* boundMethodName(BoundMethod m) {
  switch (m) {
    case BoundMethod::Box: return "box";
    case BoundMethod::Interval: return "interval";
    case BoundMethod::DualSpace: return "dual";
  }
  return "?";
}

bool parseBoundMethod(const std::string& name, BoundMethod& m) {
  for (BoundMethod c : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace})
    if (name == boundMethodName(c)) {
      m = c;
      return true;
    }
  return false;
}

namespace {

void validate(const StochasticInput& in, const StochasticConfig& cfg, const StaticLayer& base, int width, int height) {
  const int spp = cfg.pattern.spp;
  if (width < 1 || height < 1 || width > raster::kMaxTargetSize || height > raster::kMaxTargetSize)
    throw std::invalid_argument("stochastic: the output must be 1 to 16384 pixels a side");
  if (spp < 1 || spp > kMaxSpp) throw std::invalid_argument("stochastic: samples per pixel must be in [1, 64]");
  if (in.indices.size() % 3 != 0 || in.surface.size() != in.indices.size() / 3)
    throw std::invalid_argument("stochastic: 3 indices and one surface per triangle");
  if (in.clip0.size() != in.clip1.size() && in.motion)
    throw std::invalid_argument("stochastic: clip0 and clip1 must have the same size");
  if ((base.depth && (base.depth->width() != width || base.depth->height() != height)) ||
      (base.covered && (base.covered->width() != width || base.covered->height() != height)))
    throw std::invalid_argument("stochastic: the static layer must have the output's size");
  if (cfg.pattern.fixed) {
    const Sample& f = *cfg.pattern.fixed;
    const bool onLens = cfg.pattern.shape == LensShape::Square ? (std::abs(f.u) <= 1.0f && std::abs(f.v) <= 1.0f)
                                                                : f.u * f.u + f.v * f.v <= 1.0f;
    if (!(f.t >= 0.0f && f.t < 1.0f) || !onLens)
      throw std::invalid_argument("stochastic: a fixed sample needs t in [0, 1) and (u, v) on the lens");
  }
  if (cfg.pattern.blockStrata < 0 || cfg.pattern.blockStrata > kMaxBlockStrata)
    throw std::invalid_argument("stochastic: block strata must be in [0, 8]");
  if (cfg.dualBlock < 1 || cfg.dualBlock > kMaxDualBlock || (cfg.dualBlock & (cfg.dualBlock - 1)) != 0)
    throw std::invalid_argument("stochastic: the dual-space block side must be a power of two in [1, 64]");
  if (cfg.timeStrata < 0 || cfg.timeStrata > kMaxTimeStrata || cfg.lensStrata < 0 || cfg.lensStrata > kMaxLensStrata)
    throw std::invalid_argument("stochastic: interval strata must be in [1, 64] (time) and [1, 8] (lens)");
}

// Everything the tiles share, read-only while they run.
struct Pass {
  const StochasticInput& in;
  const StochasticConfig& cfg;
  const StaticLayer& base;
  const StochasticDebug& debug;
  const PixelSink* sink;
  raster::Image<ResolvedPixel>& out;
  TriangleSource source;
  TriangleSetup setup{};
  Strata strata{};
  bool interval = false;
  SamplePattern pattern{};
  TestContext test{};
  raster::TileGrid grid{};
  raster::TileBins bins{};
  std::vector<uint64_t>* triTests = nullptr;
  std::vector<uint64_t>* triHits = nullptr;
};

// A tile no triangle reached: every sample is the static layer's or background, as the resolve
// would find (same pixels, without touching the samples).
void resolveEmptyTile(const Pass& ps, const raster::PixelRect& tr) {
  const int spp = ps.cfg.pattern.spp;
  uint32_t staticRefs[kMaxSpp], noRefs[kMaxSpp];
  std::fill_n(staticRefs, spp, kStaticRef);
  std::fill_n(noRefs, spp, kNoTriangle);
  for (int y = tr.y0; y <= tr.y1; ++y)
    for (int x = tr.x0; x <= tr.x1; ++x) {
      const bool covered = ps.base.covered && ps.base.covered->at(x, y);
      ResolvedPixel& o = ps.out.at(x, y);
      o = resolveUntouched(covered, spp);
      if (ps.sink) (*ps.sink)(x, y, o, covered ? staticRefs : noRefs, nullptr);
      if (ps.debug.testsPerPixel)
        (*ps.debug.testsPerPixel)[static_cast<size_t>(y) * static_cast<size_t>(ps.out.width()) + static_cast<size_t>(x)] = 0;
    }
}

// The tile's samples, each starting as the static layer's (its depth, kStaticRef) or background.
void initTile(const Pass& ps, const raster::PixelRect& tr, bool busy, TileSamples& ts) {
  const size_t spp = static_cast<size_t>(ps.cfg.pattern.spp);
  ts.rect = tr;
  ts.spp = ps.cfg.pattern.spp;
  const size_t pixels = static_cast<size_t>(tr.x1 - tr.x0 + 1) * static_cast<size_t>(tr.y1 - tr.y0 + 1);
  ts.depth.resize(pixels * spp);
  ts.ref.resize(pixels * spp);
  ts.tests.assign(pixels, 0);
  const bool strata = busy && ps.interval && !ps.cfg.exhaustive;
  if (busy) ts.samples.resize(pixels * spp);
  if (strata) ts.stratum.resize(pixels * spp);
  for (int y = tr.y0; y <= tr.y1; ++y)
    for (int x = tr.x0; x <= tr.x1; ++x) {
      const size_t p = ts.pixel(x, y);
      const float z = ps.base.depth ? ps.base.depth->at(x, y) : 1.0f;
      const uint32_t r = (ps.base.covered && ps.base.covered->at(x, y)) ? kStaticRef : kNoTriangle;
      std::fill_n(ts.depth.data() + p * spp, spp, z);
      std::fill_n(ts.ref.data() + p * spp, spp, r);
      if (!busy) continue;
      Sample* smp = ts.samples.data() + p * spp;
      pixelSamples(ps.pattern, x, y, smp);
      if (strata)
        for (size_t k = 0; k < spp; ++k) ts.stratum[p * spp + k] = ps.strata.of(smp[k]);
    }
}

// Each triangle of the tile, in submission order, through its method's loop.
void testTriangles(const Pass& ps, std::span<const uint32_t> list, TileSamples& ts, StochasticStats& st) {
  const BoundMethod method = ps.cfg.exhaustive ? BoundMethod::Box : ps.cfg.method;
  const size_t strata = ps.interval ? static_cast<size_t>(ps.strata.count()) : 0;
  for (const uint32_t t : list) {
    const TriangleBound& s = ps.setup.tris[t];
    TestedTriangle tri;
    tri.index = t;
    ps.source.fetch(t, tri.a, tri.b);
    tri.rect = intersect(s.rect, ts.rect);
    TestCounters c;
    if (s.isStatic)
      testStatic(tri, ps.test, ts, c, st);
    else if (method == BoundMethod::Box)
      testBox(tri, ps.test, ts, c, st);
    else if (method == BoundMethod::Interval)
      testInterval(tri, ps.test, ps.strata,
                   std::span<const raster::PixelRect>(ps.setup.strataRects.data() + t * strata, strata), ts, c, st);
    else
      testDual(tri, ps.test, ps.cfg.dualBlock, ps.out.width(), ps.out.height(), ts, c, st);
    st.tests += c.tests;
    st.hits += c.hits;
    // Per-triangle counts: integers added atomically, the totals do not depend on the schedule.
    if (c.tests) std::atomic_ref<uint64_t>((*ps.triTests)[t]).fetch_add(c.tests);
    if (c.hits) std::atomic_ref<uint64_t>((*ps.triHits)[t]).fetch_add(c.hits);
  }
}

// Resolve of every pixel of the tile, the sink and the debug outputs.
void resolveTile(const Pass& ps, const TileSamples& ts, bool busy, StochasticStats& st) {
  const int spp = ts.spp;
  const size_t sppz = static_cast<size_t>(spp), width = static_cast<size_t>(ps.out.width());
  for (int y = ts.rect.y0; y <= ts.rect.y1; ++y)
    for (int x = ts.rect.x0; x <= ts.rect.x1; ++x) {
      const size_t p = ts.pixel(x, y);
      const uint32_t* ref = ts.ref.data() + p * sppz;
      const Sample* samples = busy ? ts.samples.data() + p * sppz : nullptr;
      ResolvedPixel& o = ps.out.at(x, y);
      if (resolvePixel(ref, spp, ps.in.surface, samples, o)) ++st.pixelsMerged;
      if (ps.sink) (*ps.sink)(x, y, o, ref, samples);
      const size_t g = static_cast<size_t>(y) * width + static_cast<size_t>(x);
      if (ps.debug.testsPerPixel) (*ps.debug.testsPerPixel)[g] = ts.tests[p];
      for (size_t k = 0; k < sppz; ++k) {
        if (ps.debug.sampleTriangle) (*ps.debug.sampleTriangle)[g * sppz + k] = ref[k];
        if (ps.debug.sampleDepth) (*ps.debug.sampleDepth)[g * sppz + k] = ts.depth[p * sppz + k];
      }
    }
}

// STE quantiles over the triangles tested at least once (nearest rank).
void steQuantiles(const std::vector<uint64_t>& tests, const std::vector<uint64_t>& hits, StochasticStats& stats) {
  std::vector<double> perTri;
  for (size_t t = 0; t < tests.size(); ++t)
    if (tests[t] > 0) perTri.push_back(static_cast<double>(hits[t]) / static_cast<double>(tests[t]));
  if (perTri.empty()) return;
  std::sort(perTri.begin(), perTri.end());
  auto rank = [&](double q) {
    return perTri[std::min(perTri.size() - 1, static_cast<size_t>(q * static_cast<double>(perTri.size())))];
  };
  stats.steTriangleP10 = rank(0.1);
  stats.steTriangleMedian = rank(0.5);
  stats.steTriangleP90 = rank(0.9);
}

}  // namespace

StochasticStats StochasticRasterizer::render(const StochasticInput& in, const StochasticConfig& cfg,
                                             const StaticLayer& base, raster::Image<ResolvedPixel>& out,
                                             const StochasticDebug& debug, const PixelSink* sink) {
  const auto t0 = raster::Clock::now();
  const int width = out.width(), height = out.height();
  validate(in, cfg, base, width, height);
  const int spp = cfg.pattern.spp;
  const bool lens = in.lens.active();
  Pass ps{.in = in, .cfg = cfg, .base = base, .debug = debug, .sink = sink, .out = out,
          .source = {in.clip0, in.clip1, in.indices, in.motion}};
  ps.interval = cfg.method == BoundMethod::Interval;
  ps.strata = Strata(in.motion ? (cfg.timeStrata > 0 ? cfg.timeStrata : (lens ? 4 : 8)) : 1,
                     lens ? (cfg.lensStrata > 0 ? cfg.lensStrata : 3) : 1);
  ps.pattern = cfg.pattern;
  ps.pattern.motion = in.motion;
  ps.pattern.lens = lens;
  const SampleTarget target = makeSampleTarget(width, height, in.cull);
  // Sample k of a pixel has t in [k/S, (k+1)/S) unless a fixed sample replaces the pattern.
  ps.test = {.target = &target, .lens = in.lens, .motion = in.motion, .stratified = in.motion && !ps.pattern.fixed};

  StochasticStats stats;
  stats.spp = spp;
  const size_t triCount = in.indices.size() / 3;
  stats.triangles = triCount;
  stats.samples = static_cast<uint64_t>(width) * static_cast<uint64_t>(height) * static_cast<uint64_t>(spp);

  // Setup, then binning (serial: a few entries per moving triangle), submission order per tile.
  const SetupOptions so{.lens = in.lens, .width = width, .height = height, .staticShortcut = cfg.staticShortcut,
                        .exhaustive = cfg.exhaustive, .strata = ps.interval ? &ps.strata : nullptr};
  raster_.run([&] { setupTriangles(ps.source, so, ps.setup); });
  ps.grid = raster_.tileGrid(width, height);
  raster::binRects(
      ps.grid, static_cast<uint32_t>(triCount),
      [&](uint32_t t) { return ps.setup.tris[t].live ? ps.setup.tris[t].rect : raster::PixelRect{}; }, ps.bins);
  for (const TriangleBound& s : ps.setup.tris) {
    if (s.live) {
      stats.bounds += s.isStatic || !ps.interval ? 1 : static_cast<uint64_t>(ps.strata.count());
      stats.trianglesStatic += s.isStatic ? 1 : 0;
    } else {
      // Dropped: invalid index or non-finite; no sample: valid but the footprint holds no pixel centre.
      ++(s.valid ? stats.trianglesNoSample : stats.trianglesDropped);
    }
  }
  stats.msSetup = raster::msSince(t0);

  if (debug.sampleTriangle) debug.sampleTriangle->assign(stats.samples, kNoTriangle);
  if (debug.sampleDepth) debug.sampleDepth->assign(stats.samples, 1.0f);
  if (debug.testsPerPixel) debug.testsPerPixel->assign(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  std::vector<uint64_t> ownTests, ownHits;
  ps.triTests = debug.testsPerTriangle ? debug.testsPerTriangle : &ownTests;
  ps.triHits = debug.hitsPerTriangle ? debug.hitsPerTriangle : &ownHits;
  ps.triTests->assign(triCount, 0);
  ps.triHits->assign(triCount, 0);

  // Tile stage and resolve.
  const auto t1 = raster::Clock::now();
  std::vector<StochasticStats> tileStats(ps.grid.count());
  tbb::enumerable_thread_specific<TileSamples> scratch;
  raster_.run([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, ps.grid.count(), 1), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t tile = r.begin(); tile != r.end(); ++tile) {
        const raster::PixelRect tr = ps.grid.rect(tile);
        const std::span<const uint32_t> list = ps.bins.tile(tile);
        const bool busy = !list.empty();
        if (!busy && !debug.sampleTriangle && !debug.sampleDepth) {
          resolveEmptyTile(ps, tr);
          continue;
        }
        TileSamples& ts = scratch.local();
        initTile(ps, tr, busy, ts);
        testTriangles(ps, list, ts, tileStats[tile]);
        resolveTile(ps, ts, busy, tileStats[tile]);
      }
    });
  });
  for (const StochasticStats& s : tileStats) stats.addTile(s);
  steQuantiles(*ps.triTests, *ps.triHits, stats);
  stats.msRaster = raster::msSince(t1);
  stats.msTotal = raster::msSince(t0);
  return stats;
}

}  // namespace penumbra::stochastic
