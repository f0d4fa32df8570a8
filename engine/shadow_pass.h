// The shadow pass: per area light, the visible fraction V of the light at every receiver of the
// frame (every layer's, after a stochastic pass: layer l in rows [l h, (l + 1) h) of one receiver
// image) from the chosen technique (shadows/technique.h). The scene is turned into what shadows/
// consumes here: the light's region is fitted to the receivers, instances whose bounds cannot
// shadow them are culled before their triangles are flattened to world space (at the casters'
// time), and a light with no caster in reach takes no pass.
//
// Thread-safety: one frame at a time per rasterizer; runs in its arena.
#pragma once

#include <vector>

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/render_options.h"
#include "engine/scene.h"
#include "raster/pipeline.h"
#include "shadows/light_view.h"

namespace penumbra::engine {

// The receivers of every layer, stacked: the G-buffer's (one layer) or layerReceivers' (after a
// stochastic pass, a layer the pixel does not have is not a receiver).
shadows::ReceiverImage stackReceivers(raster::Rasterizer& raster, const Frame& frame,
                                      const std::vector<raster::Image<shadows::Receiver>>& layerReceivers);

// V per area light over `receivers` (1 on background texels); one LightShadowStats per light in
// frame.stats.shadows, msShadows.
std::vector<raster::ImageFloat> runShadowPass(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                                              const ResolvedOptions& options, const shadows::ReceiverImage& receivers,
                                              FrameStats& stats);

}  // namespace penumbra::engine
