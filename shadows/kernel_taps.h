// The per-receiver tap loops of the kernel techniques (PCF, PCSS) in SIMD lanes: each lane computes
// one tap's tangent-space point, the texel it reads (a gather from the depth map) and the
// receiver-plane threshold there (shadow_map.h), with the same float operations in the same order
// as the scalar expressions of ShadowMap::stored and ReceiverPlane::threshold. No FMA (the project
// builds with -ffp-contract=off and the kernels never call MulAdd), clamps with the NaN behaviour of
// std::min / std::max (a NaN coordinate reads texel 0, like the scalar code), truncation of
// non-negative floats to texel indices: every target gives the bits of the scalar reference
// functions below, which are the original loops written plainly.
//
// Patterns are separate x[] and y[] arrays readable up to n rounded up to kTapLanes (TapPattern
// pads them); the lanes past n are computed and not counted.
//
// The SIMD code is compiled for every x86 target Highway knows; each call runs the target its simd
// argument names (raster/simd.h: 0 = the best the CPU supports; techniques pass their rasterizer's
// RasterConfig::simd.taps), so tests run each in turn.
//
// Thread-safety: the kernels are pure functions of their arguments (the map is only read) and may
// run concurrently.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

namespace penumbra::shadows {

// The widest vector, in floats (AVX-512): patterns are padded to a multiple of it and the kernels
// use at most this many lanes.
inline constexpr int kTapLanes = 16;

// The lookup constants of a ShadowMap (shadow_map.h): the stored value (near / depth, 0 = nothing
// drawn) of the texel holding tangent point (tanX, tanY) is
//     data[row * stride + column], column = trunc(min(maxX, max(0, ax tanX + bx))), row likewise.
// row * stride + column < 2^31 (maps are at most 8192^2, depthMapParams), so indices fit int32.
struct TapMap {
  const float* data = nullptr;
  int32_t stride = 0;  // floats between rows
  float ax = 0, bx = 0, ay = 0, by = 0, maxX = 0, maxY = 0;

  float stored(float tanX, float tanY) const {
    const float fx = std::min(maxX, std::max(0.0f, ax * tanX + bx));
    const float fy = std::min(maxY, std::max(0.0f, ay * tanY + by));
    return data[static_cast<size_t>(fy) * static_cast<size_t>(stride) + static_cast<size_t>(fx)];
  }
};

// A receiver's depth test (ReceiverPlane, shadow_map.h): lit by stored value z iff
//     z <= scale * min(hi, max(lo, a tanX + b tanY + c))
// (scale = +inf where the bias reaches the receiver's depth: every tap is lit).
struct TapPlane {
  float a = 0, b = 0, c = 0, lo = 0, hi = 0, scale = 0;

  float threshold(float tanX, float tanY) const { return scale * std::min(hi, std::max(lo, a * tanX + b * tanY + c)); }
};

// A pattern as the kernels read it: count points, x[] and y[] zero-padded to a multiple of
// kTapLanes.
struct TapPattern {
  std::vector<float> x, y;
  int count = 0;

  TapPattern() = default;
  explicit TapPattern(std::span<const glm::vec2> points);
};

// The blocker search's result: the number of blocking taps and the sum, in tap order, of their
// occluder depths (near / z) as doubles.
struct BlockerSum {
  int count = 0;
  double sum = 0.0;
};

// PCSS taps: pattern point p (n of them) shifted by (shiftX, shiftY) and wrapped to [0, 1), over
// half-extents (hx, hy) around (cx, cy):
//     tanX = cx + (2 frac(p.x + shiftX) - 1) hx,  tanY = cy + (2 frac(p.y + shiftY) - 1) hy.
// countLitTaps: how many pass the depth test (z <= threshold).
int countLitTaps(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n, float shiftX,
                 float shiftY, float cx, float cy, float hx, float hy, int64_t simd = 0);
// searchBlockers: the taps that fail it (z > threshold), with depths znear / z.
BlockerSum searchBlockers(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                          float shiftX, float shiftY, float cx, float cy, float hx, float hy, float znear, int64_t simd = 0);
// PCF taps: texel offsets o rotated by (c, s) = (cos, sin) of an angle, scaled by the texel size
// (tanX grows with columns, tanY falls with rows):
//     tanX = cx + (c o.x - s o.y) texelX,  tanY = cy - (s o.x + c o.y) texelY.
int countLitRotatedTaps(const TapMap& map, const TapPlane& plane, const float* ox, const float* oy, int n, float c,
                        float s, float cx, float cy, float texelX, float texelY, int64_t simd = 0);

// The scalar references: the same results, one tap at a time (no padding needed).
int countLitTapsScalar(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                       float shiftX, float shiftY, float cx, float cy, float hx, float hy);
BlockerSum searchBlockersScalar(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                                float shiftX, float shiftY, float cx, float cy, float hx, float hy, float znear);
int countLitRotatedTapsScalar(const TapMap& map, const TapPlane& plane, const float* ox, const float* oy, int n,
                              float c, float s, float cx, float cy, float texelX, float texelY);


}  // namespace penumbra::shadows
