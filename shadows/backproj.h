// Backprojection soft shadow mapping (Guennebaud, Barthe & Paulin 2006; occlusion bitmasks after
// Schwarz & Stamminger 2007; the course slides in ../shared/papers): one depth map from the light
// centre, and for each receiver the occluders rebuilt from it and projected onto the light.
//
// 1. Search area (HSM): the map region through which the light can be seen from the receiver down
//    to the nearest possible blocker, in tangent units centred on the receiver with half-extents
//    (w/2, h/2) (1/z_min - 1/d_r). z_min starts at the near plane; the nearest depth over the area
//    gives a larger z_min and a smaller area (twice). A test of the final area's depth bounds
//    against the receiver plane settles a uniformly lit (V = 1) or uniformly blocked (V = 0) area
//    without micro-occluders. The bounds (search=): the min/max pyramid (HSM, loose), a min/max
//    stack (MSSM, exact; raster::MinMaxStack), or the pyramid up to 8 texels and a stack on its
//    level 2 beyond (YSM, default: exact to 4 texels, a sixteenth of MSSM's memory).
// 2. Micro-occluders: each texel of the area that is a blocker (nearer than the receiver plane's
//    biased depth at its centre, as PCF's test) is a micropatch: the texel's square of the map at
//    its depth z, parallel to the light. Seen from the receiver at depth d_r, it covers on the light
//    the axis-aligned rectangle d_r z / (d_r - z) * (t - t_r) for its tangent extents t. Search cap
//    (MSSM-like): an area wider than search_cap texels is searched at the pyramid level where it
//    is not, each coarse texel a patch at its nearest depth. micro=quads (Schwarz & Stamminger
//    2008): quads between neighbouring level-0 blocker texels' centres at their depths, a
//    triangle where one of the four is not a blocker; no cracks at depth discontinuities, the
//    outline half a texel in (quads_outline adds the outline texels' patches); a blocker texel in
//    no quad (one texel wide) is taken as its patch. Triangles mark the bitmask's samples by exact
//    edge tests.
// 3. Light occlusion: occlusion=area sums the rectangles' areas clipped to the light (overlaps
//    count twice: it over-darkens where occluders overlap as seen from the receiver);
//    occlusion=bitmask (default) marks, in a bitmask of K light samples (jittered on a grid of
//    cells, positions on a 1024^2 lattice of the light), the samples each rectangle covers, exactly
//    (two table lookups per axis); V = unmarked samples / K, so an overlap counts once. The pattern
//    is rotated per pixel (a toroidal shift from a hash of the pixel), deterministic. The light
//    samples below the receiver's tangent plane are marked too (V's definition, area_light.h); the
//    area variant multiplies by horizonFraction instead.
// Fails where one map cannot see the occluders: those hidden behind the nearest one from the light
// centre (the map keeps one layer), and gaps between micropatches at depth discontinuities (light
// leaks through the cracks of a surface seen edge-on, closed by gap_fill). docs/techniques/backproj.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo backprojTechnique();
}
