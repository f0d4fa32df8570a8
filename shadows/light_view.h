// What a light must cover and the views the techniques render from it.
//
// LightRegion (DESIGN.md: "shadow maps fitted to the receivers the camera sees; a light whose
// frustum holds no caster that can reach a visible receiver: no shadow maps"): from the G-buffer's
// receivers in front of the light, the convex region through which light can reach them, bounded by
// the light plane, the farthest receiver depth and four planes through the light's edges that
// enclose every receiver. A triangle outside it cannot shadow any visible receiver; it is culled
// before any pass (and whole instances are culled by their bounding boxes before flattening).
//
// LightView: a perspective view from a point on the light looking along the light normal (every
// view of a light has the same axes, so maps from several light points are parallel), its
// off-axis frustum fitted to the receivers' bounding box, limited to |tan| <= kMaxTan on each side
// (receivers outside, within ~6 degrees of the light plane, read the map's edge texels; they are
// counted in LightRegion::receiversOutside and --stats prints them).
// Depth is reversed and infinite: clip z = near, w = depth along the axis, so the stored value
// z/w = near / depth (1 at the near plane, towards 0 far away, DepthFunc::Greater, cleared to 0 =
// nothing there): float keeps a uniform relative precision at every distance.
//
// Thread-safety: LightRegion, LightView and CasterSet are plain values, read from any thread once
// made; fitRegion and cullCasters run TBB loops in the caller's arena and write only their result.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "raster/image.h"
#include "shadows/area_light.h"

namespace penumbra::shadows {

// One G-buffer texel as the shadow techniques see it.
struct Receiver {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f};    // the geometric (face) normal, unit, facing the viewer: the tangent
                             // plane of V's definition (area_light.h) and of every bias and offset;
                             // an interpolated shading normal is for shading only
  uint32_t valid = 0;        // 0: background, nothing to shade
  // The shutter time the receiver is at, when casters move (ShadowInputs::castersOpen): a point of
  // a moving surface is placed at one time (the frame's casters' time) and sees the casters then;
  // kWholeShutter (a static surface) sees them over the whole shutter, V averaged over time.
  float time = -1.0f;
  bool wholeShutter() const { return time < 0.0f; }
};
using ReceiverImage = raster::Image<Receiver>;

// World-space triangles: indices (3 per triangle) into positions.
struct Geometry {
  std::span<const glm::vec3> positions;
  std::span<const uint32_t> indices;
  // Per triangle, 1 where it belongs to a closed mesh wound counter-clockwise seen from outside
  // (engine Mesh::closed, in an instance that does not mirror it): its faces turned away from a
  // viewer may be culled without changing the nearest surface along any ray. Empty: unknown, as 0.
  std::span<const uint8_t> closed{};
  size_t triangles() const { return indices.size() / 3; }
  bool isClosed(size_t t) const { return t < closed.size() && closed[t] != 0; }
};

inline constexpr float kMaxTan = 10.0f;

// Light-space coordinates: (x, y) along the light's right and up from its centre, d along the normal.
inline glm::vec3 toLightSpace(const RectLight& light, glm::vec3 p) {
  const glm::vec3 r = p - light.center;
  return {glm::dot(r, light.right), glm::dot(r, light.up), glm::dot(r, light.normal())};
}

struct LightRegion {
  bool empty = true;               // no receiver in front of the light
  size_t receivers = 0;            // valid receivers in front of the light
  size_t receiversBehind = 0;      // valid receivers behind the light plane (unlit)
  size_t receiversOutside = 0;     // in front, but beyond |tan| = kMaxTan from the light centre
  glm::vec3 lo{0.0f}, hi{0.0f};    // light-space bounding box of the receivers in front (d > 0)
  // Side planes: x <= w/2 + d * sxHi, x >= -w/2 + d * sxLo (and y likewise); 0 < d <= hi.z.
  float sxLo = 0, sxHi = 0, syLo = 0, syHi = 0;

  // Could anything in the light-space box [lo, hi] (world box given by 8 corners) shadow a
  // receiver? Conservative: false only when every corner is outside one bounding plane.
  bool mayShadow(const RectLight& light, const glm::vec3 worldCorners[8]) const;
};

// Scans the receivers (tile-parallel in the caller's arena; deterministic).
LightRegion fitRegion(const RectLight& light, const ReceiverImage& receivers);

// Triangles of `geometry` that may shadow a receiver (their index triples, in order): those not
// entirely outside one of the region's planes, less those whose plane has the light strictly on
// one side and every receiver on that side (a ground under the scene cannot shadow what stands on
// it); and the smallest depth of the kept triangles' parts inside the region, for the near plane
// (0 when one reaches the light itself: views then use their smallest near plane).
// The kept triangles' parts inside the region are also boxed in light space ([lo, hi]; lo.z is
// minDepth), for views fitted to what can cast a shadow (makeLightView).
struct CasterSet {
  std::vector<uint32_t> indices;
  std::vector<uint8_t> closed;  // per kept triangle, Geometry::closed's flag (empty when it is)
  size_t trianglesIn = 0, trianglesCulled = 0;
  float minDepth = 0.0f;
  glm::vec3 lo{0.0f}, hi{0.0f};  // light space; lo.z > 0 when boxed()
  size_t trianglesKept() const { return indices.size() / 3; }
  bool boxed() const { return lo.z > 0.0f && lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; }
};
// With `receivers`, a large triangle whose plane the receivers' box cannot clear is tested against
// every receiver (TBB in the caller's arena; at most 64 such scans per call).
CasterSet cullCasters(const RectLight& light, const LightRegion& region, const Geometry& geometry,
                      const ReceiverImage* receivers = nullptr);

struct LightView {
  glm::vec3 origin{0.0f};           // world position (a point on the light)
  glm::vec3 right{1, 0, 0}, up{0, 0, 1}, axis{0, -1, 0};  // the light's frame; axis = normal
  glm::vec2 tanLo{-1.0f}, tanHi{1.0f};  // frustum extent at unit depth: x/d and y/d ranges
  float znear = 0.01f;
  int width = 0, height = 0;        // map resolution
  glm::mat4 viewProj{1.0f};         // world -> clip (reversed infinite depth, see above)
  // The sides of the map cut to the casters (makeLightView; bits as DepthTarget::fillBorder: 1
  // column 0 = tanLo.x, 2 the last column, 4 row 0 = tanHi.y, 8 the last row): their outermost
  // texels must be left empty after rendering (clearCasterCutBorder), since the receivers beyond
  // them read them.
  unsigned casterCut = 0;

  // View-space (x, y, depth) of a world point.
  glm::vec3 toView(glm::vec3 p) const {
    const glm::vec3 r = p - origin;
    return {glm::dot(r, right), glm::dot(r, up), glm::dot(r, axis)};
  }
  // Continuous map coordinates of a view-space point (pixel (i, j) centre at (i + 0.5, j + 0.5)).
  glm::vec2 toMap(glm::vec3 v) const {
    const float tx = v.x / v.z, ty = v.y / v.z;
    return {(tx - tanLo.x) / (tanHi.x - tanLo.x) * static_cast<float>(width),
            (tanHi.y - ty) / (tanHi.y - tanLo.y) * static_cast<float>(height)};
  }
  // World size of one texel at view depth d (the larger of its two sides).
  float texelWorld(float d) const {
    return d * std::max((tanHi.x - tanLo.x) / static_cast<float>(width), (tanHi.y - tanLo.y) / static_cast<float>(height));
  }
  // Depth along the axis of a stored map value (0 = nothing: +inf).
  float depthOf(float stored) const { return stored > 0.0f ? znear / stored : INFINITY; }
};

// The view from the light-space point (lightPoint.x, lightPoint.y, 0) (world units from the
// light centre along right and up) on the light, fitted to the region's receivers,
// width x height texels. Its near plane is `znear` (> 0). `margin` (tangent units) widens the
// frustum on every side beyond the receivers (for occluders a receiver sees outside them).
// With `casters` (boxed, and no margin) the frustum is also cut to the casters' box as this light
// point sees it, widened by kCasterFitMargin texels: a receiver outside it has nothing between it
// and this light point, and its lookup, clamped to the map's border, reads an empty texel (a
// rasterized caster covers texel centres inside it, a surfel at most kMaxSurfelReach texels
// beyond its point). Where the casters cover a small part of the receivers (objects on a wide
// ground) the same texels cover them finely.
inline constexpr int kCasterFitMargin = 6;
LightView makeLightView(const RectLight& light, const LightRegion& region, glm::vec2 lightPoint, float znear,
                        int width, int height, glm::vec2 margin = glm::vec2(0.0f),
                        const CasterSet* casters = nullptr);

// Empties the outermost texels of the sides of `view` cut to the casters (LightView::casterCut)
// in a map of `empty`-valued texels: a caster part outside the region (which shadows no receiver)
// may have been drawn there.
template <class T>
void clearCasterCutBorder(const LightView& view, raster::Image<T>& map, T empty) {
  const int w = map.width(), h = map.height();
  if (view.casterCut == 0 || w <= 0 || h <= 0) return;
  for (int x = 0; x < w; ++x) {
    if (view.casterCut & 4u) map.at(x, 0) = empty;
    if (view.casterCut & 8u) map.at(x, h - 1) = empty;
  }
  for (int y = 0; y < h; ++y) {
    if (view.casterCut & 1u) map.at(0, y) = empty;
    if (view.casterCut & 2u) map.at(w - 1, y) = empty;
  }
}

// The source view of view-warped multi-view shadows (Marrs et al. 2018, section 3.1): from behind
// the light's centre, moved back along the normal by D (Eq. 1, from `sample`'s field of view) so
// that its frustum contains the whole light and every receiver, with its near plane on the light
// (depth D), at the resolution that keeps `sample`'s texel size on surfaces at depth `znear` from
// the light (Eq. 3, per axis); where a side would pass maxSize both shrink by the same factor (the
// texels keep their shape).
LightView makeContainingView(const RectLight& light, const LightRegion& region, const LightView& sample, float znear,
                             int maxSize);

}  // namespace penumbra::shadows
