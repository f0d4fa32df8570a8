// Point clouds for the point splatter (raster/splat.h): sampled from a scene's surfaces, or read
// from a text file. Used by `penumbra render --points` and `penumbra bench points`.
//
// Surface sampling: area-weighted uniform over the world-space triangles of every instance.
// Point i takes its triangle from a cumulative-area table (the first triangle whose running sum of
// areas exceeds u0 * total) and its barycentrics from u1, u2 by the square-root warp
//   b0 = 1 - sqrt(u1),  b1 = sqrt(u1) (1 - u2),  b2 = sqrt(u1) u2
// (Osada et al. 2002, "Shape Distributions", section 4.2; pbrt-v4 SampleUniformTriangle), where
// (u0, u1, u2) = pointRandom(i, 0..2): a counter-based hash of (i, dimension), so point i is the
// same whatever the thread count or the order the points are made in. Consecutive points lie on
// unrelated triangles: the cloud is in random order, the worst case for a splatter's caches.
// Areas are summed in double (a float running sum over millions of triangles loses the small ones).
//
// .xyz text files: one point per line, "x y z" or "x y z r g b", fields separated by spaces or
// tabs; x, y, z finite floats, r, g, b integers in [0, 255] (sRGB bytes; alpha is 255; points
// without a color are white). Blank lines and lines whose first non-blank character is '#' are
// skipped; a CR before the line end is ignored. At most kMaxCloudPoints points.
//
// Thread-safety: pure functions; sampleSurface runs tbb::parallel_for in the caller's task arena.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "engine/error.h"
#include "engine/scene.h"

namespace penumbra::apps {

// 2^26 points: 1 GiB of positions and payloads, and the point index still fits the 32-bit payload.
inline constexpr int64_t kMaxCloudPoints = int64_t{1} << 26;

// Uniform in [0, 1) from (index, dimension): SplitMix64 (Steele et al. 2014) at position
// 4 * index + dimension of its sequence, the top 53 bits scaled by 2^-53. dimension in [0, 3].
double pointRandom(uint64_t index, uint32_t dimension);

struct SurfacePoints {
  std::vector<glm::vec3> positions;  // world space
  std::vector<glm::vec3> normals;    // world-space unit face normal of the point's triangle (attributes only)
  std::vector<int32_t> materials;    // the point's mesh material, -1: default (attributes only)
};

// `count` points in [1, kMaxCloudPoints] on the scene's triangles; normals and materials are
// filled only when `attributes` is set. An Error when the scene has no triangle of non-zero area.
engine::Result<SurfacePoints> sampleSurface(const engine::Scene& scene, int64_t count, bool attributes);

// Packed RGBA8 payloads (raster::packRgba8) for sampled points: the material's base color factor
// (linear; default material white) times the headlight term 0.15 + 0.85 |n . v|, v the unit
// direction from the point to `eye`, encoded to sRGB bytes, alpha 255.
std::vector<uint32_t> headlightColors(const engine::Scene& scene, const SurfacePoints& points, glm::vec3 eye);

struct XyzCloud {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> colors;  // packed RGBA8, one per point
};

// Reads an .xyz file (format above). Errors name the file and, for its contents, "line N".
engine::Result<XyzCloud> readXyz(const std::string& path);
// The same from text in memory; `name` names it in errors.
engine::Result<XyzCloud> parseXyz(std::string_view text, const std::string& name);

}  // namespace penumbra::apps
