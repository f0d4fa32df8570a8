#include "shadows/light_view.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <limits>

#include "raster/large_pages.h"

namespace penumbra::shadows {

namespace {

struct Scan {
  size_t front = 0, behind = 0, outside = 0;
  glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
};

}  // namespace

LightRegion fitRegion(const RectLight& light, const ReceiverImage& receivers) {
  // Min/max and counts are order-independent, so the parallel reduction is deterministic.
  const Scan s = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, receivers.height(), 8), Scan{},
      [&](const tbb::blocked_range<int>& rows, Scan acc) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < receivers.width(); ++x) {
            const Receiver& r = receivers.at(x, y);
            if (!r.valid) continue;
            const glm::vec3 p = toLightSpace(light, r.position);
            if (!(p.z > 0.0f)) {
              ++acc.behind;
              continue;
            }
            ++acc.front;
            if (std::abs(p.x) > kMaxTan * p.z || std::abs(p.y) > kMaxTan * p.z) ++acc.outside;
            acc.lo = glm::min(acc.lo, p);
            acc.hi = glm::max(acc.hi, p);
          }
        return acc;
      },
      [](Scan a, const Scan& b) {
        a.front += b.front;
        a.behind += b.behind;
        a.outside += b.outside;
        a.lo = glm::min(a.lo, b.lo);
        a.hi = glm::max(a.hi, b.hi);
        return a;
      });
  LightRegion r;
  r.receivers = s.front;
  r.receiversBehind = s.behind;
  r.receiversOutside = s.outside;
  if (s.front == 0) return r;
  r.empty = false;
  r.lo = s.lo;
  r.hi = s.hi;
  // Tightest side planes through the light's edges that contain every corner of the receiver box.
  const float hw = 0.5f * light.width, hh = 0.5f * light.height;
  r.sxLo = r.syLo = std::numeric_limits<float>::max();
  r.sxHi = r.syHi = -std::numeric_limits<float>::max();
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? s.hi.x : s.lo.x, (c & 2) ? s.hi.y : s.lo.y, (c & 4) ? s.hi.z : s.lo.z);
    r.sxHi = std::max(r.sxHi, (p.x - hw) / p.z);
    r.sxLo = std::min(r.sxLo, (p.x + hw) / p.z);
    r.syHi = std::max(r.syHi, (p.y - hh) / p.z);
    r.syLo = std::min(r.syLo, (p.y + hh) / p.z);
  }
  return r;
}

namespace {

// Bit k set: light-space point p is outside bounding plane k of the region.
unsigned outsideMask(const LightRegion& r, float hw, float hh, glm::vec3 p) {
  unsigned m = 0;
  if (p.z <= 0.0f) m |= 1u;
  if (p.z > r.hi.z) m |= 2u;
  if (p.x > hw + p.z * r.sxHi) m |= 4u;
  if (p.x < -hw + p.z * r.sxLo) m |= 8u;
  if (p.y > hh + p.z * r.syHi) m |= 16u;
  if (p.y < -hh + p.z * r.syLo) m |= 32u;
  return m;
}

// The smallest depth of the part of triangle p (light space) inside the region: the triangle
// clipped by the region's planes (Sutherland-Hodgman; a triangle crossing the light plane beside
// the light has no part near depth 0 inside the region, one crossing the light itself has). 0 when
// the part reaches the light plane. The part's light-space box is added to [lo, hi].
float minDepthInRegion(const LightRegion& r, float hw, float hh, const glm::vec3 p[3], glm::vec3& lo,
                       glm::vec3& hi) {
  if (outsideMask(r, hw, hh, p[0]) == 0 && outsideMask(r, hw, hh, p[1]) == 0 &&
      outsideMask(r, hw, hh, p[2]) == 0) {
    lo = glm::min(lo, glm::min(p[0], glm::min(p[1], p[2])));
    hi = glm::max(hi, glm::max(p[0], glm::max(p[1], p[2])));
    return std::min({p[0].z, p[1].z, p[2].z});
  }
  // Planes as f(q) >= 0.
  auto plane = [&](int k, glm::vec3 q) {
    switch (k) {
      case 0: return q.z;
      case 1: return r.hi.z - q.z;
      case 2: return hw + q.z * r.sxHi - q.x;
      case 3: return q.x + hw - q.z * r.sxLo;
      case 4: return hh + q.z * r.syHi - q.y;
      default: return q.y + hh - q.z * r.syLo;
    }
  };
  glm::vec3 a[12], b[12];
  int n = 3;
  for (int i = 0; i < 3; ++i) a[i] = p[i];
  for (int k = 0; k < 6 && n > 0; ++k) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const glm::vec3 u = a[i], v = a[(i + 1) % n];
      const float fu = plane(k, u), fv = plane(k, v);
      if (fu >= 0.0f) b[m++] = u;
      if ((fu >= 0.0f) != (fv >= 0.0f) && m < 12) b[m++] = u + (v - u) * (fu / (fu - fv));
    }
    n = m;
    for (int i = 0; i < n; ++i) a[i] = b[i];
  }
  float d = std::numeric_limits<float>::max();
  for (int i = 0; i < n; ++i) {
    const glm::vec3 q(a[i].x, a[i].y, std::max(a[i].z, 0.0f));
    d = std::min(d, q.z);
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  return d;
}

// The light-space positions of the receivers in front of the light, in row-major order: counted
// per row, then written in parallel at each row's offset (one allocation of the exact size; the
// order, and so every reduction over it, does not depend on the threads).
std::vector<glm::vec3, raster::LargePageAllocator<glm::vec3>> receiverPointsInFront(const RectLight& light,
                                                                                   const ReceiverImage& receivers) {
  const int w = receivers.width(), h = receivers.height();
  auto inFront = [&](const Receiver& r, glm::vec3& q) {
    if (!r.valid) return false;
    q = toLightSpace(light, r.position);
    return q.z > 0.0f;
  };
  std::vector<size_t> offset(static_cast<size_t>(h) + 1, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const Receiver* row = receivers.row(y);
      size_t n = 0;
      glm::vec3 q;
      for (int x = 0; x < w; ++x) n += inFront(row[x], q) ? 1 : 0;
      offset[static_cast<size_t>(y) + 1] = n;
    }
  });
  for (size_t y = 0; y < static_cast<size_t>(h); ++y) offset[y + 1] += offset[y];
  std::vector<glm::vec3, raster::LargePageAllocator<glm::vec3>> out(offset.back());
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const Receiver* row = receivers.row(y);
      glm::vec3* dst = out.data() + offset[static_cast<size_t>(y)];
      glm::vec3 q;
      for (int x = 0; x < w; ++x)
        if (inFront(row[x], q)) *dst++ = q;
    }
  });
  return out;
}

}  // namespace

bool LightRegion::mayShadow(const RectLight& light, const glm::vec3 worldCorners[8]) const {
  if (empty) return false;
  unsigned all = ~0u;
  for (int c = 0; c < 8; ++c) all &= outsideMask(*this, 0.5f * light.width, 0.5f * light.height, toLightSpace(light, worldCorners[c]));
  return all == 0;
}

CasterSet cullCasters(const RectLight& light, const LightRegion& region, const Geometry& geometry,
                      const ReceiverImage* receivers) {
  CasterSet out;
  out.trianglesIn = geometry.triangles();
  out.minDepth = std::numeric_limits<float>::max();
  out.lo = glm::vec3(std::numeric_limits<float>::max());
  out.hi = glm::vec3(-std::numeric_limits<float>::max());
  if (region.empty) {
    out.trianglesCulled = out.trianglesIn;
    return out;
  }
  const float hw = 0.5f * light.width, hh = 0.5f * light.height;
  // A triangle whose plane has the whole light strictly on one side and every receiver (the
  // corners of their box) on that side or on the plane cannot block any receiver-light segment
  // (a ground plane under everything the camera sees): culled too. eps: 1e-5 of the scene's size.
  glm::vec3 lightCorners[4] = {{-hw, -hh, 0}, {hw, -hh, 0}, {hw, hh, 0}, {-hw, hh, 0}};
  glm::vec3 recCorners[8];
  for (int c = 0; c < 8; ++c)
    recCorners[c] = {(c & 1) ? region.hi.x : region.lo.x, (c & 2) ? region.hi.y : region.lo.y,
                     (c & 4) ? region.hi.z : region.lo.z};
  const float eps = 1e-5f * std::max({region.hi.x - region.lo.x, region.hi.y - region.lo.y, region.hi.z - region.lo.z,
                                      light.width, light.height});
  // When the box is too coarse (a light tilted against the ground), large triangles are tested
  // against every receiver: at most kMaxPlaneScans scans, and consecutive coplanar triangles (a
  // tessellated ground) reuse the last scan's answer. "Large": twice the area at least 1e-3 of the
  // receivers' box face.
  constexpr int kMaxPlaneScans = 64;
  int scans = 0;
  std::vector<glm::vec3, raster::LargePageAllocator<glm::vec3>> recPoints;  // filled on first use
  glm::vec3 lastU(0.0f);
  float lastOffset = 0.0f;
  bool lastAnswer = false, haveLast = false;
  const float largeArea = 1e-3f * std::max((region.hi.x - region.lo.x) * (region.hi.y - region.lo.y), eps * eps);
  auto cannotBlock = [&](const glm::vec3 p[3]) {
    const glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const float len = glm::length(n);
    if (!(len > 0.0f)) return false;
    glm::vec3 u = n / len;
    if (glm::dot(u, lightCorners[0] - p[0]) < 0.0f) u = -u;  // the light on the positive side
    for (const glm::vec3& q : lightCorners)
      if (!(glm::dot(u, q - p[0]) > eps)) return false;
    bool boxOk = true;
    for (const glm::vec3& q : recCorners) boxOk = boxOk && glm::dot(u, q - p[0]) >= -eps;
    if (boxOk) return true;
    if (!receivers || !(len >= largeArea)) return false;
    const float offset = glm::dot(u, p[0]);
    if (haveLast && glm::length(u - lastU) < 1e-5f && std::abs(offset - lastOffset) < eps) return lastAnswer;
    if (scans == kMaxPlaneScans) return false;
    ++scans;
    if (recPoints.empty()) recPoints = receiverPointsInFront(light, *receivers);
    // min over receivers of the signed distance; min is order-independent: deterministic.
    const float minDist = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, recPoints.size(), 8192), std::numeric_limits<float>::max(),
        [&](const tbb::blocked_range<size_t>& r, float m) {
          for (size_t i = r.begin(); i != r.end(); ++i) m = std::min(m, glm::dot(u, recPoints[i]) - offset);
          return m;
        },
        [](float a, float b) { return std::min(a, b); });
    haveLast = true;
    lastU = u;
    lastOffset = offset;
    lastAnswer = minDist >= -eps;
    return lastAnswer;
  };
  // Sequential: the kept list must keep submission order, and this is a few ns per triangle.
  out.indices.reserve(geometry.indices.size());
  for (size_t t = 0; t < out.trianglesIn; ++t) {
    const uint32_t* tri = &geometry.indices[t * 3];
    glm::vec3 p[3];
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      p[k] = toLightSpace(light, geometry.positions[tri[k]]);
      finite = finite && std::isfinite(p[k].x) && std::isfinite(p[k].y) && std::isfinite(p[k].z);
    }
    if (!finite || (outsideMask(region, hw, hh, p[0]) & outsideMask(region, hw, hh, p[1]) & outsideMask(region, hw, hh, p[2])) ||
        cannotBlock(p)) {
      ++out.trianglesCulled;
      continue;
    }
    out.indices.insert(out.indices.end(), tri, tri + 3);
    if (!geometry.closed.empty()) out.closed.push_back(geometry.closed[t]);
    out.minDepth = std::min(out.minDepth, minDepthInRegion(region, hw, hh, p, out.lo, out.hi));
  }
  if (out.indices.empty() || out.minDepth == std::numeric_limits<float>::max()) out.minDepth = 0.0f;
  if (!(out.lo.x <= out.hi.x && out.lo.y <= out.hi.y && out.lo.z <= out.hi.z))
    out.lo = out.hi = glm::vec3(0.0f);
  return out;
}

namespace {

// The view from `origin` along the light's normal whose frustum spans the tangent box [lo, hi]
// (clamped to kMaxTan, with half a texel of margin on each side so points on the box's faces map
// inside the image, and never an extent below 1/100 of the other, centred on the box).
LightView finishView(const RectLight& light, glm::vec3 origin, glm::vec2 lo, glm::vec2 hi, float znear, int width,
                     int height) {
  LightView v;
  v.right = light.right;
  v.up = light.up;
  v.axis = light.normal();
  v.origin = origin;
  v.znear = znear;
  v.width = width;
  v.height = height;
  lo = glm::clamp(lo, glm::vec2(-kMaxTan), glm::vec2(kMaxTan));
  hi = glm::clamp(hi, glm::vec2(-kMaxTan), glm::vec2(kMaxTan));
  // Texels at most 100 times longer than wide: receivers along a line (a degenerate box) would
  // otherwise give a map a millionth of a texel wide that the rasterizer cannot resolve.
  const glm::vec2 raw = hi - lo;
  const glm::vec2 ext = glm::max(raw, glm::vec2(std::max(1e-6f, 1e-2f * std::max(raw.x, raw.y))));
  lo -= 0.5f * (ext - raw);
  hi += 0.5f * (ext - raw);
  const glm::vec2 margin(ext.x / static_cast<float>(width), ext.y / static_cast<float>(height));
  v.tanLo = lo - margin;
  v.tanHi = hi + margin;
  // Clip: X = (2 (x - tanLo.x d) / ext - d), Y likewise, Z = near, W = d; x, y, d in view space.
  const glm::vec2 e = v.tanHi - v.tanLo;
  glm::mat4 toView(1.0f);  // world -> view (x, y, d, 1)
  for (int i = 0; i < 3; ++i) {
    toView[i][0] = v.right[i];
    toView[i][1] = v.up[i];
    toView[i][2] = v.axis[i];
  }
  toView[3] = glm::vec4(-glm::dot(v.right, v.origin), -glm::dot(v.up, v.origin), -glm::dot(v.axis, v.origin), 1.0f);
  glm::mat4 proj(0.0f);  // column-major: proj[col][row]
  proj[0][0] = 2.0f / e.x;
  proj[2][0] = -(2.0f * v.tanLo.x / e.x + 1.0f);
  proj[1][1] = 2.0f / e.y;
  proj[2][1] = -(2.0f * v.tanLo.y / e.y + 1.0f);
  proj[3][2] = znear;
  proj[2][3] = 1.0f;
  v.viewProj = proj * toView;
  return v;
}

glm::vec3 boxCorner(const LightRegion& r, int c) {
  return {(c & 1) ? r.hi.x : r.lo.x, (c & 2) ? r.hi.y : r.lo.y, (c & 4) ? r.hi.z : r.lo.z};
}

}  // namespace

LightView makeLightView(const RectLight& light, const LightRegion& region, glm::vec2 lightPoint, float znear,
                        int width, int height, glm::vec2 margin, const CasterSet* casters) {
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p = boxCorner(region, c);
    const glm::vec2 t((p.x - lightPoint.x) / p.z, (p.y - lightPoint.y) / p.z);
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  unsigned cut = 0;
  if (casters && casters->boxed() && margin == glm::vec2(0.0f)) {
    // The casters' parts inside the region, seen from this light point (the extremes of (x - l) / d
    // over a box with d > 0 are at its corners), widened by kCasterFitMargin texels of the result.
    glm::vec2 clo(std::numeric_limits<float>::max()), chi(-std::numeric_limits<float>::max());
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 p((c & 1) ? casters->hi.x : casters->lo.x, (c & 2) ? casters->hi.y : casters->lo.y,
                        (c & 4) ? casters->hi.z : casters->lo.z);
      const glm::vec2 t((p.x - lightPoint.x) / p.z, (p.y - lightPoint.y) / p.z);
      clo = glm::min(clo, t);
      chi = glm::max(chi, t);
    }
    const glm::vec2 ilo = glm::max(lo, clo), ihi = glm::min(hi, chi);
    const glm::vec2 size(static_cast<float>(width), static_cast<float>(height));
    const bool finite =
        std::isfinite(clo.x) && std::isfinite(clo.y) && std::isfinite(chi.x) && std::isfinite(chi.y);
    if (finite && ilo.x < ihi.x && ilo.y < ihi.y && size.x > 4.0f * kCasterFitMargin &&
        size.y > 4.0f * kCasterFitMargin) {
      const glm::vec2 pad =
          (ihi - ilo) * (static_cast<float>(kCasterFitMargin) / (size - 2.0f * kCasterFitMargin));
      const glm::vec2 cutLo = clo - pad, cutHi = chi + pad;
      cut = (cutLo.x > lo.x ? 1u : 0u) | (cutHi.x < hi.x ? 2u : 0u) | (cutHi.y < hi.y ? 4u : 0u) |
            (cutLo.y > lo.y ? 8u : 0u);
      lo = glm::max(lo, cutLo);
      hi = glm::min(hi, cutHi);
    }
  }
  LightView v = finishView(light, light.center + lightPoint.x * light.right + lightPoint.y * light.up,
                           lo - margin, hi + margin, znear, width, height);
  v.casterCut = cut;
  return v;
}

LightView makeContainingView(const RectLight& light, const LightRegion& region, const LightView& sample, float znear,
                             int maxSize) {
  // Eq. 1: back by D = max(w, h) / (2 tan(fov / 2)), the light samples' widest field of view.
  const glm::vec2 sampleExt = sample.tanHi - sample.tanLo;
  const float back = std::max(light.width, light.height) / std::max(std::max(sampleExt.x, sampleExt.y), 1e-6f);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int c = 0; c < 8; ++c) {  // the receivers
    const glm::vec3 p = boxCorner(region, c);
    const glm::vec2 t(p.x / (p.z + back), p.y / (p.z + back));
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  for (int c = 0; c < 4; ++c) {  // the light's corners, at depth D
    const glm::vec2 t(((c & 1) ? 0.5f : -0.5f) * light.width / back, ((c & 2) ? 0.5f : -0.5f) * light.height / back);
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  // Eq. 3: the same world texel size as the samples' views at their near plane, per axis: a side of
  // m (ext_source / ext_sample) (near + D) / near, at most maxSize.
  const float grow = (znear + back) / znear;
  auto side = [&](float extSource, float extSample, int m) {
    return std::max(16.0, std::ceil(static_cast<double>(m) * static_cast<double>(extSource / extSample) *
                                     static_cast<double>(grow)));
  };
  // Texels at most 100 times longer than wide: receivers along a line (a degenerate box) would
  // otherwise give a map a millionth of a texel wide that the rasterizer cannot resolve.
  const glm::vec2 raw = hi - lo;
  const glm::vec2 ext = glm::max(raw, glm::vec2(std::max(1e-6f, 1e-2f * std::max(raw.x, raw.y))));
  lo -= 0.5f * (ext - raw);
  hi += 0.5f * (ext - raw);
  const double sw = side(ext.x, sampleExt.x, sample.width), sh = side(ext.y, sampleExt.y, sample.height);
  const double shrink = std::min(1.0, static_cast<double>(maxSize) / std::max(sw, sh));
  const auto fit = [&](double s) { return static_cast<int>(std::clamp(std::ceil(s * shrink), 16.0, 1.0 * maxSize)); };
  const int w = fit(sw), h = fit(sh);
  // Its near plane is the light's plane (depth D): nothing behind the light is rasterized.
  return finishView(light, light.center - back * light.normal(), lo, hi, back, w, h);
}

}  // namespace penumbra::shadows
