// Homogeneous clipping (Sutherland-Hodgman in clip space) for the few triangles that cross the
// near or far plane or leave the guard band. Vertices are [x, y, z, w, varyings...].
//
// Watertightness: a new vertex is always interpolated from the endpoint inside the plane towards
// the one outside, so the two triangles sharing an edge compute bit-identical vertices on it.
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include "raster/setup.h"

namespace penumbra::raster {

inline constexpr int kMaxVaryings = 16;
// A triangle clipped by 6 planes (near, far, 4 guard band) gains at most one vertex per plane:
// 3 + 6 = 9; the buffers hold twice that, and the clipper never writes past them even when
// rounding makes a polygon slightly non-convex.
inline constexpr int kMaxClipVerts = 18;
// Clip-space position, up to kMaxVaryings varyings and the 3 barycentrics of the submitted triangle.
inline constexpr int kClipStride = 4 + kMaxVaryings + 3;

// Clips against near (z >= 0), far (z <= w) and the guard band (guardDistances), in double
// precision: an intersection far from a vertex with large w keeps its accuracy.
// `in` holds the triangle's three vertices, each `4 + nv` doubles. Writes the clipped convex
// polygon to `out` (kMaxClipVerts vertices of kClipStride doubles) and returns its vertex count
// (0 when the triangle is entirely outside, else >= 3).
int clipTriangle(const double* const in[3], int nv, const GuardPlanes& guard, double* out);

}  // namespace penumbra::raster
