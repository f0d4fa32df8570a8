// Homogeneous clipping (Sutherland-Hodgman in clip space) for the few triangles that cross the
// near or far plane or leave the guard band. Vertices are [x, y, z, w, varyings...].
//
// Watertightness: a new vertex is always interpolated from the endpoint inside the plane towards
// the one outside, so the two triangles sharing an edge compute bit-identical vertices on it.
//
// Pure functions; safe from any thread.
#pragma once

#include "raster/setup.h"

namespace penumbra::raster {

inline constexpr int kMaxVaryings = 16;
// A triangle clipped by at most 7 planes (near, far, 4 guard band, w >= 0) gains at most one vertex
// per plane: 3 + 7 = 10.
inline constexpr int kMaxClipVerts = 10;
// Clip-space position, up to kMaxVaryings varyings and the 3 barycentrics of the submitted triangle.
inline constexpr int kClipStride = 4 + kMaxVaryings + 3;

// Planes to clip against (bit set of VertexFlags: kOutNear, kOutFar, kOutGuard).
// `in` holds the triangle's three vertices, each `4 + nv` floats. Writes the clipped convex polygon
// to `out` (kMaxClipVerts vertices of kClipStride floats) and returns its vertex count (0 when the
// triangle is entirely outside, else >= 3).
int clipTriangle(const float* const in[3], int nv, uint32_t planes, const Viewport& vp, float* out);

}  // namespace penumbra::raster
