// The shading pass: per pixel, Lambert diffuse plus Blinn-Phong specular from the directional and
// point lights (unshadowed) and the area lights (their exact unshadowed irradiance, Lambert's
// polygon formula, times V; specular towards the light's centre), and the constant ambient term;
// the background where nothing was drawn. After a stochastic pass each of a pixel's layers is
// shaded once and the layers are blended by their sample counts (a box filter). Linear color
// (alpha = coverage) and its sRGB encoding.
//
// Thread-safety: one frame at a time per rasterizer; rows in parallel in its arena, deterministic.
#pragma once

#include <vector>

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/scene.h"
#include "raster/pipeline.h"

namespace penumbra::engine {

// visibility: per area light, V of every layer's receivers (layer l in rows [l h, (l + 1) h)).
// Fills frame.linear (when the plan keeps it), frame.color and stats.msShade.
void shadeFrame(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                const std::vector<raster::ImageFloat>& visibility, Frame& frame);

}  // namespace penumbra::engine
