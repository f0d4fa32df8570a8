// Multi-view rasterization: N depth maps rendered from stratified points on the light (a Hammersley
// set over its rectangle, or Poisson-disk points), V = the fraction of maps (and taps: pcf=5 adds
// the texel's 4 neighbours, the VWSS paper's MVR) in which the receiver is lit. It converges to
// the true V as N and the map resolution grow (up to bias and the sampling of the light), which
// makes it the accurate rasterized baseline. Memory stays at one map: each map is rendered (the
// back faces of closed meshes culled in its own view with cull=auto: the same map, fewer
// triangles), then every receiver's lit count is incremented, then the next map reuses the
// buffers; map rendering counts as "maps", the per-map lookups as "evaluate".
// docs/techniques/mvr.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {

TechniqueInfo mvrTechnique();

}  // namespace penumbra::shadows
