// Triangle setup: from clip-space vertices to snapped fixed-point triangles with exact integer edge
// functions (conventions in raster/conventions.h). Also the per-vertex projection used by the
// vertex stage and the homogeneous clipper (clip.h) for the triangles that need it.
//
// Thread-safety: every function here is pure; safe to call from any thread.
#pragma once

#include <cstddef>
#include <cstdint>

#include "raster/conventions.h"

namespace penumbra::raster {

// Outcodes and flags of a projected vertex.
enum VertexFlags : uint32_t {
  kOutLeft = 1u << 0,   // x < -w
  kOutRight = 1u << 1,  // x >  w
  kOutBottom = 1u << 2, // y < -w
  kOutTop = 1u << 3,    // y >  w
  kOutNear = 1u << 4,   // z < 0
  kOutFar = 1u << 5,    // z >  w
  kOutGuard = 1u << 6,  // projects outside the guard band (or w <= 0): must be clipped
  kNonFinite = 1u << 7, // NaN or Inf in the clip position: dropped
  kFrustumMask = 0x3fu,
  kNeedsClip = kOutNear | kOutFar | kOutGuard,
};

struct Viewport {
  int width = 0, height = 0;
  // Multisampling: the sample's offset from the pixel centre in fixed point (samplePattern). Every
  // snapped vertex is moved by minus this, exactly (integers), so the pixel centres of the moved
  // triangle are the sample positions of the original: per sample the same exact coverage, fill
  // rule and depth plane as at pixel centres.
  int32_t sampleX = 0, sampleY = 0;
};

// A vertex after the vertex stage: snapped screen position (valid when no kNeedsClip/kNonFinite
// flag is set), z/w and 1/w.
struct ScreenVert {
  int32_t x = 0, y = 0;  // fixed point, pixel centre (i, j) at (256 i, 256 j)
  float z = 0;           // z / w
  float iw = 0;          // 1 / w
  uint32_t flags = 0;
};

// The guard band as four clip-space planes: a vertex (w > 0) projects inside the band, screen x
// and y within [-kGuardBandPixels, kGuardBandPixels], when every distance is >= 0. The vertex
// stage's kOutGuard flag and the clipper evaluate these same expressions in double, so a vertex the
// flag leaves alone is never moved by the clipper (edges shared with clipped triangles stay put).
struct GuardPlanes {
  double xlo, xhi, ylo, yhi;  // x in [xlo w, xhi w], y in [ylo w, yhi w]
};
GuardPlanes guardPlanes(const Viewport& vp);
inline void guardDistances(const GuardPlanes& g, double x, double y, double w, double d[4]) {
  d[0] = g.xhi * w - x;
  d[1] = x - g.xlo * w;
  d[2] = g.yhi * w - y;
  d[3] = y - g.ylo * w;
}

ScreenVert projectVertex(float x, float y, float z, float w, const Viewport& vp, const GuardPlanes& guard);
// The same flags and snapped x, y, without z and 1/w (left 0): what coverage alone needs.
ScreenVert projectVertexXY(float x, float y, float z, float w, const Viewport& vp, const GuardPlanes& guard);
// projectVertex for n vertices in SIMD lanes (setup_lanes.cpp, SimdChoice::setup's target), bit for
// bit: clip holds x, y, z, w of each vertex (4n floats). Returns how many are non-finite.
uint64_t projectVertices(const float* clip, size_t n, const Viewport& vp, const GuardPlanes& guard, ScreenVert* out,
                         int64_t simd);
// A vertex made by the clipper (double precision, w > 0, on or inside every plane up to rounding):
// its screen position is clamped into the guard band before snapping.
ScreenVert projectClipped(const double p[4], const Viewport& vp);

// A triangle ready for the tile stage: one 64-byte cache line, all the depth-only path reads.
// Edge k runs from vertex k to vertex k+1; its coefficients and fill-rule bias are derived from the
// vertices where needed (edgeCoefficients), which is cheaper than reading them from memory.
struct alignas(64) SetupTri {
  int32_t vx[3], vy[3];    // snapped vertices, ordered so that the doubled area is > 0
  int32_t minX, minY, maxX, maxY;  // inclusive pixel bounding box, clamped to the viewport
  float z0, zx, zy;        // depth plane: z(i, j) = z0 + zx (i - minX) + zy (j - minY), clamped
  float zmin, zmax;        // to [zmin, zmax], the vertices' range (keeps coarse depth exact)
  uint32_t primitive;      // triangle index in the draw
};
static_assert(sizeof(SetupTri) == 64);

// E_k(p) = A (p.x - v_k.x) + B (p.y - v_k.y) - bias; inside iff E_k >= 0 for k = 0, 1, 2.
struct EdgeCoefficients {
  int32_t a[3], b[3];
  int32_t bias[3];  // 0 on top-left edges (E >= 0 inside), 1 otherwise (E > 0 inside)
};
inline EdgeCoefficients edgeCoefficients(const SetupTri& t) {
  EdgeCoefficients e;
  for (int k = 0; k < 3; ++k) {
    const int n = k == 2 ? 0 : k + 1;
    const int32_t dx = t.vx[n] - t.vx[k], dy = t.vy[n] - t.vy[k];
    e.a[k] = -dy;
    e.b[k] = dx;
    e.bias[k] = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1;  // top-left rule, conventions.h
  }
  return e;
}

// Perspective-correct interpolation planes (fragment path only), same origin as the depth plane:
// s(i, j) = s0 + sx (i - minX) + sy (j - minY) for s = 1/w (sw), l1/w1 (s1), l2/w2 (s2), where
// l_k are the screen-space barycentrics of the ordered vertices.
struct SetupAttr {
  float sw0, swx, swy;
  float s10, s1x, s1y;
  float s20, s2x, s2y;
  uint32_t vary[3];  // varyings of the ordered vertices; top bit set: chunk-local (clipped) vertex
  uint8_t order[3];  // submitted vertex (0..2) of each ordered vertex
  bool clipped;      // made by the clipper: varyings are followed by 3 submitted barycentrics
  bool frontFacing;
};
inline constexpr uint32_t kChunkLocalVarying = 0x80000000u;

enum class SetupResult : uint8_t { Ok, CulledFacing, Degenerate, NoSample };

// Sets up the triangle (v0, v1, v2) as submitted. On Ok, `out` is filled except primitive;
// `attr`, when non-null, receives the interpolation planes and `order` the submitted vertex
// index (0..2) of each ordered vertex.
SetupResult setupTriangle(const ScreenVert& v0, const ScreenVert& v1, const ScreenVert& v2, CullMode cull,
                          const Viewport& vp, SetupTri& out, SetupAttr* attr, int order[3]);

// Setup of a group of triangles in SIMD lanes (setup_lanes.cpp, one Highway target per
// SimdChoice::setup): bounding box, zero-area and facing culls, vertex order and the planes of
// kSetupGroup triangles at once. The records are those setupTriangle makes, bit for bit: every
// integer quantity setupTriangle forms in int64 (the doubled area, the edge values at the plane
// origin) is below 2^50 (conventions.h bounds coordinates by 2^23), so the lanes form it exactly in
// double, and the planes repeat setupTriangle's double operations in its order, without FMA.
inline constexpr int kSetupGroup = 16;  // a multiple of every target's lane count
struct SetupGroupIn {                   // the triangles' vertices as submitted, one array per field
  alignas(64) int32_t x[3][kSetupGroup];
  alignas(64) int32_t y[3][kSetupGroup];
  alignas(64) float z[3][kSetupGroup];
  alignas(64) float iw[3][kSetupGroup];
  uint32_t primitive[kSetupGroup];
};
// Sets up lanes 0 .. n-1 of `in` (n <= kSetupGroup) with `simd`'s target (simd.h). The triangles
// setup keeps are written to tris[0 ..) in lane order (with their primitive) and, when attrs is not
// null, their planes, order and frontFacing to attrs[0 ..) (vary and clipped left to the caller).
// Returns the kept lanes as a bit mask; verdicts[r] counts the lanes with SetupResult r.
uint32_t setupLanes(const SetupGroupIn& in, int n, CullMode cull, const Viewport& vp, SetupTri* tris,
                    SetupAttr* attrs, uint64_t verdicts[4], int64_t simd);

// Edge value of edge k at pixel (i, j), exact, bias applied: inside iff >= 0 for all k.
inline int64_t edgeAt(const SetupTri& t, const EdgeCoefficients& e, int k, int64_t i, int64_t j) {
  return int64_t{e.a[k]} * (i * kSubpixelOne - t.vx[k]) + int64_t{e.b[k]} * (j * kSubpixelOne - t.vy[k]) - e.bias[k];
}

// The tile stage's decision for the snapped triangle (v0, v1, v2), as submitted, at pixel centre
// (px, py), without setting it up: the orientation and facing of setupTriangle, then the three
// edge functions with the top-left bias of edgeCoefficients. Cheaper than setupTriangle when most
// answers are "outside" (the stochastic rasterizer's per-sample test).
inline bool coversPixel(const ScreenVert& v0, const ScreenVert& v1, const ScreenVert& v2, CullMode cull, int px,
                        int py) {
  const int64_t area = (int64_t{v1.x} - v0.x) * (int64_t{v2.y} - v0.y) - (int64_t{v1.y} - v0.y) * (int64_t{v2.x} - v0.x);
  if (area == 0) return false;
  const bool front = area < 0;
  if ((cull == CullMode::Back && !front) || (cull == CullMode::Front && front)) return false;
  const ScreenVert* p[3] = {&v0, front ? &v2 : &v1, front ? &v1 : &v2};
  const int64_t sx = int64_t{px} * kSubpixelOne, sy = int64_t{py} * kSubpixelOne;
  for (int k = 0; k < 3; ++k) {
    const ScreenVert& a = *p[k];
    const ScreenVert& b = *p[k == 2 ? 0 : k + 1];
    const int64_t dx = int64_t{b.x} - a.x, dy = int64_t{b.y} - a.y;
    const int64_t bias = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1;
    if (-dy * (sx - a.x) + dx * (sy - a.y) - bias < 0) return false;
  }
  return true;
}

// Perspective-correct barycentrics of the ordered vertices at pixel (i, j), exactly as the fragment
// stage computes them (Rasterizer::shadeTile and stochastic::sampleFragment share this).
inline void orderedBarycentrics(const SetupTri& t, const SetupAttr& a, int i, int j, float b[3]) {
  const float dx = static_cast<float>(i - t.minX), dy = static_cast<float>(j - t.minY);
  const float sw = (a.sw0 + a.swx * dx) + a.swy * dy;
  const float s1 = (a.s10 + a.s1x * dx) + a.s1y * dy;
  const float s2 = (a.s20 + a.s2x * dx) + a.s2y * dy;
  const float iw = 1.0f / sw;
  b[1] = s1 * iw;
  b[2] = s2 * iw;
  b[0] = 1.0f - b[1] - b[2];
}

// Depth of the triangle's plane at pixel (i, j), exactly as the tile stage computes it.
inline float depthAt(const SetupTri& t, int i, int j) {
  const float dx = static_cast<float>(i - t.minX), dy = static_cast<float>(j - t.minY);
  float z = (t.z0 + t.zx * dx) + t.zy * dy;
  z = z < t.zmin ? t.zmin : z;
  return z > t.zmax ? t.zmax : z;
}

}  // namespace penumbra::raster
