// Shared building blocks of the depth-map techniques (hard, PCF, PCSS, MVR): a depth map rendered
// from a LightView with the pipeline's depth-only pass, texel lookup, and the depth comparison with
// slope-scaled bias (Filament's surface_shadowing: the techniques share these and stay thin).
//
// Depth maps store near / depth (light_view.h): reversed, 0 = nothing drawn.
// Bias: a receiver at view depth d whose normal makes angle theta with the ray from the view origin
// spans about texelWorld(d) * tan(theta) of depth inside one texel, so it is compared as
//     lit  <=>  occluderDepth >= d - texelWorld(d) * (bias + slope_bias * min(tan(theta), 10)).
//
// Thread-safety: a ShadowMap is written by one thread (rendered, then prepareLookup) and then read
// from any number of threads; the other types here are values or pure functions, SkipCounter adds
// per thread.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "raster/depth_target.h"
#include "raster/kernels.h"
#include "shadows/kernel_taps.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

// A depth map and the constants of its lookups. It caches a pointer into its own depth image, so
// it cannot be copied (a copy would read the original's texels); a move carries the image and
// derives the pointer again.
struct ShadowMap {
  LightView view;
  raster::DepthTarget depth;

  ShadowMap() = default;
  ShadowMap(const ShadowMap&) = delete;
  ShadowMap& operator=(const ShadowMap&) = delete;
  ShadowMap(ShadowMap&& o) noexcept : view(o.view), depth(std::move(o.depth)) { relink(o); }
  ShadowMap& operator=(ShadowMap&& o) noexcept {
    view = o.view;
    depth = std::move(o.depth);
    relink(o);
    return *this;
  }

  // Call after rendering (renderDepthMap does): caches the lookup constants.
  void prepareLookup();
  // The stored value (near / depth; 0 = nothing) of the texel holding tangent-space point
  // (tanX, tanY) = (x/d, y/d), clamped to the map's edge.
  float stored(float tanX, float tanY) const {
    const float fx = std::min(maxX_, std::max(0.0f, ax_ * tanX + bx_));
    const float fy = std::min(maxY_, std::max(0.0f, ay_ * tanY + by_));
    return data_[static_cast<size_t>(fy) * stride_ + static_cast<size_t>(fx)];
  }
  // Depth along the axis of the nearest caster at that texel, +inf where nothing was drawn.
  float occluder(float tanX, float tanY) const { return view.depthOf(stored(tanX, tanY)); }
  // The column / row that stored() reads for a tangent coordinate.
  int column(float tanX) const { return static_cast<int>(std::min(maxX_, std::max(0.0f, ax_ * tanX + bx_))); }
  int row(float tanY) const { return static_cast<int>(std::min(maxY_, std::max(0.0f, ay_ * tanY + by_))); }
  // The lookup constants, for the SIMD tap kernels (kernel_taps.h); stored() reads the same texels.
  TapMap tapMap() const { return {data_, static_cast<int32_t>(stride_), ax_, bx_, ay_, by_, maxX_, maxY_}; }

 private:
  // After a move: the lookup constants of `o`, the pointer into this map's own image.
  void relink(ShadowMap& o) {
    const bool prepared = o.data_ != nullptr;
    stride_ = o.stride_, ax_ = o.ax_, bx_ = o.bx_, ay_ = o.ay_, by_ = o.by_, maxX_ = o.maxX_, maxY_ = o.maxY_;
    data_ = prepared ? &depth.image().at(0, 0) : nullptr;
    o.data_ = nullptr;
  }
  const float* data_ = nullptr;
  size_t stride_ = 0;
  float ax_ = 0, bx_ = 0, ay_ = 0, by_ = 0, maxX_ = 0, maxY_ = 0;
};

// Back-face culling in the light's views (the "cull" parameter of mvr and vwss): none; back (every
// face turned away from the light: right for closed meshes only, an open surface seen from behind
// disappears); auto (the faces of closed meshes only, Geometry::closed; the paper's choice for its
// closed characters).
enum class CasterCull { None, Back, Auto };
ParamSpec casterCullParam(int defaultIndex);
CasterCull casterCull(const ParamSet& params);
// A draw of the casters under a cull choice: its triangles (indices into the casters' positions,
// with their closed flags) and the rasterizer's cull mode for them. The light's views mirror the
// usual camera (right x up is the viewing direction, light_view.h): a face turned away from the
// light is CullMode::Front there.
struct CasterDraw {
  std::vector<uint32_t> indices;
  std::vector<uint8_t> closed;
  raster::CullMode cull = raster::CullMode::None;
  Geometry geometry(std::span<const glm::vec3> positions) const { return {positions, indices, closed}; }
};
// For views from points on the light, each culling in its own view: one draw (None, Back) or two
// (Auto: the closed meshes' triangles culled, the rest not), empty ones dropped; submission order
// kept within each.
// For one view standing in for every point of `light` (view-warped shadows' source view): a face is
// culled only when the whole light lies behind its plane (no light point sees its front) by more
// than 30 degrees (faces near edge-on fill the gaps a grazing front face leaves in the points),
// tested per triangle here, and one draw without the rasterizer's culling takes the rest -- a face
// seen from behind by the source view may still face a corner of the light.
std::vector<CasterDraw> casterDraws(const Geometry& casters, CasterCull cull, const RectLight* light = nullptr);

// Renders the context's kept casters into map.depth from map.view (a depth-only pass,
// DepthFunc::Greater, cleared to 0; no culling, or the draws given, into the same target) and adds
// the passes' stats to ctx.mapPasses.
void renderDepthMap(ShadowContext& ctx, ShadowMap& map, std::span<const CasterDraw> draws = {});

// A view from the light centre for techniques that look for occluders beside the receivers (a
// receiver sees the light through the map region of its search area, which reaches past the
// receivers' box): the frustum fitted to the receivers grows on each side by the largest search
// area (the farthest receiver, the nearest caster), at most 1.5 times the receivers' extent, and the
// resolution with it up to twice `size` per side (the texel density then halves at worst; beyond
// the frustum the edge texels stand for what lies there); note says how much it grew.
struct WidenedView {
  LightView view;
  glm::vec2 margin{0.0f};
  std::string note;  // " (frustum widened AxB for occluders beside the receivers, D of ...)"
};
WidenedView widenedView(const ShadowContext& ctx, int size);

struct BiasParams {
  float constant = 1.0f;  // texels
  float slope = 1.0f;     // texels per unit tan(theta)
  float normal = 0.0f;    // normal offset, texels
};
// "map_size", "bias", "slope_bias" and "normal_offset", shared by the depth-map techniques.
std::vector<ParamSpec> depthMapParams(int defaultSize, double defaultBias = 1.0, double defaultSlope = 1.5,
                                      double defaultNormal = 0.0);
BiasParams biasParams(const ParamSet& params);

// Normal offset (Holbert 2011): the point a receiver is looked up at, moved along its geometric
// normal n by b.normal texel footprints of `view` at its depth, so that the depth test compares a
// point off the receiver's own surface whatever the surface's slope within a texel (the depth bias
// can then stay small: no peter-panning at contact). n faces the side the light reaches.
inline glm::vec3 offsetAlongNormal(const LightView& view, glm::vec3 p, glm::vec3 n, BiasParams b) {
  if (b.normal == 0.0f) return p;
  const float d = view.toView(p).z;
  return d > 0.0f ? p + n * (b.normal * view.texelWorld(d)) : p;
}
// The view-space position of receiver r as the depth tests see it (offsetAlongNormal).
inline glm::vec3 lookupPoint(const LightView& view, const Receiver& r, BiasParams b) {
  return view.toView(offsetAlongNormal(view, r.position, r.normal, b));
}

// The receiver depth to compare occluders with: view-space v (v.z > 0), world-space normal n.
float biasedDepth(const LightView& view, glm::vec3 v, glm::vec3 n, BiasParams b);

// A receiver's depth test, in stored units so that a lookup needs no division: the receiver is lit
// by texel value z iff z <= threshold (z = near / depth grows towards the light).
//
// Receiver-plane depth (Isidoro 2006), for kernels that look up texels away from the receiver's
// own: the ray through tangent point (tx, ty) meets the receiver's tangent plane dot(nv, q) = k at
// 1/d = (nv.x tx + nv.y ty + nv.z) / k, which is linear in (tx, ty) -- and so is the stored value
// near / d. The biased depth d (1 - beta) (beta from biasedDepth) gives the threshold
//     near / (1 - beta) * clamp((nv.x tx + nv.y ty + nv.z) / k, 1 / (2 v.z), 2 / v.z),
// the clamp bounding the plane where it is seen edge-on.
class ReceiverPlane {
 public:
  ReceiverPlane(const LightView& view, glm::vec3 v, glm::vec3 n, BiasParams b);
  float threshold(float tanX, float tanY) const {
    return scale_ * std::min(hi_, std::max(lo_, a_ * tanX + b_ * tanY + c_));
  }
  // The threshold at the centre of the texel of `m` that (tanX, tanY) reads (as TexelCentres below):
  // for single-texel lookups.
  float texelCentreThreshold(const TapMap& m, float tanX, float tanY) const {
    const float fx = std::min(m.maxX, std::max(0.0f, m.ax * tanX + m.bx));
    const float fy = std::min(m.maxY, std::max(0.0f, m.ay * tanY + m.by));
    return threshold((std::floor(fx) + 0.5f - m.bx) / m.ax, (std::floor(fy) + 0.5f - m.by) / m.ay);
  }
  float tanX() const { return tx_; }
  float tanY() const { return ty_; }
  float depth() const { return d_; }
  // The constants of threshold(), for the SIMD tap kernels (kernel_taps.h).
  TapPlane tapPlane() const { return {a_, b_, c_, lo_, hi_, scale_}; }

 private:
  float a_, b_, c_, lo_, hi_, scale_, tx_, ty_, d_;
};

// The receiver-plane test above (a texel blocks when its stored value exceeds the threshold)
// without ReceiverPlane's upper clamp, for searches that reach far from the receiver
// (backprojection, occlusion textures): along a steep receiver plane a search area reaches to
// where the plane comes nearer the light than half the receiver's depth; clamped there, the
// plane's own texels would be blockers.
struct BlockerPlane {
  TapPlane p;
  float threshold(float tanX, float tanY) const { return p.scale * std::max(p.lo, p.a * tanX + p.b * tanY + p.c); }
};

// The accelerated test of the kernel techniques (PCF, PCSS): bounds of the stored values over every
// texel that taps inside the tangent-space box [x0, x1] x [y0, y1] can read (a min/max pyramid of
// the map, raster/kernels.h), against the bounds of the receiver's threshold over the box (linear,
// so its extremes are at the corners). When even the largest stored value passes the smallest
// threshold, every tap in the box is lit; when the smallest fails the largest, every tap is
// blocked: the kernel's result is then known (1 or 0) without its taps, bit for bit the same. A
// relative margin of 1e-5 covers the rounding of thresholds evaluated at other points.
enum class BoxTest { AllLit, AllBlocked, Mixed };
BoxTest testBox(const ShadowMap& map, const raster::MinMaxPyramid& pyramid, const ReceiverPlane& plane, float x0,
                float y0, float x1, float y1);
// The "minmax" parameter (on/off) of the techniques that use testBox: off runs every tap, to show
// what the test saves (the image is the same).
ParamSpec minMaxParam();
// Counts receivers resolved without taps, per thread, summed in a fixed order (integers).
class SkipCounter {
 public:
  void add() { ++counts_.local(); }
  size_t total() const {
    size_t n = 0;
    for (size_t c : counts_) n += c;
    return n;
  }
 private:
  tbb::enumerable_thread_specific<size_t> counts_{0};
};

// Receiver-plane depth bias for single-texel lookups (Isidoro 2006): 1 / depth of the receiver's
// tangent plane dot(nv, q) = k (view space, k = dot(nv, v) for the receiver's point v) along the
// ray through the centre of the texel that tangent point (tx, ty) reads. The map stored its depth
// there, not at the receiver's point: comparing with the plane's depth at the same centre removes
// the slope term of the bias (a planar receiver is never its own occluder, at any angle). Clamped
// to [1/(2 d), 2/d] where the plane is seen edge-on (d = 1 / invD, the receiver's depth).
// TexelCentres holds a map's lookup constants with the reciprocals the centres need, made once per
// map; invK = 1 / k once per receiver: a tap is then two floors and a few multiplications.
struct TexelCentres {
  TapMap m;
  float invAx = 0, invAy = 0;
  explicit TexelCentres(const TapMap& map) : m(map), invAx(1.0f / map.ax), invAy(1.0f / map.ay) {}
  float plane(float tx, float ty, glm::vec3 nv, float invK, float invD) const {
    const float fx = std::min(m.maxX, std::max(0.0f, m.ax * tx + m.bx));
    const float fy = std::min(m.maxY, std::max(0.0f, m.ay * ty + m.by));
    const float cx = (std::floor(fx) + 0.5f - m.bx) * invAx, cy = (std::floor(fy) + 0.5f - m.by) * invAy;
    const float inv = (nv.x * cx + nv.y * cy + nv.z) * invK;
    return std::min(2.0f * invD, std::max(0.5f * invD, inv));
  }
};

}  // namespace penumbra::shadows
