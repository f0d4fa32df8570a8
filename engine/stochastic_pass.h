// The stochastic pass: the plan's stochastic instances (moving ones, or all with a lens) through
// the stochastic rasterizer (stochastic/rasterizer.h) on top of the ordinary pass's depth, and the
// G-buffer turned into up to three layers per pixel from each pixel's resolved surfaces.
//
// A layer's texel holds the G-buffer attributes of its samples, averaged (a defocused or moving
// texture is blurred like the edges); a value every sample agrees on is kept as it is, so a static
// surface gives the ordinary pass's bits. Its shadow receiver is the layer's median-time sample
// itself (a point on the surface: an average of points on a curved surface lies inside it and
// would shadow itself); a moving surface is looked up where the same surface point is at the
// casters' time (mid-shutter), so that it is not shadowed by its own mid-shutter copy.
//
// Thread-safety: one frame at a time per rasterizer; runs in its arena, the per-pixel work inside
// the tiles' tasks.
#pragma once

#include <vector>

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/render_options.h"
#include "engine/scene.h"
#include "raster/pipeline.h"
#include "shadows/light_view.h"

namespace penumbra::engine {

// Fills frame.resolved, frame.spp, frame.extraLayers, replaces frame.gbuffer with layer 0, and
// gives each layer's shadow receivers (kMaxLayers images); fills the pass's stats.
void runStochasticPass(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                       const ResolvedOptions& options, Frame& frame,
                       std::vector<raster::Image<shadows::Receiver>>& layerReceivers);

}  // namespace penumbra::engine
