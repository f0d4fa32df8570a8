#include "raster/assemble.h"

#include <algorithm>
#include <bit>

namespace penumbra::raster {

Assembly clipTriangleToPolygon(const glm::vec4 c[3], const float* const vary[3], int nv, const GuardPlanes& guard,
                               const Viewport& vp, ClipPolygon& poly) {
  // Vertex layout: position, varyings, then the barycentrics of the submitted triangle (the
  // fragment stage interpolates them to hand the functor submitted-triangle barycentrics).
  double in[3][kClipStride];
  const double* inPtr[3];
  for (int k = 0; k < 3; ++k) {
    in[k][0] = c[k].x, in[k][1] = c[k].y, in[k][2] = c[k].z, in[k][3] = c[k].w;
    for (int i = 0; i < nv; ++i) in[k][4 + i] = vary[k][i];
    for (int e = 0; e < 3; ++e) in[k][4 + nv + e] = e == k ? 1.0 : 0.0;
    inPtr[k] = in[k];
  }
  poly.count = clipTriangle(inPtr, nv + 3, guard, poly.data);
  if (poly.count < 3) return Assembly::OutsideFrustum;
  bool ok = true;
  for (int i = 0; i < poly.count; ++i) {
    poly.screen[i] = projectClipped(poly.vertex(i), vp);
    ok &= (poly.screen[i].flags & kOutGuard) == 0;
  }
  return ok ? Assembly::Clip : Assembly::Degenerate;
}

}  // namespace penumbra::raster

namespace penumbra::raster {

namespace {

// assembleTriangles with wantAttrs known at compile time: the per-triangle loop does not test it.
template <bool wantAttrs>
void assemble(const VertexStageOutput& vs, std::span<const uint32_t> indices, uint32_t vertexCount,
              CullMode cull, const Viewport& vp, uint64_t first, uint64_t last, AssembledChunk& out,
              int64_t simd) {
  out.tris.clear();
  out.attrs.clear();
  out.clipVary.clear();
  out.stats = PassStats{};
  PassStats& st = out.stats;
  st.trianglesIn = last - first;
  const bool indexed = !indices.empty();
  const int nv = vs.nv;
  const GuardPlanes guard = guardPlanes(vp);

  // Triangles drawn as they are wait in a group and are set up kSetupGroup at a time in lanes,
  // straight into out.tris; the group is flushed before a clipped triangle's pieces, so the order
  // stays the submission order.
  SetupGroupIn group{};
  uint32_t groupIdx[kSetupGroup][3];
  uint64_t verdicts[4] = {0, 0, 0, 0};  // per SetupResult
  int grouped = 0;
  auto flush = [&] {
    if (grouped == 0) return;
    const size_t base = out.tris.size();
    out.tris.resize(base + static_cast<size_t>(grouped));
    if (wantAttrs) out.attrs.resize(base + static_cast<size_t>(grouped));
    const uint32_t kept = setupLanes(group, grouped, cull, vp, out.tris.data() + base,
                                     wantAttrs ? out.attrs.data() + base : nullptr, verdicts, simd);
    const size_t end = base + static_cast<size_t>(std::popcount(kept));
    out.tris.resize(end);
    if (wantAttrs) {
      size_t i = base;
      for (uint32_t m = kept; m != 0; m &= m - 1, ++i) {
        SetupAttr& at = out.attrs[i];
        const uint32_t* idx = groupIdx[std::countr_zero(m)];
        for (int k = 0; k < 3; ++k) at.vary[k] = idx[at.order[k]];
        at.clipped = false;
      }
      out.attrs.resize(end);
    }
    grouped = 0;
  };
  // Setup of one of the clipper's pieces on its own; vref: the chunk-local varyings of its
  // vertices (kChunkLocalVarying, in out.clipVary).
  auto emit = [&](const ScreenVert& a, const ScreenVert& b, const ScreenVert& d, uint32_t prim, const uint32_t vref[3]) {
    SetupTri t;
    SetupAttr at;
    int order[3];
    const SetupResult res = setupTriangle(a, b, d, cull, vp, t, wantAttrs ? &at : nullptr, order);
    ++verdicts[static_cast<int>(res)];
    if (res != SetupResult::Ok) return;
    t.primitive = prim;
    out.tris.push_back(t);
    if (wantAttrs) {
      for (int k = 0; k < 3; ++k) {
        at.vary[k] = vref[order[k]];
        at.order[k] = static_cast<uint8_t>(order[k]);
      }
      at.clipped = true;
      out.attrs.push_back(at);
    }
  };

  ClipPolygon poly;
  for (uint64_t tri = first; tri < last; ++tri) {
    uint32_t idx[3];
    if (indexed) {
      for (int k = 0; k < 3; ++k) idx[k] = indices[tri * 3 + static_cast<uint64_t>(k)];
      if (std::max(std::max(idx[0], idx[1]), idx[2]) >= vertexCount) {
        ++st.trianglesDroppedInvalid;
        continue;
      }
    } else {
      for (int k = 0; k < 3; ++k) idx[k] = static_cast<uint32_t>(tri * 3 + static_cast<uint64_t>(k));
    }
    const ScreenVert& a = vs.screen[idx[0]];
    const ScreenVert& b = vs.screen[idx[1]];
    const ScreenVert& d = vs.screen[idx[2]];
    const uint32_t prim = static_cast<uint32_t>(tri);
    switch (classifyTriangle(a.flags, b.flags, d.flags)) {
      case Assembly::Invalid: ++st.trianglesDroppedInvalid; continue;
      case Assembly::OutsideFrustum: ++st.trianglesCulledFrustum; continue;
      case Assembly::Direct: {
        const ScreenVert* v[3] = {&a, &b, &d};
        for (int k = 0; k < 3; ++k) {
          group.x[k][grouped] = v[k]->x;
          group.y[k][grouped] = v[k]->y;
          group.z[k][grouped] = v[k]->z;
        }
        if constexpr (wantAttrs) {  // 1/w and the varyings' indices only serve the interpolation planes
          for (int k = 0; k < 3; ++k) {
            group.iw[k][grouped] = v[k]->iw;
            groupIdx[grouped][k] = idx[k];
          }
        }
        group.primitive[grouped] = prim;
        if (++grouped == kSetupGroup) flush();
        continue;
      }
      default: break;
    }
    flush();
    ++st.trianglesClipped;
    const glm::vec4 c[3] = {vs.clip[idx[0]], vs.clip[idx[1]], vs.clip[idx[2]]};
    const float* vary[3];
    for (int k = 0; k < 3; ++k) vary[k] = vs.varyings + static_cast<size_t>(idx[k]) * static_cast<size_t>(nv);
    const Assembly res = clipTriangleToPolygon(c, vary, nv, guard, vp, poly);
    if (res == Assembly::OutsideFrustum) {
      ++st.trianglesCulledFrustum;  // entirely outside the clip volume
      continue;
    }
    if (res == Assembly::Degenerate) {  // w reached 0: the polygon degenerates to the eye point
      ++st.trianglesCulledDegenerate;
      continue;
    }
    // Chunk-local varyings of the polygon's vertices.
    const int stride = nv + 3;
    const uint32_t base = static_cast<uint32_t>(out.clipVary.size() / static_cast<size_t>(stride));
    if (wantAttrs)
      for (int i = 0; i < poly.count; ++i)
        for (int c2 = 4; c2 < 4 + stride; ++c2) out.clipVary.push_back(static_cast<float>(poly.vertex(i)[c2]));
    for (int i = 1; i + 1 < poly.count; ++i) {
      const uint32_t ref[3] = {(base + 0) | kChunkLocalVarying, (base + static_cast<uint32_t>(i)) | kChunkLocalVarying,
                               (base + static_cast<uint32_t>(i) + 1) | kChunkLocalVarying};
      const size_t before = out.tris.size();
      emit(poly.screen[0], poly.screen[i], poly.screen[i + 1], prim, ref);
      st.trianglesFromClipping += out.tris.size() - before;
    }
  }
  flush();
  st.trianglesCulledFacing += verdicts[static_cast<int>(SetupResult::CulledFacing)];
  st.trianglesCulledDegenerate += verdicts[static_cast<int>(SetupResult::Degenerate)];
  st.trianglesCulledNoSample += verdicts[static_cast<int>(SetupResult::NoSample)];
  st.trianglesBinned = out.tris.size();
}

}  // namespace

void assembleTriangles(const VertexStageOutput& vs, std::span<const uint32_t> indices, uint32_t vertexCount,
                       CullMode cull, const Viewport& vp, bool wantAttrs, uint64_t first, uint64_t last,
                       AssembledChunk& out, int64_t simd) {
  if (wantAttrs)
    assemble<true>(vs, indices, vertexCount, cull, vp, first, last, out, simd);
  else
    assemble<false>(vs, indices, vertexCount, cull, vp, first, last, out, simd);
}

}  // namespace penumbra::raster
