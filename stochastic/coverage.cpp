#include "stochastic/coverage.h"

#include <algorithm>
#include <cmath>

namespace penumbra::stochastic {

using raster::ScreenVert;

ThinLens makeThinLens(float proj00, float proj11, float apertureRadius, float focusDistance) {
  ThinLens l;
  if (!(apertureRadius > 0.0f) || !(focusDistance > 0.0f)) return l;
  l.kx = apertureRadius * proj00 / focusDistance;
  l.ky = apertureRadius * proj11 / focusDistance;
  l.focusW = focusDistance;
  return l;
}

SampleTarget makeSampleTarget(int width, int height, raster::CullMode cull) {
  SampleTarget t;
  t.vp = {width, height};
  t.guard = raster::guardPlanes(t.vp);
  t.cull = cull;
  return t;
}

namespace {

// A quick, conservative reject: true only when the sample is certainly outside the triangle that
// the exact test would snap. The snapped coordinates are approximated in float (1/w once per vertex)
// with a bound on their distance from the exact ones, the orientation and the three edge functions
// evaluated in double from them, and an edge rejects only when it is negative by more than what the
// approximation can move it. Vertices the exact test would clip (or anywhere near the guard band)
// and nearly degenerate triangles are left to the exact test.
}  // namespace

bool certainlyOutside(const glm::vec4 c[3], const SampleTarget& tg, int px, int py) {
  constexpr float kLimit = 4194304.0f;  // 2^22 sub-pixel units: half the guard band
  const float sxScale = 0.5f * static_cast<float>(tg.vp.width) * raster::kSubpixelOne;
  const float syScale = 0.5f * static_cast<float>(tg.vp.height) * raster::kSubpixelOne;
  double vx[3], vy[3], err[3];
  for (int k = 0; k < 3; ++k) {
    const float w = c[k].w;
    // z in [0, w] and w > 0 (NaN fails too): otherwise the exact test may clip.
    if (!(w > 0.0f) || !(c[k].z >= 0.0f) || !(c[k].z <= w)) return false;
    const float iw = 1.0f / w;
    // Screen position in sub-pixel units, pixel centres at integers, as snapScreen computes it.
    const float sx = (c[k].x * iw * 0.5f + 0.5f) * (2.0f * sxScale) - 0.5f * raster::kSubpixelOne;
    const float sy = (0.5f - c[k].y * iw * 0.5f) * (2.0f * syScale) - 0.5f * raster::kSubpixelOne;
    if (!(std::abs(sx) < kLimit) || !(std::abs(sy) < kLimit)) return false;
    vx[k] = sx, vy[k] = sy;
    // Float rounding of the chain above (about 8 operations, relative 2^-24 each, on values up to
    // the largest term) plus the snap's own half unit, with a wide safety factor.
    const double mag = std::abs(double{c[k].x * iw}) * double{sxScale} + std::abs(double{c[k].y * iw}) * double{syScale} +
                       double{sxScale} + double{syScale} + 2.0 * raster::kSubpixelOne;
    err[k] = 0.5 + mag * 4e-6;
  }
  const double e = std::max({err[0], err[1], err[2]});
  const double pxs = double{static_cast<float>(px)} * raster::kSubpixelOne, pys = double{static_cast<float>(py)} * raster::kSubpixelOne;
  // Orientation from the approximate area; undecided when the approximation could flip it.
  const double ax = vx[1] - vx[0], ay = vy[1] - vy[0], bx = vx[2] - vx[0], by = vy[2] - vy[0];
  const double area = ax * by - ay * bx;
  const double areaErr = 2.0 * e * (std::abs(ax) + std::abs(ay) + std::abs(bx) + std::abs(by)) + 8.0 * e * e;
  if (!(std::abs(area) > areaErr)) return false;
  const double sign = area > 0.0 ? 1.0 : -1.0;
  for (int k = 0; k < 3; ++k) {
    const int n = k == 2 ? 0 : k + 1;
    const double dx = vx[n] - vx[k], dy = vy[n] - vy[k];
    const double qx = pxs - vx[k], qy = pys - vy[k];
    // Edge function with the triangle's orientation (inside >= 0), and what the approximation of
    // both ends (each coordinate off by at most e) can change it by; the top-left bias is 0 or 1.
    const double edge = sign * (dx * qy - dy * qx);
    const double bound = e * (2.0 * std::abs(qy) + std::abs(dx) + 2.0 * std::abs(qx) + std::abs(dy)) + 4.0 * e * e + 1.0;
    if (edge < -bound) return true;
  }
  return false;
}

namespace {

// Interpolation exactly as Rasterizer::shadeTile: ordered vertices' varyings vk (stride floats),
// the set-up triangle's planes, at pixel (px, py).
void interpolate(const raster::SetupTri& t, const raster::SetupAttr& a, const float* const v[3], int stride, int px,
                 int py, float* out, float b[3]) {
  raster::orderedBarycentrics(t, a, px, py, b);
  for (int c = 0; c < stride; ++c) out[c] = v[0][c] * b[0] + v[1][c] * b[1] + v[2][c] * b[2];
}

// Shared body of sampleCoverage and sampleFragment. kFragment: fill f and out.
template <bool kFragment>
bool evaluate(const glm::vec4 c[3], const float* const vary[3], int nv, const SampleTarget& tg, int px, int py,
              float& depth, raster::Fragment* f, float* out) {
  if (certainlyOutside(c, tg, px, py)) return false;
  // Flags and snapped x, y first (what coverage needs); z and 1/w only for a covered sample.
  ScreenVert s[3];
  for (int k = 0; k < 3; ++k) s[k] = raster::projectVertexXY(c[k].x, c[k].y, c[k].z, c[k].w, tg.vp, tg.guard);
  const raster::Assembly kind = raster::classifyTriangle(s[0].flags, s[1].flags, s[2].flags);
  if (kind == raster::Assembly::Invalid || kind == raster::Assembly::OutsideFrustum) return false;
  if (kind == raster::Assembly::Direct) {
    if (!raster::coversPixel(s[0], s[1], s[2], tg.cull, px, py)) return false;
    for (int k = 0; k < 3; ++k) s[k] = raster::projectVertex(c[k].x, c[k].y, c[k].z, c[k].w, tg.vp, tg.guard);
    raster::SetupTri t;
    raster::SetupAttr a;
    int order[3];
    if (raster::setupTriangle(s[0], s[1], s[2], tg.cull, tg.vp, t, kFragment ? &a : nullptr, order) !=
        raster::SetupResult::Ok)
      return false;
    depth = raster::depthAt(t, px, py);
    if constexpr (kFragment) {
      const float* v[3] = {vary[order[0]], vary[order[1]], vary[order[2]]};
      float b[3];
      interpolate(t, a, v, nv, px, py, out, b);
      float sb[3];
      sb[order[0]] = b[0], sb[order[1]] = b[1], sb[order[2]] = b[2];
      f->b0 = sb[0], f->b1 = sb[1], f->b2 = sb[2];
      f->frontFacing = a.frontFacing;
    }
    return true;
  }
  // Homogeneous clipping, as the pipeline's front end (raster/assemble.h): position, varyings,
  // then the barycentrics of the submitted triangle; the polygon is drawn as a fan.
  const int stride = nv + 3;
  raster::ClipPolygon poly;
  if (raster::clipTriangleToPolygon(c, vary, nv, tg.guard, tg.vp, poly) != raster::Assembly::Clip) return false;
  const int n = poly.count;
  const ScreenVert* sv = poly.screen;
  // The pipeline draws every fan triangle that covers the pixel and keeps the strictly nearest
  // (the first on a tie): fan triangles can overlap by a snapping step when the polygon is nearly
  // flat.
  int best = -1;
  float bestDepth = 0.0f;
  for (int i = 1; i + 1 < n; ++i) {
    if (!raster::coversPixel(sv[0], sv[i], sv[i + 1], tg.cull, px, py)) continue;
    raster::SetupTri t;
    int order[3];
    if (raster::setupTriangle(sv[0], sv[i], sv[i + 1], tg.cull, tg.vp, t, nullptr, order) != raster::SetupResult::Ok)
      continue;
    const float z = raster::depthAt(t, px, py);
    if (best < 0 || z < bestDepth) best = i, bestDepth = z;
  }
  if (best < 0) return false;
  depth = bestDepth;
  if constexpr (kFragment) {
    const int i = best;
    raster::SetupTri t;
    raster::SetupAttr a;
    int order[3];
    raster::setupTriangle(sv[0], sv[i], sv[i + 1], tg.cull, tg.vp, t, &a, order);
    // The pipeline keeps the clipped vertices' varyings as float.
    const int ref[3] = {0, i, i + 1};
    float vk[3][raster::kMaxVaryings + 3];
    const float* v[3];
    for (int k = 0; k < 3; ++k) {
      const double* p = poly.vertex(ref[order[k]]);
      for (int ch = 0; ch < stride; ++ch) vk[k][ch] = static_cast<float>(p[4 + ch]);
      v[k] = vk[k];
    }
    float b[3];
    interpolate(t, a, v, stride, px, py, out, b);
    f->b0 = out[nv], f->b1 = out[nv + 1], f->b2 = out[nv + 2];
    f->frontFacing = a.frontFacing;
  }
  return true;
}

}  // namespace

bool sampleCoverage(const glm::vec4 c[3], const SampleTarget& target, int px, int py, float& depth) {
  return evaluate<false>(c, nullptr, 0, target, px, py, depth, nullptr, nullptr);
}

bool sampleFragment(const glm::vec4 c[3], const float* const vary[3], int nv, const SampleTarget& target, int px,
                    int py, raster::Fragment& f, float* out) {
  float depth = 0.0f;
  if (!evaluate<true>(c, vary, nv, target, px, py, depth, &f, out)) return false;
  f.x = px, f.y = py;
  f.depth = depth;
  f.varyings = out;
  return true;
}

}  // namespace penumbra::stochastic
