// Percentage-closer soft shadows (Fernando 2005; the course slides in ../shared/papers): one depth
// map from the light centre, then per receiver at view depth d_r
//   1. blocker search: blocker_samples depth comparisons over the region of the map through which
//      the light can be seen from the receiver down to the near plane; in tangent units (x/d) that
//      region is centred on the receiver and has half-extents (w/2, h/2) * (1/near - 1/d_r)
//      (a point at depth d_b on a segment from the receiver to the light point l projects to
//      x_r/d_r + l (1/d_b - 1/d_r));
//   2. penumbra estimate from the average blocker depth d_b: half-extents (w/2, h/2) * (1/d_b - 1/d_r)
//      (the same projection with the blockers assumed on one plane at d_b);
//   3. PCF with filter_samples comparisons over that region (receiver-plane depth per tap).
// No blocker found: V = 1. Sample points: a Hammersley set over the rectangle, shifted per pixel
// (Cranley-Patterson rotation by a hash of the pixel). Fails where its planar-blocker assumption
// fails: occluder fusion (blockers at several depths are averaged) and thin occluders the sparse
// blocker search misses. docs/techniques/pcss.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo pcssTechnique();
}
