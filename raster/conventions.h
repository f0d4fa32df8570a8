// Conventions of the raster/ pipeline. Every stage follows these; tests check them.
//
// Clip space: homogeneous (x, y, z, w), visible volume -w <= x <= w, -w <= y <= w, 0 <= z <= w
//   (zero-to-one depth, as Vulkan/D3D). NDC = clip.xyz / w.
// Screen space: x to the right, y DOWN, in pixels; pixel (i, j) covers [i, i+1) x [j, j+1) and is
//   sampled at its centre (i + 0.5, j + 0.5). screen.x = (ndc.x * 0.5 + 0.5) * width,
//   screen.y = (0.5 - ndc.y * 0.5) * height.
// Fixed point: screen positions snapped (round to nearest, ties to even) to 1/256 pixel
//   (kSubpixelBits = 8) and shifted by half a pixel, so that the centre of pixel (i, j) is the
//   integer point (256 i, 256 j). Snapped coordinates lie in the guard band |x|, |y| <= kGuardBandFixed.
// Edge functions: for an edge a -> b, E(p) = (b.x - a.x)(p.y - a.y) - (b.y - a.y)(p.x - a.x),
//   exact in 64-bit integers. Triangles are re-ordered so that the doubled signed area
//   E_ab(c) > 0; a sample is inside when all three E >= 0 on top-left edges and E > 0 on the others.
// Fill rule: top-left, as D3D: with y down and the positive orientation above, an edge a -> b is a
//   "top" edge when it is horizontal and goes right (dy == 0, dx > 0) and a "left" edge when it goes
//   up (dy < 0). A shared edge is traversed in opposite directions by its two triangles, so exactly
//   one of them owns the samples on it: closed meshes are drawn watertight, every pixel once.
// Facing: counter-clockwise in NDC (y up), i.e. the usual glTF/OpenGL convention, is front-facing.
// Depth: z_ndc = z / w in [0, 1], interpolated linearly in screen space (it is affine there).
//   The depth test is configurable (less or greater; reversed-Z uses greater with a 1 -> 0 range).
// Varyings: interpolated perspective-correctly: with screen-space barycentrics l_i,
//   b_i = (l_i / w_i) / sum_k (l_k / w_k).
//
// Thread-safety: constants and enums only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace penumbra::raster {

// Sub-pixel precision: 8 bits, 1/256 pixel (D3D11 requires at least 8).
inline constexpr int kSubpixelBits = 8;
inline constexpr int32_t kSubpixelOne = 1 << kSubpixelBits;

// Guard band. Snapped coordinates are bounded by 2^23 (fixed) = 32768 pixels, so:
//  - edge-function deltas |dx|, |dy| <= 2^24, and E = dx*dy-type products <= 2^48 * 2: fits int64;
//  - inside a partially covered 8x8 block, E / 256 stays below 8 * (|A| + |B|) <= 2^28, which is
//    why the SIMD stage can evaluate edge functions in 32-bit lanes exactly (see tile_kernels.cpp).
// Triangles whose projection leaves this band are clipped against it in homogeneous space; the
// band is a little inside 2^15 pixels so that snapping can never step out of it.
inline constexpr double kGuardBandPixels = 32768.0 - 64.0;
inline constexpr int64_t kGuardBandFixed = int64_t{1} << 23;

// Largest render target side: the guard band must contain the viewport with room to spare.
inline constexpr int kMaxTargetSize = 16384;

// Blocks are 8x8 pixels (one 64-bit coverage mask); tiles are 2^tileLog2 pixels square.
inline constexpr int kBlockLog2 = 3;
inline constexpr int kBlockSize = 1 << kBlockLog2;

// Multisampling: 1, 2, 4 or 8 samples per pixel at the standard positions (those of D3D 10.1 and
// Vulkan's standard sample locations), offsets from the pixel centre in 1/16 pixel, y down. In
// fixed point they are multiples of 16 (exact with 8 sub-pixel bits): sample s of pixel (i, j)
// lies at (256 i + 16 dx_s, 256 j + 16 dy_s), and a sample on an edge is owned by the top-left rule
// exactly as a pixel centre is, so closed meshes cover every sample once.
struct SampleOffset {
  int8_t dx, dy;  // 1/16 pixel
};
inline constexpr SampleOffset kSamples1[] = {{0, 0}};
inline constexpr SampleOffset kSamples2[] = {{4, 4}, {-4, -4}};
inline constexpr SampleOffset kSamples4[] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
inline constexpr SampleOffset kSamples8[] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
inline constexpr int kMaxSamples = 8;
inline constexpr bool isSampleCount(int n) { return n == 1 || n == 2 || n == 4 || n == 8; }
// The pattern of n samples (isSampleCount(n)); empty otherwise.
inline constexpr std::span<const SampleOffset> samplePattern(int n) {
  return n == 1 ? std::span<const SampleOffset>(kSamples1)
         : n == 2 ? std::span<const SampleOffset>(kSamples2)
         : n == 4 ? std::span<const SampleOffset>(kSamples4)
         : n == 8 ? std::span<const SampleOffset>(kSamples8)
                  : std::span<const SampleOffset>();
}

// The samples of samplePattern(n) ordered nearest the pixel centre first (ties: the lower index):
// the order in which a resolve picks the sample a surface is shaded at. Entries past n are 0.
inline constexpr std::array<int, kMaxSamples> samplesNearestFirst(int n) {
  const std::span<const SampleOffset> p = samplePattern(n);
  std::array<int, kMaxSamples> order{};
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    const auto d2 = [&](int s) {
      const SampleOffset o = p[static_cast<size_t>(s)];
      return o.dx * o.dx + o.dy * o.dy;
    };
    int j = i;  // insertion sort, stable
    for (; j > 0 && d2(order[static_cast<size_t>(j - 1)]) > d2(i); --j)
      order[static_cast<size_t>(j)] = order[static_cast<size_t>(j - 1)];
    order[static_cast<size_t>(j)] = i;
  }
  return order;
}

enum class CullMode : uint8_t { None, Back, Front };
enum class DepthFunc : uint8_t { Less, Greater, Always };

}  // namespace penumbra::raster
