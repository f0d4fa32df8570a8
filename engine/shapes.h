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

// A closed star-shaped surface about the origin: a cube's six faces, div x div quads each, mapped
// to the unit sphere with equal angles (cells of nearly equal size) and every direction d scaled
// by radius(d) (> 0). Fine, evenly tessellated curved meshes with concavities and protrusions
// (the shadow benches' creatures and folded blobs). Seam vertices of neighbouring faces are
// bit-identical; normals are area-weighted over the welded positions (no shading seams).
Mesh makeRadialSurface(int div, float (*radius)(glm::vec3 direction));

// A (p, q) torus knot tube: the curve ((R + r cos qt) cos pt, r sin qt, (R + r cos qt) sin pt),
// t in [0, 2 pi), around y; a tube of radius `tube` swept along it (`segments` steps along the
// curve, `sides` around the tube; the frame's normal is y projected off the tangent, which the
// curve never meets for R - r > 0). Closed and watertight (indices wrap). p, q coprime; tube small
// enough that the strands do not meet.
Mesh makeTorusKnot(int p, int q, float majorRadius, float minorRadius, float tube, int segments, int sides);

// Area-weighted vertex normals where vertices with bit-identical positions share one normal.
void computeWeldedNormals(Mesh& mesh);

// The triangle counts of the shapes above, without building them (caps are checked first).
inline size_t planeTriangles(int div) { return 2 * static_cast<size_t>(div) * static_cast<size_t>(div); }
inline size_t sphereTriangles(int rings, int segments) {
  return 2 * static_cast<size_t>(segments) * static_cast<size_t>(rings - 1);
}
inline size_t cylinderTriangles(int segments) { return 4 * static_cast<size_t>(segments); }
inline size_t torusTriangles(int rings, int segments) { return 2 * static_cast<size_t>(rings) * static_cast<size_t>(segments); }
inline size_t radialSurfaceTriangles(int div) { return 12 * static_cast<size_t>(div) * static_cast<size_t>(div); }

}  // namespace penumbra::engine
