// The multisampled G-buffer pass (`render --msaa N`): the ordinary instances drawn at N samples per
// pixel (raster::Rasterizer::drawSamples: exact coverage and depth per sample at the standard
// positions), then per pixel its samples grouped by the triangle they saw into up to
// stochastic::kMaxLayers layers, largest first -- the same layered frame a stochastic pass makes,
// so the shadow pass evaluates V per layer and shading blends the layers by their sample counts
// (a box filter over the pixel).
//
// Shading runs once per pixel per triangle seen, as multisampling hardware shades: a layer is one
// triangle's samples, its texel made from one sample, the one nearest the pixel centre (ties: the
// lower index), with that sample's perspective-correct barycentrics. So silhouettes of a mesh over
// itself are antialiased like those over other objects. A pixel seeing more triangles than layers
// adds the rest's samples to a kept layer of the same instance (the same surface, a neighbouring
// triangle) or, when none is, to its largest layer (counted in FrameStats::msaaPixelsMerged).
//
// Thread-safety: runs in the rasterizer's arena; one frame at a time.
#pragma once

#include <vector>

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/scene.h"
#include "raster/pipeline.h"
#include "shadows/light_view.h"

namespace penumbra::engine {

// samples in {2, 4, 8}. Fills frame.depth (sample 0's), gbuffer (layer 0), extraLayers, resolved,
// spp = samples, and the receivers of every layer.
void drawGBufferMultisample(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                            int samples, Frame& frame,
                            std::vector<raster::Image<shadows::Receiver>>& layerReceivers);

}  // namespace penumbra::engine
