// Variance soft shadow mapping (Yang, Dong, Feng, Seidel & Kautz, "Variance Soft Shadow Mapping",
// Pacific Graphics 2010) and summed-area variance shadow maps (Lauritzen, GPU Gems 3, ch. 8,
// 2007): PCSS on a summed-area table of the VSM moments (z, z^2) (raster/sat.h, double).
//
// vssm, per receiver at normalized depth z_r (prefiltered.h):
//   - blocker search in constant time: over the search box, mean mu and variance s^2 from the
//     table; p = the Chebyshev bound at z_r (moments.h) is the lit fraction, and the blockers'
//     mean depth follows from mu = p z_r + (1 - p) z_occ (the lit texels assumed at z_r):
//         z_occ = (mu - p z_r) / (1 - p);
//   - penumbra from z_occ (PCSS), V = the Chebyshev bound over the penumbra box;
//   - kernel subdivision (Yang et al., section 4.3) against non-planar receivers and blockers:
//     each kernel is split into n x n sub-kernels; a sub-kernel whose min/max pyramid bounds
//     (HSM) put every texel behind the receiver's plane is lit (1), every texel in front of it
//     blocked (0, its mean depth the blockers'), and only the others take the Chebyshev bound.
//     The receiver's depth is its tangent plane's at each sub-kernel's centre.
// savsm: Lauritzen's version: the blocker search by blocker_samples depth taps over the search box
//   (as PCSS), then one Chebyshev bound over the penumbra box from the table.
// Both: the Chebyshev bound errs towards light where several blockers at different depths share a
// kernel (light bleeding; bleed_reduction trims it and darkens penumbrae). min_variance guards the
// variance of tiny kernels (the table's rounding: raster/sat.h, roundingBound).
// docs/techniques/vssm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo vssmTechnique();
TechniqueInfo savsmTechnique();
}  // namespace penumbra::shadows
