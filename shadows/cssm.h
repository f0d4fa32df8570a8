// Convolution soft shadow maps (Annen, Dong, Mertens, Bekaert, Seidel & Kautz, "Real-time,
// all-frequency shadows in dynamic scenes", SIGGRAPH 2008; on convolution shadow maps, Annen et al.,
// EGSR 2007): PCSS in constant time per receiver on summed-area tables of a Fourier basis of the
// shadow test.
//
// The test and its expansion. With u the depth normalized over the map's occupied range
// (u = (z - z_min) / (z_max - z_min), in [0, 1]) and u_r the receiver's, a texel is lit when
// u >= u_r, the step H(u - u_r). On (-1, 1) the step is the square wave
//     H(x) ~ 1/2 + 2 sum_{k=1..M} sigma_k sin(c_k x) / c_k,   c_k = pi (2k - 1),
// with damping sigma_k = exp(-alpha (k / M)^2) against ringing (CSM, section 3.3), and
// sin(c_k (u - u_r)) = sin(c_k u) cos(c_k u_r) - cos(c_k u) sin(c_k u_r) separates texel from
// receiver: the filtered test is a sum of filtered basis images sin(c_k u), cos(c_k u).
//
// 1. Map (msMaps): normalized linear depth from the light centre (prefiltered.h).
// 2. Pre-filter (msFilter): per texel the 2M basis values, the 2M' values u sin(c_k u), u cos(c_k u)
//    of the blocker search (M' = blocker_order <= M), u and an occupancy channel o (0 where no
//    caster covers the texel: counted lit, outside the series); one double summed-area table over
//    them (raster/sat.h; 4 M + 2 channels at most 34). Double: the basis values have both signs, so
//    the float table's cancellation would leave almost no bits at 1024^2.
// 3. Evaluate (msEvaluate), per receiver, over a box kernel (n x n sub-kernels, each with the
//    receiver's tangent-plane depth at its centre, `receiver_plane`):
//    - the blocker search over the search box (section 4 of CSSM): the blocked weight
//      B = sum o (1 - H) and the blocked depth D = sum o u (1 - H), both expanded with the first M'
//      terms, z_avg = D / B; no blocker where B is below 1e-3 of the area;
//    - penumbra from z_avg as PCSS; V = (sum o H + sum (1 - o)) / area over the penumbra box;
//    - sharpening (Annen's thesis, eq. 5.9): V^p with p = 1 + A exp(-B_s (u_r - u_avg)), darker
//      near contact where the truncated series leaks;
//    - with `minmax`, sub-kernels whose min/max pyramid bounds put every texel behind (in front of)
//      the receiver's plane are lit (blocked) without the series (Penumbra's addition, as VSSM's).
//
// Assumes what PCSS assumes (blockers on one plane per receiver) and a step smooth enough for M
// terms: the reconstructed test rises over about 1 / (2M) of the depth range. Fails: casters within
// that depth of a receiver shadow it partially (contact leaks light, a receiver's own tilted surface
// darkens it: the offset trades one for the other), ringing of the truncated series (damping trades
// it for a wider step), memory (4M + 2 doubles per texel: 151 MB at 1024^2 and M = 4).
// docs/techniques/cssm.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo cssmTechnique();
}
