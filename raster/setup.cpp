#include "raster/setup.h"

#include <algorithm>
#include <cmath>

namespace penumbra::raster {

ScreenVert projectVertex(float x, float y, float z, float w, const Viewport& vp) {
  ScreenVert s;
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(w)) {
    s.flags = kNonFinite;
    return s;
  }
  uint32_t f = 0;
  if (x < -w) f |= kOutLeft;
  if (x > w) f |= kOutRight;
  if (y < -w) f |= kOutBottom;
  if (y > w) f |= kOutTop;
  if (z < 0.0f) f |= kOutNear;
  if (z > w) f |= kOutFar;
  if (!(w > 0.0f)) {
    s.flags = f | kOutGuard;
    return s;
  }
  // Screen position in double: 8 fractional bits of a 2^15 range need more than float's 24 bits.
  const double wd = static_cast<double>(w);
  const double sx = (static_cast<double>(x) / wd * 0.5 + 0.5) * vp.width;
  const double sy = (0.5 - static_cast<double>(y) / wd * 0.5) * vp.height;
  if (!(std::abs(sx) <= kGuardBandPixels && std::abs(sy) <= kGuardBandPixels)) {
    s.flags = f | kOutGuard;
    return s;
  }
  s.x = static_cast<int32_t>(std::nearbyint(sx * kSubpixelOne - kSubpixelOne / 2));
  s.y = static_cast<int32_t>(std::nearbyint(sy * kSubpixelOne - kSubpixelOne / 2));
  s.z = static_cast<float>(static_cast<double>(z) / wd);
  s.iw = static_cast<float>(1.0 / wd);
  s.flags = f;
  return s;
}

namespace {

// ceil(a / 256) and floor(a / 256) for signed a.
inline int32_t floorDiv(int64_t a) { return static_cast<int32_t>(a >> kSubpixelBits); }
inline int32_t ceilDiv(int64_t a) { return static_cast<int32_t>(-((-a) >> kSubpixelBits)); }

}  // namespace

SetupResult setupTriangle(const ScreenVert& v0, const ScreenVert& v1, const ScreenVert& v2, CullMode cull,
                          const Viewport& vp, SetupTri& t, SetupAttr* attr, int order[3]) {
  const ScreenVert* v[3] = {&v0, &v1, &v2};
  // Doubled signed area in y-down fixed point: (v1 - v0) x (v2 - v0).
  const int64_t area = (int64_t{v1.x} - v0.x) * (int64_t{v2.y} - v0.y) - (int64_t{v1.y} - v0.y) * (int64_t{v2.x} - v0.x);
  if (area == 0) return SetupResult::Degenerate;
  // Counter-clockwise in NDC (y up) is clockwise with y down: negative area here.
  const bool front = area < 0;
  if ((cull == CullMode::Back && !front) || (cull == CullMode::Front && front)) return SetupResult::CulledFacing;
  int o[3] = {0, 1, 2};
  if (area < 0) std::swap(o[1], o[2]);
  const ScreenVert* p[3] = {v[o[0]], v[o[1]], v[o[2]]};

  int64_t minx = std::min({p[0]->x, p[1]->x, p[2]->x}), maxx = std::max({p[0]->x, p[1]->x, p[2]->x});
  int64_t miny = std::min({p[0]->y, p[1]->y, p[2]->y}), maxy = std::max({p[0]->y, p[1]->y, p[2]->y});
  // Pixel i is sampled at 256 i: candidates are ceil(min/256) .. floor(max/256), clamped.
  t.minX = std::max(ceilDiv(minx), 0);
  t.maxX = std::min(floorDiv(maxx), vp.width - 1);
  t.minY = std::max(ceilDiv(miny), 0);
  t.maxY = std::min(floorDiv(maxy), vp.height - 1);
  if (t.minX > t.maxX || t.minY > t.maxY) return SetupResult::NoSample;

  for (int k = 0; k < 3; ++k) {
    t.vx[k] = p[k]->x;
    t.vy[k] = p[k]->y;
  }

  // Planes. Barycentric l_k (of ordered vertex k) is E_{k+1}(p) / area, the edge opposite to k,
  // without bias. Per pixel step of E in x is 256 A, in y 256 B (E in fixed^2 units).
  const double inv = 1.0 / static_cast<double>(area < 0 ? -area : area);
  double l0[3], lx[3], ly[3];  // l_k at (minX, minY) and its steps
  for (int k = 0; k < 3; ++k) {
    const int e = (k + 1) % 3, n = (e + 1) % 3;
    const int64_t ea = -(int64_t{t.vy[n]} - t.vy[e]), eb = int64_t{t.vx[n]} - t.vx[e];
    const int64_t eo = ea * (int64_t{t.minX} * kSubpixelOne - t.vx[e]) + eb * (int64_t{t.minY} * kSubpixelOne - t.vy[e]);
    l0[k] = static_cast<double>(eo) * inv;
    lx[k] = static_cast<double>(ea * kSubpixelOne) * inv;
    ly[k] = static_cast<double>(eb * kSubpixelOne) * inv;
  }
  auto plane = [&](const double s[3], float& c, float& cx, float& cy) {
    c = static_cast<float>(s[0] * l0[0] + s[1] * l0[1] + s[2] * l0[2]);
    cx = static_cast<float>(s[0] * lx[0] + s[1] * lx[1] + s[2] * lx[2]);
    cy = static_cast<float>(s[0] * ly[0] + s[1] * ly[1] + s[2] * ly[2]);
  };
  const double z[3] = {p[0]->z, p[1]->z, p[2]->z};
  plane(z, t.z0, t.zx, t.zy);
  t.zmin = std::min({p[0]->z, p[1]->z, p[2]->z});
  t.zmax = std::max({p[0]->z, p[1]->z, p[2]->z});
  if (attr) {
    const double sw[3] = {p[0]->iw, p[1]->iw, p[2]->iw};
    const double s1[3] = {0.0, p[1]->iw, 0.0};
    const double s2[3] = {0.0, 0.0, p[2]->iw};
    plane(sw, attr->sw0, attr->swx, attr->swy);
    plane(s1, attr->s10, attr->s1x, attr->s1y);
    plane(s2, attr->s20, attr->s2x, attr->s2y);
    attr->frontFacing = front;
  }
  if (order) {
    for (int k = 0; k < 3; ++k) order[k] = o[k];
  }
  return SetupResult::Ok;
}

}  // namespace penumbra::raster
