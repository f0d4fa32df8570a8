// Renderer: plans and renders one frame of a Scene on the raster/ pipeline.
//
// The plan, printed with --stats: camera (given or fitted to the bounds), instances culled by
// their world bounding box against the view frustum before any vertex work, one deferred
// G-buffer pass (world position, normal, albedo, material) over the visible instances; when a
// visible instance moves or the camera has an aperture, a stochastic pass (stochastic/) over the
// moving (with a lens: all) instances on top of it, whose resolve turns the G-buffer into up to
// three layers per pixel with their sample counts (docs/stochastic.md); then per
// area light its visibility V from the chosen shadow technique (shadows/: the light's region is
// fitted to the receivers the G-buffer holds; instances that cannot shadow them are culled before
// their triangles are flattened to world space; a light with no caster in reach takes no shadow
// pass), then a tile-parallel shading pass: Lambert diffuse plus Blinn-Phong specular from
// directional and point lights (unshadowed) and area lights (exact unshadowed irradiance times V,
// specular towards the light's centre), and a constant ambient term, each layer shaded once and the
// layers blended by their counts; the background where nothing was drawn. Linear color is
// written to an RGBA8 sRGB image and, on request, kept as float.
//
// Conventions: world space right-handed, y up; clip space zero-to-one depth, depth test less.
// Thread-safety: a Renderer is not thread-safe (one frame at a time); frames are deterministic,
// byte-identical whatever the thread count.
#pragma once

#include <glm/mat4x4.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "raster/pipeline.h"
#include "shadows/technique.h"
#include "stochastic/rasterizer.h"

namespace penumbra::engine {

struct RenderOptions {
  int width = 1280;    // pixels, [1, raster::kMaxTargetSize]
  int height = 720;    // pixels, [1, raster::kMaxTargetSize]
  std::optional<Camera> camera;  // overrides the scene's camera
  // Soft shadows of the area lights: a technique of the shadows/ registry ("reference" is the
  // ray-traced ground truth) or "none" (unshadowed). Unknown names and invalid parameters throw
  // std::invalid_argument (the CLI validates them first).
  std::string shadow = "pcss";
  std::string shadowParams;   // "name=value,name=value", checked against the technique's parameters
  std::string cacheDir;       // where techniques may cache results ("" = none)
  bool shadowCulling = true;  // cull casters outside each light's region (off: to measure the saving)
  // Motion blur and depth of field: the stochastic pass (stochastic/), taken when a visible
  // instance moves or the camera has an aperture.
  int spp = 16;  // samples per pixel, [1, stochastic::kMaxSpp]
  stochastic::BoundMethod bounds = stochastic::BoundMethod::DualSpace;
  int timeStrata = 0, lensStrata = 0;  // interval bounds (0: the defaults of StochasticConfig)
  int dualBlock = 4;                   // dual-space bounds: block side in pixels (power of 2, <= 64)
  uint32_t frame = 0;                  // seeds the sample pattern
  bool staticPath = true;         // static instances seen through a pinhole take the ordinary G-buffer pass
  bool staticShortcut = true;     // in the stochastic pass, one test per pixel for a static triangle (pinhole)
  bool forceStochastic = false;   // a stochastic pass even with no motion and a pinhole (tests)
  // Instead of a stochastic pass, the pinhole frame at one shutter time and lens position: every
  // instance at time t, the camera looking through lens point (u, v). Averaging many of these is
  // the accumulation-buffer reference of motion blur and depth of field.
  std::optional<stochastic::Sample> at;
  stochastic::StochasticDebug debug;  // optional per-sample / per-pixel outputs of the stochastic pass
};

// What the shadow computation of one area light did.
struct LightShadowStats {
  std::string technique, params;
  size_t instancesCulled = 0;        // whole instances outside the light's region, before flattening
  size_t trianglesFlattened = 0;     // world-space triangles handed to shadows/
  size_t trianglesCulled = 0;        // of those, outside the region (per triangle)
  size_t receivers = 0, receiversBehind = 0, receiversOutside = 0;
  bool skipped = false;
  std::string skipReason;
  shadows::StageTimes times;
  double msFlatten = 0, msFit = 0;
  std::vector<std::string> notes;
  raster::PassStats maps;
};

// One texel of the G-buffer.
struct GBufferTexel {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f};    // world space, unit, facing the viewer
  glm::vec3 albedo{0.0f};    // linear base color
  int32_t material = -1;     // -1: background
};

struct FrameStats {
  size_t instances = 0, instancesCulled = 0;
  size_t trianglesSubmitted = 0, trianglesSkippedByCulling = 0;
  std::vector<std::string> culledNames;  // first few
  raster::PassStats gbuffer;
  std::vector<LightShadowStats> shadows;  // one per area light
  double msCull = 0, msGbuffer = 0, msShadows = 0, msShade = 0, msTotal = 0;
  std::string cameraSource;  // "scene", "options" or "fitted to bounds"
  // The stochastic pass: why it ran or was skipped, what it drew and what it saved.
  bool stochastic = false;
  std::string stochasticPlan;
  size_t instancesMoving = 0, instancesStochastic = 0, trianglesStochastic = 0;
  size_t instancesOrdinary = 0, trianglesOrdinary = 0;  // drawn by the ordinary pass instead
  stochastic::StochasticStats stoch;
  std::string boundMethod;
  double msStochastic = 0;
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
};

// The camera a frame uses: the override, else the scene's, else one framing the scene bounds
// from above and in front (the bounds fill the view).
Camera chooseCamera(const Scene& scene, const RenderOptions& options, std::string* source = nullptr);
// Projection with znear/zfar fitted to the scene bounds when the camera leaves them at 0.
glm::mat4 viewProjection(const Camera& camera, const Scene& scene, double aspect);

class Renderer;

// The accumulation-buffer reference of motion blur and depth of field (Haeberli and Akeley 1990):
// the average of n pinhole frames (RenderOptions::at) at the 3D point set t_i = (i + 0.5) / n,
// (u_i, v_i) = the concentric disk map of the radical inverses of i in bases 2 and 3. Linear
// radiance; each pixel summed in double in frame order (deterministic). n in [1, 65536].
raster::ImageFloat4 accumulationReference(Renderer& renderer, const Scene& scene, RenderOptions options, int n);

class Renderer {
 public:
  explicit Renderer(int threads = 0);
  Frame render(const Scene& scene, const RenderOptions& options);
  raster::Rasterizer& rasterizer() { return raster_; }

 private:
  raster::Rasterizer raster_;
};

}  // namespace penumbra::engine
