// Exponential soft shadow mapping (Shen, Feng & Yang, EGSR 2013; ../shared/papers/
// exponential-soft-shadow-mapping-shen2013.txt): PCSS in constant time per receiver on summed-area
// tables of the ESM basis.
//
// 1. Map (msMaps): normalized linear depth z from the light centre (prefiltered.h).
// 2. Pre-filter (msFilter): three channels per texel, e = exp(c (z - z_max)) (the ESM basis),
//    e z (the ESM-Z basis) and z, and their summed-area table: the SAT tile grid of the paper
//    (`sat=tiled`, raster/sat.h: mu-bit integers per tile, T = 2^floor((32 - mu) / 2); only the
//    tiles a receiver's search box reaches are built), or one table over the map in exact integers
//    (`sat=integer`, the paper's global normalization), double or float.
// 3. Evaluate (msEvaluate), per receiver at normalized depth z_r (its unbiased tangent plane: the
//    receiver's own surface must read 1, not exp(c bias)), with k = exp(c (z_max - z_r)):
//    - blocker search over the search box w_avg (the light's frustum from the receiver cut at the
//      near plane): s_f = k E[e] (the ESM test), and the average blocker depth (section 4.2)
//          Z_occ = (E[z] - k E[e z]) / (1 - s_f);
//    - penumbra from Z_occ as PCSS; V = k E[e] over the penumbra kernel (a box, the light's
//      rectangle projected; or `kernel=ellipse`: the penumbra's Gaussian convolved with the pixel's
//      footprint in the map, section 5.1, cut into rows of height H texels, Level0);
//    - micro-subdivision (section 5.2): a (sub-)kernel whose unclamped ESM value exceeds 1 + eps is
//      not planar (texels behind the receiver inside it); it is split into n x n sub-kernels, and
//      those still above 1 + eps take a 2 x 2 PCF (lit fraction and mean blocker depth of four taps)
//      instead; the kernel's results combine as the paper's d = sum d_i (1 - s_i) / sum (1 - s_i).
//      Every kernel is split (`split=always`), or, in the paper's order, only where the whole is
//      not planar (`split=adaptive`: faster, wrong blocker depths on complex occluders);
//    - contact (Penumbra's): where exp(-c (z_r - Z_occ)) > leak_tolerance the ESM tail would
//      leak; the penumbra kernel's n x n sub-kernels take PCF instead.
//    The exponent: c = R / (z_max - z_min) (section 7) from the map's depth range (its min/max
//    pyramid's top), or `exponent` when set. Bound: the stored values are in
//    [exp(-c (z_max - z_min)), 1], never above 1, and c (z_max - z_min) <= 80 keeps the smallest a
//    normal float (e^-80 = 1.8e-35 > FLT_MIN = 1.2e-38); the receiver factor k <= exp(80 / range)
//    is applied in double. Larger c would flush the nearest texels to 0 (as if fully blocked).
//
// Assumes blockers on one plane parallel to the light per receiver (PCSS's assumption: fused
// occluders at different depths get one average depth). Fails: contact within ~ln(100)/c of the
// occluder in normalized depth (the ESM tail leaks light; larger R helps until the non-planar
// fallback takes over); where the fallback's 2 x 2 taps alias; integer and float SATs of the whole
// map lose small values beside large ones (the reason for the tile grid). docs/techniques/essm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo essmTechnique();
}
