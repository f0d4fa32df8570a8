// Exponential variance shadow maps (Lauritzen & McCool, "Layered Variance Shadow Maps", GI 2008,
// section 4; Lauritzen's EVSM): VSM (vsm.h) on exponentially warped depth. The warps
//     w+(z) = exp(c+ z),   w-(z) = -exp(-c- z)        (z = normalized depth in [0, 1], moments.h)
// are increasing, so the depth order and the Chebyshev bound carry over; the positive warp
// stretches the depth gap behind an occluder by exp(c+ (z_r - z_occ)), which shrinks the light
// bleeding of VSM by roughly that factor squared. "evsm2" stores (w+, w+^2) and uses the positive
// bound; "evsm4" also stores (w-, w-^2) and takes the min of both bounds (the negative warp
// handles receivers near the occluder's far side, where the positive one bleeds).
//
// The minimum variance is given in normalized depth^2 and mapped to the warped space with the
// warp's derivative at the receiver: minVariance * (c w(z_r))^2 (as in Lauritzen's sample code).
//
// Float32 bound: the largest stored moment is w+^2 = exp(2 c+ z) <= exp(2 c+); it must stay below
// FLT_MAX = 3.4e38 = e^88.72, so c+ <= 44.36. The parameter range is [0, 42] (2 c <= 84, e^84 =
// 3.0e36: a factor 100 of margin). w-^2 = exp(-2 c- z) <= 1 cannot overflow; with c- in the same
// range [0, 42] it stays >= e^-84 = 3.3e-37, above FLT_MIN = 1.2e-38 (no denormals). c = 0 makes
// that warp constant and its bound 1 (every receiver lit by it).
//
// Fails like VSM, less: light bleeding remains where the occluders' warped spread is comparable to
// the receiver's warped distance (occluders near the receiver's depth); no contact hardening
// (fixed filter width).
//
// Parameters: map_size, bias, slope_bias, filter_sigma (moments.h), exponent_pos (default 40),
// exponent_neg (evsm4 only, default 5), min_variance (default 1e-7), bleed_reduction (default 0.2).
// docs/techniques/evsm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo evsm2Technique();
TechniqueInfo evsm4Technique();
}  // namespace penumbra::shadows
