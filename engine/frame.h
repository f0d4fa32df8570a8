// What a frame produces and reports: the G-buffer texel, the per-pass statistics and the Frame
// itself (images and buffers). Filled by the passes (frame_plan.h, gbuffer_pass.h,
// stochastic_pass.h, shadow_pass.h, shading.h), read by the command line, the benches and tests.
//
// Thread-safety: plain values; a Frame belongs to its caller (one writer at a time).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "raster/depth_target.h"
#include "raster/image.h"
#include "raster/stats.h"
#include "shadows/technique.h"
#include "stochastic/rasterizer.h"

namespace penumbra::engine {

// One texel of the G-buffer.
struct GBufferTexel {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f};    // shading normal: world space, unit, facing the viewer (shading only)
  glm::vec3 geometricNormal{0.0f};  // the face normal of the triangle seen, unit, facing the viewer:
                                    // the tangent plane V is defined by (docs/techniques/reference.md)
  glm::vec3 albedo{0.0f};    // linear base color
  int32_t material = -1;     // -1: background
  int32_t instance = -1;     // the scene's instance index; -1: background
  int32_t triangle = -1;     // the triangle of the instance's mesh seen (its index / 3); -1: background
  glm::vec3 bary{0.0f};      // perspective-correct barycentrics of that triangle's vertices 0, 1, 2
};

// What the shadow computation of one area light did.
struct LightShadowStats {
  std::string technique, params;
  size_t instancesCulled = 0;        // whole instances outside the light's region, before flattening
  size_t trianglesFlattened = 0;     // world-space triangles handed to shadows/
  size_t trianglesMoving = 0;        // of those, moving over the shutter (ShadowInputs::castersOpen)
  float casterTime = 0.5f;           // the frozen casters' time (and of receivers on moving surfaces)
  size_t trianglesCulled = 0;        // of those, outside the region (per triangle)
  size_t receivers = 0, receiversBehind = 0, receiversOutside = 0;
  bool skipped = false;
  std::string skipReason;
  shadows::StageTimes times;
  double msFlatten = 0, msFit = 0;
  std::vector<std::string> notes;
  raster::PassStats maps;
};

struct FrameStats {
  size_t instances = 0, instancesCulled = 0;
  size_t trianglesSubmitted = 0, trianglesSkippedByCulling = 0;
  std::vector<std::string> culledNames;  // first few
  raster::PassStats gbuffer;
  std::vector<LightShadowStats> shadows;  // one per area light
  double msCull = 0, msGbuffer = 0, msShadows = 0, msShade = 0, msTotal = 0;
  bool linearImage = true;   // the shading pass filled Frame::linear (RenderOptions::linearImage)
  std::string cameraSource;  // "scene", "options" or "fitted to the objects' bounds"
  Camera camera;             // the camera used (printed by report())
  std::string lighting;      // "" or how the scene was lit by default
  // The stochastic pass: why it ran or was skipped, what it drew and what it saved.
  bool stochastic = false;
  std::string stochasticPlan;
  size_t instancesMoving = 0, instancesStochastic = 0, trianglesStochastic = 0;
  size_t instancesOrdinary = 0, trianglesOrdinary = 0;  // drawn by the ordinary pass instead
  stochastic::StochasticStats stoch;
  std::string boundMethod;
  double msStochastic = 0;
  // Multisampling of the ordinary pass (msaa_pass.h): samples per pixel (1: none), pixels whose
  // samples saw more instances than layers, and what was done ("" for 1 sample).
  int msaa = 1;
  size_t msaaPixelsMerged = 0;
  std::string msaaPlan;
  // The plan and what each pass did and skipped, several lines (--stats).
  std::string report() const;
};

struct Frame {
  raster::ImageRgba8 color;   // sRGB encoded
  raster::ImageFloat4 linear; // linear radiance, alpha = coverage
  raster::Image<GBufferTexel> gbuffer;
  raster::DepthTarget depth;
  std::vector<raster::ImageFloat> visibility;  // per area light: V (1 on background texels); of layer 0
  // After a stochastic pass: per pixel the surfaces its samples saw (layer 0 is `gbuffer`, layer l
  // > 0 is extraLayers[l - 1]) and their sample counts; the color is their coverage-weighted blend.
  int spp = 0;  // 0: no stochastic pass
  raster::Image<stochastic::ResolvedPixel> resolved;
  std::vector<raster::Image<GBufferTexel>> extraLayers;
  FrameStats stats;
  glm::mat4 viewProj{1.0f};

  // The G-buffer texel of layer l at (x, y).
  const GBufferTexel& layerTexel(int l, int x, int y) const {
    return l == 0 ? gbuffer.at(x, y) : extraLayers[static_cast<size_t>(l - 1)].at(x, y);
  }
};

}  // namespace penumbra::engine
