// Exact coverage of one stochastic sample: the triangle at the sample's time t and lens position
// (u, v), rasterized by the same arithmetic as the main pipeline (raster/setup.h, raster/clip.h).
//
// Time-continuous triangles: each vertex has a clip-space position at shutter open (t = 0) and at
// shutter close (t = 1), linear in between: c(t) = c0 + (c1 - c0) t (clip space is a linear image
// of world space for a fixed camera, so this is the world-space motion, projected).
// Thin lens: a point on the lens at (u, v) in the unit disk (or square: sample_pattern.h LensShape), seen through as a pinhole whose image
// plane is sheared so that the focus plane stays put, moves a clip-space vertex by
//     x += u kx (w - F),  y += v ky (w - F),  z and w unchanged,
// with F the focus distance (w is the view depth) and kx = R P00 / F, ky = R P11 / F for an aperture
// radius R and projection scales P00, P11. A vertex on the focus plane does not move; the circle of
// confusion grows linearly with |w - F| / w on screen. Pinhole: R = 0, nothing moves.
//
// Per-sample exactness: sampleCoverage() projects and snaps the three vertices with
// raster::projectVertex, assembles it as the pipeline's front end does (raster/assemble.h: the
// frustum reject, and homogeneous clipping when a vertex crosses the near/far plane, leaves the
// guard band or is behind the eye), and evaluates the same integer edge functions and top-left
// rule at the pixel centre as the tile stage (raster::coversPixel). The result equals the main pipeline's coverage of the triangle
// clipAt(t, u, v) at that pixel, bit for bit (tests/stochastic/coverage_test.cpp checks it).
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cstdint>
#include <glm/vec4.hpp>

#include "raster/assemble.h"
#include "raster/fragment.h"
#include "raster/setup.h"

namespace penumbra::stochastic {

struct ThinLens {
  float kx = 0.0f, ky = 0.0f;  // clip-space shear per unit of lens coordinate and of (w - F)
  float focusW = 1.0f;         // F: view depth in focus
  bool active() const { return kx != 0.0f || ky != 0.0f; }
};

// The lens of a perspective projection (P00 = proj[0][0], P11 = proj[1][1]) for an aperture radius
// and a focus distance in view units (both > 0; radius 0 is a pinhole).
ThinLens makeThinLens(float proj00, float proj11, float apertureRadius, float focusDistance);

// Clip position of a vertex at time t and lens position (u, v): c0 + (c1 - c0) t, then the lens
// shear. Written out so that every caller computes the same float bits: a static vertex (c0 == c1)
// gives c0 exactly, and with u = v = 0 or an inactive lens nothing is added.
inline glm::vec4 clipAt(const glm::vec4& c0, const glm::vec4& c1, float t, float u, float v, const ThinLens& lens) {
  glm::vec4 p(c0.x + (c1.x - c0.x) * t, c0.y + (c1.y - c0.y) * t, c0.z + (c1.z - c0.z) * t, c0.w + (c1.w - c0.w) * t);
  if (lens.active()) {
    const float d = p.w - lens.focusW;
    p.x += u * (lens.kx * d);
    p.y += v * (lens.ky * d);
  }
  return p;
}

// What the per-sample test needs besides the triangle: the viewport and its guard band.
struct SampleTarget {
  raster::Viewport vp;
  raster::GuardPlanes guard;
  raster::CullMode cull = raster::CullMode::None;
};
SampleTarget makeSampleTarget(int width, int height, raster::CullMode cull);

// The quick reject sampleCoverage starts with: true only when pixel centre (px, py) is certainly
// outside the triangle the exact test would snap (float approximations of the snapped positions
// with a bound on their error; anything near the guard band, the near or far plane or degenerate is
// left undecided, false). Exposed for its tests.
bool certainlyOutside(const glm::vec4 c[3], const SampleTarget& target, int px, int py);

// Coverage of pixel centre (px, py) by the triangle with clip vertices c[3] (submission order), as
// the main pipeline decides it; on coverage, `depth` receives z / w exactly as the tile stage
// writes it. Non-finite vertices cover nothing.
bool sampleCoverage(const glm::vec4 c[3], const SampleTarget& target, int px, int py, float& depth);

// The same, and the fragment the main pipeline's draw() would hand its fragment functor at that
// pixel: depth, facing, perspective-correct barycentrics and the interpolated varyings (nv floats
// per vertex, vary[k] for submitted vertex k; `out` holds kMaxVaryings + 3 floats and
// f.varyings points into it). Bit-identical to raster::Rasterizer::draw for unclipped and clipped
// triangles alike.
bool sampleFragment(const glm::vec4 c[3], const float* const vary[3], int nv, const SampleTarget& target, int px,
                    int py, raster::Fragment& f, float* out);

}  // namespace penumbra::stochastic
