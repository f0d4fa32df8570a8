// Variance shadow maps (Donnelly & Lauritzen, "Variance Shadow Maps", I3D 2006): the moment map of
// (z, z^2) from the light centre (moments.h), pre-filtered with a Gaussian, and per receiver the
// one-sided Chebyshev bound on the fraction of the filter region at or beyond the receiver's depth,
// with Lauritzen's light-bleeding reduction. docs/techniques/vsm.md.
//
// Assumes the filter region's occluders lie at one depth in front of the receiver (a single planar
// occluder): then the bound is exact. Fails where it does not: two occluders at different depths
// in one filter region make a large variance and let light through (light bleeding); the penumbra
// width is the fixed filter width (no contact hardening); receivers closer than about
// sqrt(min_variance) * (zFar - zNear) behind their occluder are partly lit.
//
// Parameters: map_size, bias, slope_bias, filter_sigma (moments.h), min_variance (default 1e-5,
// normalized depth^2), bleed_reduction (default 0.2).
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo vsmTechnique();
}
