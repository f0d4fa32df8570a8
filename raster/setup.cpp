#include "raster/setup.h"

#include <algorithm>
#include <cmath>

namespace penumbra::raster {

GuardPlanes guardPlanes(const Viewport& vp) {
  // Screen x = (ndc.x * 0.5 + 0.5) W in [-G, G]  <=>  ndc.x in [-(2G/W + 1), 2G/W - 1]; y is flipped.
  const double g = kGuardBandPixels;
  return {-(2.0 * g / vp.width + 1.0), 2.0 * g / vp.width - 1.0, 1.0 - 2.0 * g / vp.height, 2.0 * g / vp.height + 1.0};
}

namespace {

// Snapped x, y (z and 1/w left to the caller). lrint rounds to nearest, ties to even (the default
// rounding mode), as nearbyint would, but compiles to one instruction.
void snapXY(ScreenVert& s, double wd, double x, double y, const Viewport& vp, bool clamp) {
  double sx = (x / wd * 0.5 + 0.5) * vp.width;
  double sy = (0.5 - y / wd * 0.5) * vp.height;
  if (clamp) {
    sx = std::clamp(sx, -kGuardBandPixels, kGuardBandPixels);
    sy = std::clamp(sy, -kGuardBandPixels, kGuardBandPixels);
  }
  s.x = static_cast<int32_t>(std::lrint(sx * kSubpixelOne - kSubpixelOne / 2)) - vp.sampleX;
  s.y = static_cast<int32_t>(std::lrint(sy * kSubpixelOne - kSubpixelOne / 2)) - vp.sampleY;
}

ScreenVert snapScreen(double wd, double x, double y, double z, const Viewport& vp, bool clamp) {
  ScreenVert s;
  snapXY(s, wd, x, y, vp, clamp);
  s.z = static_cast<float>(z / wd);
  s.iw = static_cast<float>(1.0 / wd);
  return s;
}

}  // namespace

ScreenVert projectVertexXY(float x, float y, float z, float w, const Viewport& vp, const GuardPlanes& guard) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(w)) {
    ScreenVert s;
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
  // Screen position in double: 8 fractional bits of a 2^15 range need more than float's 24 bits.
  const double xd = x, yd = y, wd = w;
  double d[4];
  guardDistances(guard, xd, yd, wd, d);
  ScreenVert s;
  if (!(w > 0.0f) || d[0] < 0.0 || d[1] < 0.0 || d[2] < 0.0 || d[3] < 0.0) {
    s.flags = f | kOutGuard;
    return s;
  }
  snapXY(s, wd, xd, yd, vp, false);
  s.flags = f;
  return s;
}

ScreenVert projectVertex(float x, float y, float z, float w, const Viewport& vp, const GuardPlanes& guard) {
  ScreenVert s = projectVertexXY(x, y, z, w, vp, guard);
  if (!(s.flags & (kNonFinite | kOutGuard))) {
    const double wd = w;
    s.z = static_cast<float>(static_cast<double>(z) / wd);
    s.iw = static_cast<float>(1.0 / wd);
  }
  return s;
}

ScreenVert projectClipped(const double p[4], const Viewport& vp) {
  if (!(p[3] > 0.0) || !std::isfinite(p[0]) || !std::isfinite(p[1])) {
    ScreenVert s;
    s.flags = kOutGuard;
    return s;
  }
  return snapScreen(p[3], p[0], p[1], p[2], vp, true);
}

namespace {

// ceil(a / 256) and floor(a / 256) for signed a.
inline int32_t floorDiv(int32_t a) { return a >> kSubpixelBits; }
inline int32_t ceilDiv(int32_t a) { return -((-a) >> kSubpixelBits); }

}  // namespace

SetupResult setupTriangle(const ScreenVert& v0, const ScreenVert& v1, const ScreenVert& v2, CullMode cull,
                          const Viewport& vp, SetupTri& t, SetupAttr* attr, int order[3]) {
  // Bounding box first: most small triangles that are rejected hold no pixel centre.
  // Pixel i is sampled at 256 i: candidates are ceil(min/256) .. floor(max/256), clamped.
  const int32_t minx = std::min({v0.x, v1.x, v2.x}), maxx = std::max({v0.x, v1.x, v2.x});
  const int32_t miny = std::min({v0.y, v1.y, v2.y}), maxy = std::max({v0.y, v1.y, v2.y});
  t.minX = std::max(ceilDiv(minx), 0);
  t.maxX = std::min(floorDiv(maxx), vp.width - 1);
  t.minY = std::max(ceilDiv(miny), 0);
  t.maxY = std::min(floorDiv(maxy), vp.height - 1);
  if (t.minX > t.maxX || t.minY > t.maxY) return SetupResult::NoSample;

  // Doubled signed area in y-down fixed point: (v1 - v0) x (v2 - v0).
  const int64_t area = (int64_t{v1.x} - v0.x) * (int64_t{v2.y} - v0.y) - (int64_t{v1.y} - v0.y) * (int64_t{v2.x} - v0.x);
  if (area == 0) return SetupResult::Degenerate;
  // Counter-clockwise in NDC (y up) is clockwise with y down: negative area here.
  const bool front = area < 0;
  if ((cull == CullMode::Back && !front) || (cull == CullMode::Front && front)) return SetupResult::CulledFacing;
  const ScreenVert& p0 = v0;
  const ScreenVert& p1 = front ? v2 : v1;
  const ScreenVert& p2 = front ? v1 : v2;
  t.vx[0] = p0.x, t.vx[1] = p1.x, t.vx[2] = p2.x;
  t.vy[0] = p0.y, t.vy[1] = p1.y, t.vy[2] = p2.y;

  // Planes from the barycentrics of ordered vertices 1 and 2: l1 = E_20(p) / area,
  // l2 = E_01(p) / area (edge functions without bias), so that s = s0 + (s1 - s0) l1 + (s2 - s0) l2
  // for any quantity s linear in screen space. E steps by 256 A per pixel in x, 256 B in y.
  const double inv = 1.0 / static_cast<double>(front ? -area : area);
  const int64_t ox = int64_t{t.minX} * kSubpixelOne, oy = int64_t{t.minY} * kSubpixelOne;
  const int64_t a1 = -(int64_t{p0.y} - p2.y), b1 = int64_t{p0.x} - p2.x;  // edge 2 -> 0
  const int64_t a2 = -(int64_t{p1.y} - p0.y), b2 = int64_t{p1.x} - p0.x;  // edge 0 -> 1
  const double l1 = static_cast<double>(a1 * (ox - p2.x) + b1 * (oy - p2.y)) * inv;
  const double l2 = static_cast<double>(a2 * (ox - p0.x) + b2 * (oy - p0.y)) * inv;
  const double l1x = static_cast<double>(a1 * kSubpixelOne) * inv, l1y = static_cast<double>(b1 * kSubpixelOne) * inv;
  const double l2x = static_cast<double>(a2 * kSubpixelOne) * inv, l2y = static_cast<double>(b2 * kSubpixelOne) * inv;
  auto plane = [&](double s0, double d1, double d2, float& c, float& cx, float& cy) {
    c = static_cast<float>(s0 + d1 * l1 + d2 * l2);
    cx = static_cast<float>(d1 * l1x + d2 * l2x);
    cy = static_cast<float>(d1 * l1y + d2 * l2y);
  };
  const double z0 = p0.z;
  plane(z0, double{p1.z} - z0, double{p2.z} - z0, t.z0, t.zx, t.zy);
  t.zmin = std::min({p0.z, p1.z, p2.z});
  t.zmax = std::max({p0.z, p1.z, p2.z});
  if (attr) {
    const double w0 = p0.iw, w1 = p1.iw, w2 = p2.iw;
    plane(w0, w1 - w0, w2 - w0, attr->sw0, attr->swx, attr->swy);
    plane(0.0, w1, 0.0, attr->s10, attr->s1x, attr->s1y);
    plane(0.0, 0.0, w2, attr->s20, attr->s2x, attr->s2y);
    attr->frontFacing = front;
  }
  if (order) {
    order[0] = 0;
    order[1] = front ? 2 : 1;
    order[2] = front ? 1 : 2;
  }
  return SetupResult::Ok;
}

}  // namespace penumbra::raster
