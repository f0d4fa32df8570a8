// Post-filtered soft variance shadow mapping (../shared/papers/post-filtered-soft-variance-shadow-
// mapping-blog.txt): PCSS's three steps on a mip chain of the VSM moments (z, z^2) (raster/sat.h,
// mipChain4, sampled trilinearly), with no pre-filter beyond the mips.
//
// Per receiver at normalized depth z_r (prefiltered.h):
//   1. blocker search: one trilinear fetch of the moments over the search box (the level whose
//      texels are the box's size, log2 of its larger side); p = the Chebyshev bound at z_r; p > 0.99
//      means lit (V = 1); else z_occ = (mu - p z_r) / (1 - p) (the blog's average occluder depth).
//   2. penumbra from z_occ, the PCSS way for the rectangular light: half-extents
//      (w/2, h/2) (1/d_occ - 1/d_r) in tangent units, clamped to the search box. The blog is written
//      for directional lights (a fixed search area, the penumbra scaled by the occluder distance);
//      with an area light both follow from the light's size and the receiver's depth as in PCSS.
//   3. post-filter: `taps` Poisson-disk points over the penumbra ellipse (scaled per axis by the
//      half-extents), rotated per pixel (deterministic, from the pixel), each fetched at the mip
//      level of its share of the kernel (log2 of the taps' spacing in texels); the moments are
//      averaged, then one Chebyshev bound.
//   The blog's listings fetch at the receiver's centre instead of the tap's coordinate in both
//   loops, and its second listing drops the penumbra scale: this implementation does what the
//   text means (each tap at its own coordinate, the penumbra passed through).
// test=pcf is the blog's hybrid: steps 1 and 2 as above, then PCF with the same taps on the depth
// map (each against the receiver's plane), so the filter has no light bleeding.
// Fails: the mips are box-filtered, so wide kernels look blocky; Chebyshev bleeding where blockers
// at several depths share a tap's texel; thin casters leak near contact (the blog's own caveat).
// docs/techniques/pfsvsm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo pfsvsmTechnique();
}
