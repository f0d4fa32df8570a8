// Procedural meshes: plane, box, sphere, cylinder, torus, centered on the origin in object space.
//
// Conventions (glTF's): right-handed, y up; triangles wind counter-clockwise seen from outside, so
// cross(b - a, c - a) points out of the solid; normals are unit length and outward; texcoords in
// [0, 1] with v down. Closed shapes (box, sphere, cylinder, torus) are watertight through their
// positions: vertices are duplicated where normals or texcoords differ (box corners, seams, cap
// rims, poles), but duplicates have bit-identical positions, so welding equal positions gives a
// closed 2-manifold in which every edge is used by exactly two triangles in opposite directions.
// Every returned mesh has its bounds computed and no material (-1).
//
// Preconditions (checked in debug builds; release builds raise counts to their minimum):
// sizes > 0, div >= 1, segments >= 3, rings >= 2 (sphere) or >= 3 (torus), minor < major radius.
//
// Thread-safety: pure functions.
#pragma once

#include <cstddef>
#include <glm/vec3.hpp>

#include "engine/scene.h"

namespace penumbra::engine {

// A sx-by-sz rectangle in the y = 0 plane facing +y, split into div x div quads (open surface).
// u runs along +x, v along +z.
Mesh makePlane(float sx, float sz, int div);

// An axis-aligned box of the given full extents: 24 vertices (4 per face, flat normals), 12 triangles.
Mesh makeBox(glm::vec3 size);

// A UV sphere: `rings` bands from pole (+y) to pole, `segments` slices around y. The poles get one
// triangle per slice (no degenerate triangles).
Mesh makeSphere(float radius, int rings, int segments);

// A capped cylinder around y, from y = -height / 2 to +height / 2, `segments` slices; flat caps
// with their own vertices (normals +-y).
Mesh makeCylinder(float radius, float height, int segments);

// A torus around y: the tube of radius `minorRadius` follows a circle of radius `majorRadius` in the
// y = 0 plane; `rings` steps around the major circle, `segments` around the tube.
Mesh makeTorus(float majorRadius, float minorRadius, int rings, int segments);

// The triangle counts of the shapes above, without building them (caps are checked first).
inline size_t planeTriangles(int div) { return 2 * static_cast<size_t>(div) * static_cast<size_t>(div); }
inline size_t sphereTriangles(int rings, int segments) {
  return 2 * static_cast<size_t>(segments) * static_cast<size_t>(rings - 1);
}
inline size_t cylinderTriangles(int segments) { return 4 * static_cast<size_t>(segments); }
inline size_t torusTriangles(int rings, int segments) { return 2 * static_cast<size_t>(rings) * static_cast<size_t>(segments); }

}  // namespace penumbra::engine
