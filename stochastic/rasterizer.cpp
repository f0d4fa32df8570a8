#include "stochastic/rasterizer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

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

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr int kTileLog2 = 6;
constexpr int kTile = 1 << kTileLog2;
constexpr uint32_t kStaticRef = 0xFFFFFFFEu;

struct TriSetup {
  PixelRect rect;
  bool isStatic = false;
  bool live = false;
};

struct TileScratch {
  std::vector<Sample> samples;
  std::vector<uint16_t> stratum;  // interval method: each sample's stratum, (t * L + u) * L + v
  std::vector<float> depth;
  std::vector<uint32_t> ref;
  std::vector<uint32_t> tests;
};

void counters(StochasticStats& into, const StochasticStats& s) {
  into.blocksCulled += s.blocksCulled;
  into.samplesScanned += s.samplesScanned;
  into.tests += s.tests;
  into.hits += s.hits;
  into.staticShared += s.staticShared;
  into.depthPassed += s.depthPassed;
  into.pixelsMerged += s.pixelsMerged;
}

}  // namespace

StochasticStats StochasticRasterizer::render(const StochasticInput& in, const StochasticConfig& cfg,
                                             const StaticLayer& base, raster::Image<ResolvedPixel>& out,
                                             const StochasticDebug& debug, const PixelSink* sink) {
  const auto t0 = Clock::now();
  const int width = out.width(), height = out.height();
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
    if (!(f.t >= 0.0f && f.t < 1.0f) || !(f.u * f.u + f.v * f.v <= 1.0f))
      throw std::invalid_argument("stochastic: a fixed sample needs t in [0, 1) and (u, v) in the unit disk");
  }
  const bool lens = in.lens.active();
  const bool motion = in.motion;
  const int timeStrata = motion ? (cfg.timeStrata > 0 ? cfg.timeStrata : (lens ? 4 : 8)) : 1;
  const int lensStrata = lens ? (cfg.lensStrata > 0 ? cfg.lensStrata : 3) : 1;
  if (cfg.dualBlock < 1 || cfg.dualBlock > 64 || (cfg.dualBlock & (cfg.dualBlock - 1)) != 0)
    throw std::invalid_argument("stochastic: the dual-space block side must be a power of two in [1, 64]");
  if (timeStrata > 64 || lensStrata > 8 || cfg.timeStrata < 0 || cfg.lensStrata < 0)
    throw std::invalid_argument("stochastic: interval strata must be in [1, 64] (time) and [1, 8] (lens)");
  const int strata = cfg.method == BoundMethod::Interval ? timeStrata * lensStrata * lensStrata : 1;
  // Interval strata boundaries: the footprints' domains and the samples' membership use the same
  // floats (a sample at a boundary belongs to exactly one stratum, whose domain holds it).
  float tEdge[65], lEdge[9];
  for (int i = 0; i <= timeStrata; ++i) tEdge[i] = static_cast<float>(i) / static_cast<float>(timeStrata);
  for (int i = 0; i <= lensStrata; ++i)
    lEdge[i] = -1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(lensStrata);
  auto cell = [](const float* edge, int n, float v) {  // the cell [edge[c], edge[c + 1]) holding v
    int c = 0;
    while (c + 1 < n && v >= edge[c + 1]) ++c;
    return c;
  };
  SamplePattern pattern = cfg.pattern;
  pattern.motion = motion;
  pattern.lens = lens;
  // Sample k of a pixel has t in [k/S, (k+1)/S) unless a fixed sample replaces the pattern.
  const bool stratified = motion && !pattern.fixed;

  const size_t triCount = in.indices.size() / 3;
  const uint32_t vertexCount = static_cast<uint32_t>(in.clip0.size());
  StochasticStats stats;
  stats.spp = spp;
  stats.triangles = triCount;
  stats.samples = static_cast<uint64_t>(width) * static_cast<uint64_t>(height) * static_cast<uint64_t>(spp);
  const SampleTarget target = makeSampleTarget(width, height, in.cull);

  auto fetch = [&](size_t tri, glm::vec4 a[3], glm::vec4 b[3]) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = in.indices[tri * 3 + static_cast<size_t>(k)];
      a[k] = in.clip0[i];
      b[k] = motion ? in.clip1[i] : in.clip0[i];
    }
  };

  // Setup: bounds per triangle (and per stratum).
  std::vector<TriSetup> setup(triCount);
  std::vector<PixelRect> strataRects(cfg.method == BoundMethod::Interval ? triCount * static_cast<size_t>(strata) : 0);
  raster_.run([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, triCount, 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t tri = r.begin(); tri != r.end(); ++tri) {
        TriSetup& s = setup[tri];
        bool valid = true;
        for (int k = 0; k < 3; ++k) valid &= in.indices[tri * 3 + static_cast<size_t>(k)] < vertexCount;
        if (!valid) continue;
        glm::vec4 a[3], b[3];
        fetch(tri, a, b);
        for (int k = 0; k < 3; ++k)
          for (int c = 0; c < 4; ++c) valid &= std::isfinite(a[k][c]) && std::isfinite(b[k][c]);
        if (!valid) continue;
        s.isStatic = cfg.staticShortcut && !lens && (!motion || (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]));
        s.rect = cfg.exhaustive ? PixelRect{0, 0, width - 1, height - 1}
                                : footprint(a, b, Domain{}, in.lens, motion && !s.isStatic, width, height);
        s.live = !s.rect.empty();
        if (s.live && cfg.method == BoundMethod::Interval && !s.isStatic) {
          for (int ti = 0; ti < timeStrata; ++ti)
            for (int ui = 0; ui < lensStrata; ++ui)
              for (int vi = 0; vi < lensStrata; ++vi) {
                // The first and last cells reach to the domain's ends (every sample is inside).
                Domain d;
                d.t0 = tEdge[ti], d.t1 = tEdge[ti + 1];
                d.u0 = lEdge[ui], d.u1 = lEdge[ui + 1];
                d.v0 = lEdge[vi], d.v1 = lEdge[vi + 1];
                strataRects[tri * static_cast<size_t>(strata) +
                            static_cast<size_t>((ti * lensStrata + ui) * lensStrata + vi)] =
                    footprint(a, b, d, in.lens, motion, width, height);
              }
        }
      }
    });
  });
  // Binning (serial: a few entries per moving triangle), submission order per tile.
  const int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
  const size_t numTiles = static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY);
  std::vector<uint64_t> offsets(numTiles + 1, 0);
  for (size_t tri = 0; tri < triCount; ++tri) {
    const TriSetup& s = setup[tri];
    if (!s.live) continue;
    stats.bounds += s.isStatic ? 1 : static_cast<uint64_t>(strata);
    stats.trianglesStatic += s.isStatic ? 1 : 0;
    for (int ty = s.rect.y0 >> kTileLog2; ty <= s.rect.y1 >> kTileLog2; ++ty)
      for (int tx = s.rect.x0 >> kTileLog2; tx <= s.rect.x1 >> kTileLog2; ++tx)
        ++offsets[static_cast<size_t>(ty * tilesX + tx) + 1];
  }
  for (size_t t = 0; t < numTiles; ++t) offsets[t + 1] += offsets[t];
  std::vector<uint32_t> entries(offsets[numTiles]);
  {
    std::vector<uint64_t> cursor(offsets.begin(), offsets.end() - 1);
    for (size_t tri = 0; tri < triCount; ++tri) {
      const TriSetup& s = setup[tri];
      if (!s.live) continue;
      for (int ty = s.rect.y0 >> kTileLog2; ty <= s.rect.y1 >> kTileLog2; ++ty)
        for (int tx = s.rect.x0 >> kTileLog2; tx <= s.rect.x1 >> kTileLog2; ++tx)
          entries[cursor[static_cast<size_t>(ty * tilesX + tx)]++] = static_cast<uint32_t>(tri);
    }
  }
  // Dropped: invalid index or non-finite; no sample: valid but the footprint holds no pixel centre.
  for (size_t tri = 0; tri < triCount; ++tri) {
    if (setup[tri].live) continue;
    bool valid = true;
    for (int k = 0; k < 3; ++k) valid &= in.indices[tri * 3 + static_cast<size_t>(k)] < vertexCount;
    if (valid) {
      glm::vec4 a[3], b[3];
      fetch(tri, a, b);
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 4; ++c) valid &= std::isfinite(a[k][c]) && std::isfinite(b[k][c]);
    }
    ++(valid ? stats.trianglesNoSample : stats.trianglesDropped);
  }
  stats.msSetup = msSince(t0);

  if (debug.sampleTriangle) debug.sampleTriangle->assign(stats.samples, kNoTriangle);
  if (debug.sampleDepth) debug.sampleDepth->assign(stats.samples, 1.0f);
  if (debug.testsPerPixel) debug.testsPerPixel->assign(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  // Per-triangle counts (integers added atomically: the totals do not depend on the schedule).
  std::vector<uint64_t> ownTests, ownHits;
  std::vector<uint64_t>& triTestsOut = debug.testsPerTriangle ? *debug.testsPerTriangle : ownTests;
  std::vector<uint64_t>& triHitsOut = debug.hitsPerTriangle ? *debug.hitsPerTriangle : ownHits;
  triTestsOut.assign(triCount, 0);
  triHitsOut.assign(triCount, 0);

  // Tile stage.
  const auto t1 = Clock::now();
  std::vector<StochasticStats> tileStats(numTiles);
  tbb::enumerable_thread_specific<TileScratch> scratch;
  raster_.run([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, numTiles, 1), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t tile = range.begin(); tile != range.end(); ++tile) {
        StochasticStats& st = tileStats[tile];
        TileScratch& sc = scratch.local();
        const int tx = static_cast<int>(tile % static_cast<size_t>(tilesX)), ty = static_cast<int>(tile / static_cast<size_t>(tilesX));
        const PixelRect tr{tx * kTile, ty * kTile, std::min(width, (tx + 1) * kTile) - 1,
                           std::min(height, (ty + 1) * kTile) - 1};
        const int tw = tr.x1 - tr.x0 + 1, th = tr.y1 - tr.y0 + 1;
        const size_t pixels = static_cast<size_t>(tw) * static_cast<size_t>(th);
        const size_t sppz = static_cast<size_t>(spp);
        const uint32_t* first = entries.data() + offsets[tile];
        const uint32_t* last = entries.data() + offsets[tile + 1];
        const bool busy = first != last;
        if (!busy && !debug.sampleTriangle && !debug.sampleDepth) {
          // No triangle reached the tile: every sample is the static layer's or background, as
          // the resolve below would find (same pixels, without touching the samples).
          uint32_t staticRefs[kMaxSpp], noRefs[kMaxSpp];
          std::fill_n(staticRefs, spp, kStaticRef);
          std::fill_n(noRefs, spp, kNoTriangle);
          for (int y = tr.y0; y <= tr.y1; ++y)
            for (int x = tr.x0; x <= tr.x1; ++x) {
              const bool covered = base.covered && base.covered->at(x, y);
              ResolvedPixel& o = out.at(x, y);
              o = ResolvedPixel{};
              if (covered) {
                o.layers = 1;
                o.layer[0].surface = kStaticSurface;
                o.layer[0].count = static_cast<uint16_t>(spp);
                o.layer[0].sample = static_cast<uint16_t>((spp - 1) / 2);
                o.layer[0].triangle = kNoTriangle;
              } else {
                o.background = static_cast<uint16_t>(spp);
              }
              if (sink) (*sink)(x, y, o, covered ? staticRefs : noRefs, nullptr);
              if (debug.testsPerPixel)
                (*debug.testsPerPixel)[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 0;
            }
          continue;
        }
        sc.depth.resize(pixels * sppz);
        sc.ref.resize(pixels * sppz);
        sc.tests.assign(pixels, 0);
        if (busy) sc.samples.resize(pixels * sppz);
        if (busy && cfg.method == BoundMethod::Interval && !cfg.exhaustive) sc.stratum.resize(pixels * sppz);
        for (int y = tr.y0; y <= tr.y1; ++y)
          for (int x = tr.x0; x <= tr.x1; ++x) {
            const size_t p = static_cast<size_t>(y - tr.y0) * static_cast<size_t>(tw) + static_cast<size_t>(x - tr.x0);
            const float z = base.depth ? base.depth->at(x, y) : 1.0f;
            const uint32_t r = (base.covered && base.covered->at(x, y)) ? kStaticRef : kNoTriangle;
            std::fill_n(sc.depth.data() + p * sppz, sppz, z);
            std::fill_n(sc.ref.data() + p * sppz, sppz, r);
            if (busy) {
              Sample* smp = sc.samples.data() + p * sppz;
              pixelSamples(pattern, x, y, smp);
              if (cfg.method == BoundMethod::Interval && !cfg.exhaustive)
                for (size_t k = 0; k < sppz; ++k)
                  sc.stratum[p * sppz + k] = static_cast<uint16_t>(
                      (cell(tEdge, timeStrata, smp[k].t) * lensStrata + cell(lEdge, lensStrata, smp[k].u)) * lensStrata +
                      cell(lEdge, lensStrata, smp[k].v));
            }
          }

        for (const uint32_t* e = first; e != last; ++e) {
          const uint32_t tri = *e;
          const TriSetup& s = setup[tri];
          glm::vec4 a[3], b[3];
          fetch(tri, a, b);
          uint64_t triTests = 0, triHits = 0;
          auto pixelIndex = [&](int x, int y) {
            return static_cast<size_t>(y - tr.y0) * static_cast<size_t>(tw) + static_cast<size_t>(x - tr.x0);
          };
          auto test = [&](size_t p, int x, int y, int k) {
            const Sample& smp = sc.samples[p * sppz + static_cast<size_t>(k)];
            glm::vec4 c[3];
            for (int i = 0; i < 3; ++i) c[i] = clipAt(a[i], b[i], smp.t, smp.u, smp.v, in.lens);
            ++triTests;
            ++sc.tests[p];
            float z;
            if (!sampleCoverage(c, target, x, y, z)) return;
            ++triHits;
            float& dz = sc.depth[p * sppz + static_cast<size_t>(k)];
            if (z < dz) {
              dz = z;
              sc.ref[p * sppz + static_cast<size_t>(k)] = tri;
              ++st.depthPassed;
            }
          };
          const PixelRect rr = intersect(s.rect, tr);
          if (s.isStatic) {
            // The ordinary path: one test at the pixel centre decides every sample of the pixel.
            for (int y = rr.y0; y <= rr.y1; ++y)
              for (int x = rr.x0; x <= rr.x1; ++x) {
                const size_t p = pixelIndex(x, y);
                ++triTests;
                ++sc.tests[p];
                float z;
                if (!sampleCoverage(a, target, x, y, z)) continue;
                ++triHits;
                st.staticShared += sppz;
                for (size_t k = 0; k < sppz; ++k) {
                  float& dz = sc.depth[p * sppz + k];
                  if (z < dz) {
                    dz = z;
                    sc.ref[p * sppz + k] = tri;
                    ++st.depthPassed;
                  }
                }
              }
          } else if (cfg.method == BoundMethod::Box || cfg.exhaustive) {
            for (int y = rr.y0; y <= rr.y1; ++y)
              for (int x = rr.x0; x <= rr.x1; ++x) {
                const size_t p = pixelIndex(x, y);
                st.samplesScanned += sppz;
                for (int k = 0; k < spp; ++k) test(p, x, y, k);
              }
          } else if (cfg.method == BoundMethod::Interval) {
            for (int si = 0; si < strata; ++si) {
              const PixelRect sr = intersect(strataRects[tri * static_cast<size_t>(strata) + static_cast<size_t>(si)], tr);
              if (sr.empty()) continue;
              const int ti = si / (lensStrata * lensStrata);  // the time stratum: an index range of the samples
              // Samples are sorted by time, one per 1/S of the shutter: the stratum's index range.
              const int k0 = stratified ? std::max(0, ti * spp / timeStrata - 1) : 0;
              const int k1 = stratified ? std::min(spp - 1, ((ti + 1) * spp + timeStrata - 1) / timeStrata) : spp - 1;
              for (int y = sr.y0; y <= sr.y1; ++y)
                for (int x = sr.x0; x <= sr.x1; ++x) {
                  const size_t p = pixelIndex(x, y);
                  const uint16_t* stratumOf = sc.stratum.data() + p * sppz;
                  for (int k = k0; k <= k1; ++k) {
                    ++st.samplesScanned;
                    if (stratumOf[k] != si) continue;
                    test(p, x, y, k);
                  }
                }
            }
          } else {  // dual space, per 8x8 block
            const int bs = cfg.dualBlock;
            for (int by = rr.y0 & ~(bs - 1); by <= rr.y1; by += bs)
              for (int bx = rr.x0 & ~(bs - 1); bx <= rr.x1; bx += bs) {
                const PixelRect br = intersect(rr, PixelRect{bx, by, bx + bs - 1, by + bs - 1});
                if (br.empty()) continue;
                Domain d;
                if (!dualSpaceDomain(a, b, in.lens, motion, br, width, height, d)) {
                  ++st.blocksCulled;
                  continue;
                }
                int k0 = 0, k1 = spp - 1;
                if (stratified) {
                  k0 = std::max(0, static_cast<int>(std::floor(d.t0 * static_cast<float>(spp))) - 1);
                  k1 = std::min(spp - 1, static_cast<int>(std::floor(d.t1 * static_cast<float>(spp))) + 1);
                }
                for (int y = br.y0; y <= br.y1; ++y)
                  for (int x = br.x0; x <= br.x1; ++x) {
                    const size_t p = pixelIndex(x, y);
                    for (int k = k0; k <= k1; ++k) {
                      const Sample& smp = sc.samples[p * sppz + static_cast<size_t>(k)];
                      ++st.samplesScanned;
                      if (smp.t < d.t0 || smp.t > d.t1 || smp.u < d.u0 || smp.u > d.u1 || smp.v < d.v0 || smp.v > d.v1)
                        continue;
                      test(p, x, y, k);
                    }
                  }
              }
          }
          st.tests += triTests;
          st.hits += triHits;
          if (triTests) std::atomic_ref<uint64_t>(triTestsOut[tri]).fetch_add(triTests);
          if (triHits) std::atomic_ref<uint64_t>(triHitsOut[tri]).fetch_add(triHits);
        }

        // Resolve: group each pixel's samples by surface.
        for (int y = tr.y0; y <= tr.y1; ++y)
          for (int x = tr.x0; x <= tr.x1; ++x) {
            const size_t p = static_cast<size_t>(y - tr.y0) * static_cast<size_t>(tw) + static_cast<size_t>(x - tr.x0);
            const uint32_t* ref = sc.ref.data() + p * sppz;
            ResolvedPixel& o = out.at(x, y);
            o = ResolvedPixel{};
            uint32_t surf[kMaxSpp];
            uint16_t count[kMaxSpp];
            int n = 0;
            for (int k = 0; k < spp; ++k) {
              if (ref[k] == kNoTriangle) {
                ++o.background;
                continue;
              }
              const uint32_t sid = ref[k] == kStaticRef ? kStaticSurface : in.surface[ref[k]];
              int j = 0;
              while (j < n && surf[j] != sid) ++j;
              if (j == n) {
                surf[n] = sid;
                count[n++] = 0;
              }
              ++count[j];
            }
            int order[kMaxSpp];
            for (int j = 0; j < n; ++j) order[j] = j;
            std::sort(order, order + n, [&](int a2, int b2) {
              return count[a2] != count[b2] ? count[a2] > count[b2] : surf[a2] < surf[b2];
            });
            o.layers = static_cast<uint8_t>(std::min(n, kMaxLayers));
            for (int l = 0; l < o.layers; ++l) {
              ResolvedLayer& L = o.layer[l];
              const int j = order[l];
              L.surface = surf[j];
              L.count = count[j];
              // The median sample in time of this surface.
              int want = (count[j] - 1) / 2;
              for (int k = 0; k < spp; ++k) {
                const uint32_t sid = ref[k] == kNoTriangle ? kNoTriangle
                                     : ref[k] == kStaticRef ? kStaticSurface
                                                            : in.surface[ref[k]];
                if (sid != surf[j] || want-- > 0) continue;
                L.sample = static_cast<uint16_t>(k);
                L.triangle = ref[k] == kStaticRef ? kNoTriangle : ref[k];
                L.at = busy ? sc.samples[p * sppz + static_cast<size_t>(k)] : Sample{};
                break;
              }
            }
            if (n > kMaxLayers) {
              ++st.pixelsMerged;
              for (int l = kMaxLayers; l < n; ++l) o.layer[0].count = static_cast<uint16_t>(o.layer[0].count + count[order[l]]);
            }
            if (sink) (*sink)(x, y, o, ref, busy ? sc.samples.data() + p * sppz : nullptr);
            const size_t g = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x));
            if (debug.testsPerPixel) (*debug.testsPerPixel)[g] = sc.tests[p];
            if (debug.sampleTriangle || debug.sampleDepth)
              for (int k = 0; k < spp; ++k) {
                if (debug.sampleTriangle) (*debug.sampleTriangle)[g * sppz + static_cast<size_t>(k)] = ref[k];
                if (debug.sampleDepth) (*debug.sampleDepth)[g * sppz + static_cast<size_t>(k)] = sc.depth[p * sppz + static_cast<size_t>(k)];
              }
          }
      }
    });
  });
  for (const StochasticStats& s : tileStats) counters(stats, s);
  std::vector<double> perTri;
  for (size_t t = 0; t < triCount; ++t)
    if (triTestsOut[t] > 0) perTri.push_back(static_cast<double>(triHitsOut[t]) / static_cast<double>(triTestsOut[t]));
  if (!perTri.empty()) {
    std::sort(perTri.begin(), perTri.end());
    auto rank = [&](double q) { return perTri[std::min(perTri.size() - 1, static_cast<size_t>(q * static_cast<double>(perTri.size())))]; };
    stats.steTriangleP10 = rank(0.1);
    stats.steTriangleMedian = rank(0.5);
    stats.steTriangleP90 = rank(0.9);
  }
  stats.msRaster = msSince(t1);
  stats.msTotal = msSince(t0);
  return stats;
}

}  // namespace penumbra::stochastic
