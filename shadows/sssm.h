// Stochastic soft shadow maps (Liktor, Spassov, Mückl and Dachsbacher 2015): the area light used as
// the lens of a thin-lens camera, so that one stochastic map samples the whole 4D shadow light
// field, then pre-filtered per filter plane with per-sample circles of confusion.
//
//  sample      the stochastic rasterizer (stochastic/) renders every surface from the light centre's
//              frustum with the light rectangle as a square lens focused on the plane at depth F:
//              texel k, one sample, holds the ray from light point L_k (4 x 4 texel blocks take
//              different strata of the light, section 7.1) through the texel's point of the focus
//              plane, and the depth d_k of the nearest surface it hits (exact: the ray against the
//              covering triangle's plane, in double; +inf when none). Coverage is exact per sample,
//              the bounding method a parameter (box, interval, dual; its STE in --stats).
//  reproject   each filter plane at depth D_i (planes uniform in 1/d or d over the receivers'
//              depths) gets every sample in one of two pools: in front (d_k < D_i: an occluder of
//              the plane), placed at the centre of its circle of confusion, its hit point seen from
//              the light centre t_k + L_k (1/d_k - 1/F) (or, as the paper, the texel its ray
//              crosses); or behind, at the crossing t_k + L_k (1/D_i - 1/F). Samples landing on one
//              texel are merged in sample order per band of rows (moments and radii averaged, the
//              count kept as the weight, section 7.4): deterministic, in parallel.
//  init        per sample the EVSM moments of d_k (section 5.1) and its circle of confusion on the
//              plane (Eq. 6): half-extents (w/2, h/2) |1/d_k - 1/D| in tangent units (a rectangle:
//              the light is one); a ray that meets nothing gets radius 0 and the moments of the
//              farthest receiver. Then widened to the smallest circle of a nearer sample that holds
//              it among 12 rotated Poisson-disc taps within 32 texels (section 7.2), smoothed by a
//              Gaussian of radius 2 texels; circles far beyond the filter's reach widen nothing.
//  levels      the finest level and `levels` coarser ones (2; 0: as many as the largest circle
//              needs); a sample moves to the next level with the weight of Eq. 8 (R_G = 8).
//  filter      per level, per texel of an active tile, the gather over the window the tile's
//              largest circle needs (at most R_G): the samples whose rectangle holds the texel,
//              weighted by count / the texels it covers (the discrete 1 / rho^2 of Eq. 7), so a
//              sample's weights sum to its count at any level; optional interleaved sampling.
//  resolve     a 3 x 3 box of each level's own sums, then coarsest to finest bilinear up-sampling
//              added to the finer level; per texel Eq. 7's normalized average of both pools (or the
//              coverage estimator: the front weights as the blocked fraction, the rest behind).
//  lighting    a receiver at depth d reads the two nearest planes' moments at its texel from the
//              light centre, evaluates the EVSM4 bound at its biased depth on each, and interpolates
//              linearly in 1/d (or d).
//  active      a camera pre-pass (the receivers) marks the tiles of each plane and level that the
//              lighting and the resolve read; only those are filtered (section 7.5), the rest is
//              skipped and counted; the image is the same bits either way.
//
// Thread-safety: as every technique (technique.h); deterministic at any thread count (sums in a
// fixed order, no atomics on floats).
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {

TechniqueInfo sssmTechnique();

}  // namespace penumbra::shadows
