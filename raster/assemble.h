// Assemble stage: from a submitted triangle's three projected vertices to what setup draws.
//
//   classify   the vertices' flags decide: drop it (a non-finite vertex), cull it (all three
//              outside one frustum plane), draw it as it is (no vertex needs clipping), or clip it;
//   clip       homogeneous clipping (clip.h) against near, far and the guard band, in double: the
//              polygon's vertices carry the varyings and the barycentrics of the submitted
//              triangle, and are projected and snapped (projectClipped); the polygon is drawn as a
//              fan from its first vertex, (0, i, i + 1) for i = 1 .. n - 2.
//
// The pipeline's front end (Rasterizer) and the stochastic rasterizer's exact per-sample test
// (stochastic/coverage.h) both assemble triangles with these functions, so a sample is decided by
// the same arithmetic as a pixel of the main pipeline.
//
// assembleTriangles runs both steps and setup (setup.h) over a range of a draw's triangles: the
// front end of one chunk, emitting its set-up triangles in submission order.
//
// Thread-safety: pure functions; safe from any thread (assembleTriangles writes only its output chunk).
#pragma once

#include <cstdint>
#include <glm/vec4.hpp>
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "raster/clip.h"
#include "raster/setup.h"
#include "raster/stats.h"

namespace penumbra::raster {

enum class Assembly : uint8_t {
  Direct,          // no vertex needs clipping: set up (v0, v1, v2) as submitted
  Clip,            // a vertex crosses near/far or leaves the guard band: clipTriangleToPolygon
  Invalid,         // a non-finite vertex: dropped (PassStats::trianglesDroppedInvalid)
  OutsideFrustum,  // every vertex outside one frustum plane, or nothing left after clipping
  Degenerate,      // a clipped vertex projects outside the guard band (w reached 0)
};

// Flags of the three vertices (projectVertex / projectVertexXY) -> Direct, Clip, Invalid or
// OutsideFrustum.
inline Assembly classifyTriangle(uint32_t f0, uint32_t f1, uint32_t f2) {
  const uint32_t any = f0 | f1 | f2;
  if (any & kNonFinite) return Assembly::Invalid;
  if (f0 & f1 & f2 & kFrustumMask) return Assembly::OutsideFrustum;
  return (any & kNeedsClip) ? Assembly::Clip : Assembly::Direct;
}

// A clipped triangle: its convex polygon, projected.
struct ClipPolygon {
  int count = 0;                                  // vertices, >= 3 when assembled
  ScreenVert screen[kMaxClipVerts];               // snapped, projectClipped
  double data[kMaxClipVerts * kClipStride];       // per vertex: clip x, y, z, w, nv varyings, 3 barycentrics
  const double* vertex(int i) const { return data + i * kClipStride; }
};

// Clips the triangle with clip positions c[3] (submission order) and nv varyings per vertex
// (vary[k] for vertex k; unused when nv == 0) and projects the polygon. Returns Clip with
// poly.count >= 3, OutsideFrustum when nothing is left, Degenerate when a vertex projects outside
// the guard band.
Assembly clipTriangleToPolygon(const glm::vec4 c[3], const float* const vary[3], int nv, const GuardPlanes& guard,
                               const Viewport& vp, ClipPolygon& poly);

// What the vertex stage leaves for the front end: per vertex its clip position, its projection
// (flags, snapped position, z/w, 1/w) and nv varyings.
struct VertexStageOutput {
  std::span<const glm::vec4> clip;
  std::span<const ScreenVert> screen;
  const float* varyings = nullptr;  // nv floats per vertex
  int nv = 0;
};

// An allocator whose resize() leaves new elements default-initialized (for these plain records:
// unwritten) instead of zeroed: the front end grows its record vectors by a setup group, lets
// setupLanes write the records it keeps, and shrinks them back, so zeroing would be pure waste
// (64 bytes a triangle). setupLanes writes every byte of a kept SetupTri (SetupLanes test).
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// The set-up triangles of one chunk of a draw, in submission order (the pieces of a clipped
// triangle in fan order). attrs (one per triangle) and clipVary (the varyings, then the submitted
// barycentrics, of the vertices the clipper made, nv + 3 floats each) are filled on request: the
// fragment stage needs them, a depth-only pass does not.
struct AssembledChunk {
  std::vector<SetupTri, DefaultInitAllocator<SetupTri>> tris;
  std::vector<SetupAttr, DefaultInitAllocator<SetupAttr>> attrs;
  std::vector<float> clipVary;
  PassStats stats;  // trianglesIn, dropped, culled, clipped, from clipping
};

// Triangles [first, last) of a draw (indices: 3 per triangle, or empty for vertex i = 3t + k),
// assembled and set up into `out`, which is cleared first. An index >= vertexCount drops its
// triangle (counted with the non-finite ones). Triangles drawn as they are are set up in lanes
// (setupLanes, with `simd`'s target), the clipper's pieces one by one (setupTriangle): the
// same records either way.
void assembleTriangles(const VertexStageOutput& vs, std::span<const uint32_t> indices, uint32_t vertexCount,
                       CullMode cull, const Viewport& vp, bool wantAttrs, uint64_t first, uint64_t last,
                       AssembledChunk& out, int64_t simd = 0);

}  // namespace penumbra::raster
