// Bounds of a time-continuous, defocused triangle: which samples the stochastic rasterizer tests.
// Every bound is conservative: a sample outside it cannot be covered (coverage.h decides the rest),
// so all methods produce the same image and differ only in how many samples they test.
//
//  - footprint(): the pixel rectangle the triangle can cover for any (t, u, v) in a domain (a box
//    of times and lens positions). A vertex's clip position is multilinear in (t, u, v), so the
//    triangle at any point of the domain lies in the convex hull of its vertices at the domain's
//    corners (up to 8 per vertex); that hull is clipped against the near plane and projected. Used
//    over the whole shutter and lens (the box method) and over strata (the interval method).
//  - dualSpaceDomain(): Laine, Aila, Karras and Lehtinen 2011. For a screen rectangle (an 8x8
//    block), the times and lens positions at which the triangle can overlap it. In homogeneous
//    coordinates a point lies right of the screen line X when x - X w >= 0, and a triangle has
//    such a point only if one of its vertices does (whatever the signs of w: clipless). x - X w of
//    a vertex is linear in t for a fixed lens position and linear in u for a fixed time, so each
//    side of the rectangle excludes an interval of t (and of u, v) where every vertex lies beyond
//    it; the hull of what is left is the bound.
//
// A margin of 1/64 pixel covers snapping (1/512 pixel) and float rounding; tests compare every
// method with testing every sample of the screen (StochasticConfig::exhaustive).
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <glm/vec4.hpp>

#include "raster/bin.h"
#include "stochastic/coverage.h"

namespace penumbra::stochastic {

// A box of shutter times and lens positions.
struct Domain {
  float t0 = 0.0f, t1 = 1.0f;
  float u0 = -1.0f, u1 = 1.0f;
  float v0 = -1.0f, v1 = 1.0f;
};

// Inclusive pixel rectangles: raster's (raster/bin.h), which the binning of tiles takes.
using raster::PixelRect;
using raster::intersect;

// The triangle (clip positions c0 at shutter open, c1 at close) over the domain: the pixels whose
// centres it may cover, clamped to the viewport. motion = false ignores t (c0 is used).
PixelRect footprint(const glm::vec4 c0[3], const glm::vec4 c1[3], const Domain& d, const ThinLens& lens, bool motion,
                    int width, int height);

// Narrows d to the times and lens positions at which the triangle may cover a pixel centre of
// the rectangle r (pixels of a width x height viewport). False when nothing is left.
bool dualSpaceDomain(const glm::vec4 c0[3], const glm::vec4 c1[3], const ThinLens& lens, bool motion,
                     const PixelRect& r, int width, int height, Domain& d);

}  // namespace penumbra::stochastic
