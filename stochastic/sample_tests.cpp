#include "stochastic/sample_tests.h"

#include <algorithm>
#include <cmath>

namespace penumbra::stochastic {

namespace {

// The exact test of sample k of pixel p = (x, y), and the depth test.
inline void testSample(const TestedTriangle& tri, const TestContext& ctx, TileSamples& ts, size_t p, int x, int y,
                       int k, TestCounters& c, StochasticStats& st) {
  const size_t i = p * static_cast<size_t>(ts.spp) + static_cast<size_t>(k);
  const Sample& smp = ts.samples[i];
  glm::vec4 clip[3];
  for (int v = 0; v < 3; ++v) clip[v] = clipAt(tri.a[v], tri.b[v], smp.t, smp.u, smp.v, ctx.lens);
  ++c.tests;
  ++ts.tests[p];
  float z;
  if (!sampleCoverage(clip, *ctx.target, x, y, z)) return;
  ++c.hits;
  if (z < ts.depth[i]) {
    ts.depth[i] = z;
    ts.ref[i] = tri.index;
    ++st.depthPassed;
  }
}

}  // namespace

void testStatic(const TestedTriangle& tri, const TestContext& ctx, TileSamples& ts, TestCounters& c,
                StochasticStats& st) {
  const size_t spp = static_cast<size_t>(ts.spp);
  const raster::PixelRect& rr = tri.rect;
  for (int y = rr.y0; y <= rr.y1; ++y)
    for (int x = rr.x0; x <= rr.x1; ++x) {
      const size_t p = ts.pixel(x, y);
      ++c.tests;
      ++ts.tests[p];
      float z;
      if (!sampleCoverage(tri.a, *ctx.target, x, y, z)) continue;
      ++c.hits;
      st.staticShared += spp;
      for (size_t k = 0; k < spp; ++k) {
        float& dz = ts.depth[p * spp + k];
        if (z < dz) {
          dz = z;
          ts.ref[p * spp + k] = tri.index;
          ++st.depthPassed;
        }
      }
    }
}

void testBox(const TestedTriangle& tri, const TestContext& ctx, TileSamples& ts, TestCounters& c, StochasticStats& st) {
  const raster::PixelRect& rr = tri.rect;
  for (int y = rr.y0; y <= rr.y1; ++y)
    for (int x = rr.x0; x <= rr.x1; ++x) {
      const size_t p = ts.pixel(x, y);
      st.samplesScanned += static_cast<uint64_t>(ts.spp);
      for (int k = 0; k < ts.spp; ++k) testSample(tri, ctx, ts, p, x, y, k, c, st);
    }
}

void testInterval(const TestedTriangle& tri, const TestContext& ctx, const Strata& strata,
                  std::span<const raster::PixelRect> strataRects, TileSamples& ts, TestCounters& c, StochasticStats& st) {
  const int spp = ts.spp;
  for (int si = 0; si < strata.count(); ++si) {
    const raster::PixelRect sr = intersect(strataRects[static_cast<size_t>(si)], ts.rect);
    if (sr.empty()) continue;
    // Samples are sorted by time, one per 1/S of the shutter: the time stratum's index range.
    const int ti = strata.timeOf(si);
    const int k0 = ctx.stratified ? std::max(0, ti * spp / strata.time - 1) : 0;
    const int k1 = ctx.stratified ? std::min(spp - 1, ((ti + 1) * spp + strata.time - 1) / strata.time) : spp - 1;
    for (int y = sr.y0; y <= sr.y1; ++y)
      for (int x = sr.x0; x <= sr.x1; ++x) {
        const size_t p = ts.pixel(x, y);
        const uint16_t* stratumOf = ts.stratum.data() + p * static_cast<size_t>(spp);
        for (int k = k0; k <= k1; ++k) {
          ++st.samplesScanned;
          if (stratumOf[k] != si) continue;
          testSample(tri, ctx, ts, p, x, y, k, c, st);
        }
      }
  }
}

void testDual(const TestedTriangle& tri, const TestContext& ctx, int bs, int width, int height, TileSamples& ts,
              TestCounters& c, StochasticStats& st) {
  const int spp = ts.spp;
  const raster::PixelRect& rr = tri.rect;
  for (int by = rr.y0 & ~(bs - 1); by <= rr.y1; by += bs)
    for (int bx = rr.x0 & ~(bs - 1); bx <= rr.x1; bx += bs) {
      const raster::PixelRect br = intersect(rr, raster::PixelRect{bx, by, bx + bs - 1, by + bs - 1});
      if (br.empty()) continue;
      Domain d;
      if (!dualSpaceDomain(tri.a, tri.b, ctx.lens, ctx.motion, br, width, height, d)) {
        ++st.blocksCulled;
        continue;
      }
      int k0 = 0, k1 = spp - 1;
      if (ctx.stratified) {
        k0 = std::max(0, static_cast<int>(std::floor(d.t0 * static_cast<float>(spp))) - 1);
        k1 = std::min(spp - 1, static_cast<int>(std::floor(d.t1 * static_cast<float>(spp))) + 1);
      }
      for (int y = br.y0; y <= br.y1; ++y)
        for (int x = br.x0; x <= br.x1; ++x) {
          const size_t p = ts.pixel(x, y);
          for (int k = k0; k <= k1; ++k) {
            const Sample& smp = ts.samples[p * static_cast<size_t>(spp) + static_cast<size_t>(k)];
            ++st.samplesScanned;
            if (smp.t < d.t0 || smp.t > d.t1 || smp.u < d.u0 || smp.u > d.u1 || smp.v < d.v0 || smp.v > d.v1) continue;
            testSample(tri, ctx, ts, p, x, y, k, c, st);
          }
        }
    }
}

}  // namespace penumbra::stochastic
