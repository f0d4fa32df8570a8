// Multi-view rasterization: N depth maps rendered from stratified points on the light (a Hammersley
// set over its rectangle), V = the fraction of maps in which the receiver is lit. It converges to
// the true V as N and the map resolution grow (up to bias and the sampling of the light), which
// makes it the accurate rasterized baseline. Memory stays at one map: each map is rendered, then
// every receiver's lit count is incremented, then the next map reuses the buffers; map rendering
// counts as "maps", the per-map lookups as "evaluate". docs/techniques/mvr.md.
#pragma once

#include <glm/vec2.hpp>
#include <vector>

#include "shadows/technique.h"

namespace penumbra::shadows {

TechniqueInfo mvrTechnique();

// Light-space points (world units from the centre along right and up) of n stratified samples on a
// width x height light: Hammersley points over the rectangle. Shared by techniques that sample the
// light with views (MVR, VWSS) so they compare on the same light samples.
std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n);

}  // namespace penumbra::shadows
