// Exponential shadow maps (Annen, Mertens, Seidel, Flerackers, Kautz, "Exponential Shadow Maps",
// GI 2008; Salvi, "Rendering Filtered Shadows with Exponential Shadow Maps", ShaderX6 2008): the
// depth test H(z_occ - z_r) is approximated by exp(c (z_occ - z_r)), which separates into
// exp(c z_occ) * exp(-c z_r); the map of exp(c z_occ) (moments.h) can then be pre-filtered
// linearly, and per receiver
//     V = clamp(E[exp(c z_occ)] * exp(-c z_r), 0, 1)     (z = normalized depth in [0, 1]),
// computed in double as exp(log E[exp(c z_occ)] - c z_r), and flushed to 0 below 2^-24 (so that a
// full umbra is exactly 0).
//
// Assumes the receiver lies behind every occluder of its filter region (z_occ <= z_r, the
// "planarity" assumption of Annen et al., section 3): then the approximation errs only towards
// light near contact. Fails: receivers within about ln(1/V) / c of their occluder in normalized
// depth are lit (at c = 80, V > 0.01 for a gap below 0.058 of the depth range: lost contact
// shadows); texels farther than the receiver inside its filter region (next to an occluder's
// silhouette, or on a receiver tilted away from the light) each contribute exp(c (z_occ - z_r))
// > 1 and outweigh the occluders, so shadows shrink and leak at their edges (ESM errs towards
// light); fixed filter width, so no contact hardening.
//
// Float32 bound: the stored value exp(c z_occ) <= exp(c) must stay below FLT_MAX = 3.4e38 =
// e^88.72, so c <= 88 (the parameter's range is [1, 88]; e^88 = 1.65e38). The blur is a convex
// combination and cannot exceed it.
//
// Parameters: map_size, bias, slope_bias, filter_sigma (moments.h), exponent (default 80).
// docs/techniques/esm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo esmTechnique();
}
