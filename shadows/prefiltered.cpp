#include "shadows/prefiltered.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

namespace penumbra::shadows {

float PrefilterMap::zAt(double x, double y) const {
  const int w = z.width(), h = z.height();
  const int ix = !(x >= 0.0) ? 0 : x >= w - 1 ? w - 1 : static_cast<int>(x);
  const int iy = !(y >= 0.0) ? 0 : y >= h - 1 ? h - 1 : static_cast<int>(y);
  return z.at(ix, iy);
}

void preparePrefilterMap(ShadowContext& ctx, const ParamSet& params, PrefilterMap& m, PrefilterNeeds needs) {
  const auto t0 = Clock::now();
  const int size = params.integer("map_size");
  m.map.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
  m.map.warp = MomentWarp{.kind = MomentKind::Vsm, .cPos = 0.0f, .cNeg = 0.0f};
  if (needs.moments)
    renderMomentMap(ctx, m.map);
  else
    renderNormalizedDepth(ctx, m.map, m.z);
  ctx.times.msMaps += msSince(t0);
  const auto t1 = Clock::now();
  const LightView& v = m.map.view;
  m.tpx = static_cast<double>(v.width) / static_cast<double>(v.tanHi.x - v.tanLo.x);
  m.tpy = static_cast<double>(v.height) / static_cast<double>(v.tanHi.y - v.tanLo.y);
  if (needs.moments) m.z.resize(v.width, v.height);
  std::vector<float> rowMin(static_cast<size_t>(v.height), INFINITY),
      rowMax(static_cast<size_t>(v.height), -INFINITY);
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, v.height, 16), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y) {
        float lo = INFINITY, hi = -INFINITY;
        for (int x = 0; x < v.width; ++x) {
          const float z = needs.moments ? m.map.texels.at(x, y).r : m.z.at(x, y);
          if (needs.moments) m.z.at(x, y) = z;
          lo = std::min(lo, z);
          if (z < 1.0f) hi = std::max(hi, z);
        }
        rowMin[static_cast<size_t>(y)] = lo, rowMax[static_cast<size_t>(y)] = hi;
      }
    });
    if (needs.pyramid) m.pyramid = raster::buildMinMaxPyramid(m.z);
  });
  m.zMin = INFINITY;
  for (float z : rowMin) m.zMin = std::min(m.zMin, z);
  m.zMax = m.zMin;
  for (float z : rowMax) m.zMax = std::max(m.zMax, z);
  ctx.times.msFilter += msSince(t1);
}

ReceiverKernel receiverKernel(const PrefilterMap& m, const ShadowContext& ctx, const Receiver& r,
                              BiasParams b, bool usePlane) {
  const LightView& view = m.map.view;
  const glm::vec3 v = lookupPoint(view, r, b);
  const float znear = view.znear;
  const glm::vec2 halfLight(0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height);
  const glm::vec2 searchTan = halfLight * std::max(1.0f / znear - 1.0f / v.z, 0.0f);
  const glm::vec2 c = view.toMap(v);
  const auto zr = static_cast<double>(receiverDepth(m.map, v, r.normal, b));
  ReceiverKernel k{.cx = static_cast<double>(c.x),
                   .cy = static_cast<double>(c.y),
                   .zr = zr,
                   .biasZ = std::max(static_cast<double>(m.map.normalizedDepth(v.z)) - zr, 0.0),
                   .dr = static_cast<double>(v.z),
                   .sx = static_cast<double>(searchTan.x) * m.tpx,
                   .sy = static_cast<double>(searchTan.y) * m.tpy,
                   .plane = ReceiverPlane(view, v, r.normal, b),
                   .usePlane = usePlane};
  // Texel (x, y) is at tangents (tanLo.x + x / tpx, tanHi.y - y / tpy).
  const TapPlane p = k.plane.tapPlane();
  const auto d = [](float f) { return static_cast<double>(f); };
  k.lx = d(p.a) / m.tpx;
  k.ly = -d(p.b) / m.tpy;
  k.l0 = d(p.a) * d(view.tanLo.x) + d(p.b) * d(view.tanHi.y) + d(p.c);
  k.lo = d(p.lo), k.hi = d(p.hi), k.scale = d(p.scale);
  k.znear = d(view.znear);
  k.zNear = d(m.map.zNear);
  k.invRange = 1.0 / (d(m.map.zFar) - d(m.map.zNear));
  return k;
}

glm::dvec2 penumbraHalf(const PrefilterMap& m, const ShadowContext& ctx, const ReceiverKernel& k, double zb,
                        double minHalf) {
  const double db = std::max(m.viewDepth(zb), static_cast<double>(m.map.view.znear));
  const double f = std::max(1.0 / db - 1.0 / k.dr, 0.0);
  // Never wider than the search box (the blocker cannot be nearer than the near plane).
  const double hx = std::min(0.5 * static_cast<double>(ctx.in.light.width) * f * m.tpx, k.sx);
  const double hy = std::min(0.5 * static_cast<double>(ctx.in.light.height) * f * m.tpy, k.sy);
  return {std::max(hx, minHalf), std::max(hy, minHalf)};
}

bool shrinkSearchBox(const PrefilterMap& m, const ShadowContext& ctx, ReceiverKernel& k) {
  constexpr int kSteps = 4;
  bool shrunk = false;
  // Texel indices of a box edge, kept in int range (the query clamps to the map).
  const auto texel = [](double t) { return static_cast<int>(std::clamp(t, -0x1p30, 0x1p30)); };
  for (int i = 0; i < kSteps; ++i) {
    float mn = 0, mx = 0;
    raster::queryMinMax(m.pyramid, texel(std::floor(k.cx - k.sx)), texel(std::floor(k.cy - k.sy)),
                        texel(std::ceil(k.cx + k.sx)), texel(std::ceil(k.cy + k.sy)), mn, mx);
    if (!(mn >= 0.0f)) return shrunk;  // an empty query (a box off the map) or NaN: keep the box
    const glm::dvec2 s = penumbraHalf(m, ctx, k, static_cast<double>(mn));
    const double sx = std::min(s.x, k.sx), sy = std::min(s.y, k.sy);
    const bool smaller = sx < 0.9 * k.sx || sy < 0.9 * k.sy;
    shrunk |= sx < k.sx || sy < k.sy;
    k.sx = sx, k.sy = sy;
    if (!smaller) break;
  }
  return shrunk;
}

std::vector<uint8_t> tilesReached(ShadowContext& ctx, const PrefilterMap& m, BiasParams b, int tile,
                                  int tilesX, int tilesY, bool hsm) {
  std::vector<uint8_t> reached(static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY), 0);
  const ReceiverImage& rec = *ctx.in.receivers;
  const glm::vec3 n = ctx.in.light.normal(), c = ctx.in.light.center;
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, rec.height(), 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < rec.width(); ++x) {
          const Receiver& r = rec.at(x, y);
          if (!r.valid || !(glm::dot(r.position - c, n) > 0.0f)) continue;
          ReceiverKernel k = receiverKernel(m, ctx, r, b, false);
          if (hsm) shrinkSearchBox(m, ctx, k);
          // One texel of margin for the PCF taps and the half-texel minimum kernel.
          const auto clampTile = [&](double t, int count) {
            return static_cast<int>(std::clamp(std::floor(t / tile), 0.0, static_cast<double>(count - 1)));
          };
          const int tx0 = clampTile(k.cx - k.sx - 1.0, tilesX), tx1 = clampTile(k.cx + k.sx + 1.0, tilesX);
          const int ty0 = clampTile(k.cy - k.sy - 1.0, tilesY), ty1 = clampTile(k.cy + k.sy + 1.0, tilesY);
          for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx) {
              uint8_t& flag =
                  reached[static_cast<size_t>(ty) * static_cast<size_t>(tilesX) + static_cast<size_t>(tx)];
              // Plain stores of the same value from several threads would race in the C++
              // model: an atomic_ref store is well-defined and the result order-independent.
              if (!std::atomic_ref<uint8_t>(flag).load(std::memory_order_relaxed))
                std::atomic_ref<uint8_t>(flag).store(1, std::memory_order_relaxed);
            }
        }
    });
  });
  return reached;
}

std::vector<ParamSpec> prefilterParams(int defaultSubdivision) {
  std::vector<ParamSpec> p = depthMapParams(1024, 0.5, 0.5);
  p.push_back(
      {.name = "receiver_plane",
       .kind = ParamKind::Choice,
       .defaultValue = 0,
       .minValue = 0,
       .maxValue = 1,
       .choices = {"on", "off"},
       .help = "compare each sub-kernel with the receiver's tangent plane at its centre (off: one depth)"});
  p.push_back({.name = "subdivision",
               .kind = ParamKind::Int,
               .defaultValue = static_cast<double>(defaultSubdivision),
               .minValue = 1,
               .maxValue = 8,
               .choices = {},
               .help = "kernels split into n x n sub-kernels (1: none)"});
  return p;
}

ParamSpec searchParam(int defaultIndex) {
  return choiceParam("search", defaultIndex, {"hsm", "near"},
                     "blocker search box: the light's frustum from the receiver cut at the nearest depth the "
                     "min/max pyramid finds in it (HSM, refined up to 4 times), or at the near plane");
}

std::string tileNote(size_t built, size_t total) {
  char buf[96];
  std::snprintf(buf, sizeof buf,
                "%zu of %zu tiles built (%.0f%%), %zu skipped: no receiver's kernel reaches them", built,
                total, total ? 100.0 * static_cast<double>(built) / static_cast<double>(total) : 0.0,
                total - built);
  return buf;
}

}  // namespace penumbra::shadows
