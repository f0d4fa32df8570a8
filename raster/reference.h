// The reference rasterizer: slow, scalar, obvious. Tests and `penumbra stress` compare the fast
// pipeline against it. It shares no code with setup.cpp or tile_kernels.cpp on purpose.
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cstdint>
#include <glm/vec4.hpp>
#include <vector>

namespace penumbra::raster::reference {

// A triangle snapped to the pipeline's fixed point (conventions.h), in submission order.
struct SnappedTriangle {
  int64_t x[3], y[3];
  double z[3];  // z / w
};

// Projects and snaps; the vertices must have w > 0 and project inside the guard band.
SnappedTriangle snap(const glm::vec4 clip[3], int width, int height);

// Coverage of the snapped triangle at every pixel centre, top-left rule, either orientation:
// adds 1 to count[y * width + x] for each covered pixel. Zero-area triangles cover nothing.
// With a sample offset (dx16, dy16 in 1/16 pixel, conventions.h's sample patterns) the point
// tested is the pixel centre plus that offset instead.
void coverage(const SnappedTriangle& t, int width, int height, std::vector<uint32_t>& count, int dx16 = 0,
              int dy16 = 0);

// Coverage decided in homogeneous coordinates, without clipping or division (2D homogeneous
// rasterization, Olano and Greer 1997): the sample (sx, sy) in NDC is inside when the three edge
// functions of the triangle's (x, y, w) share the sign of its orientation and the interpolated z/w
// lies in [0, 1]. Valid for vertices behind the eye. Floating point: pixels whose edge distance is
// below `margin` (relative) are reported as 2 = "on an edge, either answer is right".
// Returns per pixel 0 (outside), 1 (inside) or 2 (ambiguous).
std::vector<uint8_t> homogeneousCoverage(const glm::vec4 clip[3], int width, int height, double margin);

}  // namespace penumbra::raster::reference
