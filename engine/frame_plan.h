// The plan of a frame, made before any pixel work: the camera (given, or fitted to the bounds),
// its projection and thin lens, the instances culled by the view frustum (their bounds over the
// shutter, against the frusta of the lens's four corners), and which visible instances take the
// ordinary G-buffer pass and which the stochastic pass (motion blur, depth of field): none when
// nothing visible moves and the camera is a pinhole; with a lens, all of them; otherwise only the
// moving ones. The plan's text is what --stats prints.
//
// Thread-safety: pure functions of the scene and the options; safe from any thread.
#pragma once

#include <glm/mat4x4.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/frame.h"
#include "engine/render_options.h"
#include "engine/scene.h"
#include "stochastic/coverage.h"

namespace penumbra::engine {

struct FramePlan {
  int width = 0, height = 0;
  Camera camera;
  glm::mat4 viewProj{1.0f};     // pinhole, or through the fixed sample's lens point
  float tanHalf = 0;            // tan(fovY / 2)
  float pixelAngle = 0;         // angle a pixel subtends (texture level of detail)
  stochastic::ThinLens lens;    // of the camera (inactive for a pinhole)
  bool lensActive = false;      // the stochastic pass samples the lens (not for a fixed sample)
  std::optional<stochastic::Sample> at;  // a fixed-sample frame: every instance at this (t, u, v)
  // Casters' time for the shadow pass: mid-shutter, or the fixed sample's time.
  float casterTime = 0.5f;
  float exposureScale = 1.0f;   // 2^exposure, for the 8-bit image
  ToneMap toneMap = ToneMap::None;
  bool linearImage = true;      // fill Frame::linear (RenderOptions::linearImage)
  bool stochasticPass = false;
  std::vector<size_t> ordinary, stochastic;  // instance indices, in scene order

  // An instance's transforms at shutter open and close (both at t for a fixed sample).
  void transforms(const Instance& inst, glm::mat4& open, glm::mat4& close) const;
};

// Plans the frame; fills the plan's part of `stats` (camera source, culling, instance counts, the
// stochastic plan's reason) and times it (msCull).
FramePlan planFrame(const Scene& scene, const ResolvedOptions& options, FrameStats& stats);

// The camera a frame uses: the override, else the scene's, else one framing the scene bounds
// from above and in front (the bounds fill the view).
Camera chooseCamera(const Scene& scene, const RenderOptions& options, std::string* source = nullptr);
// Projection with znear/zfar fitted to the scene bounds when the camera leaves them at 0.
glm::mat4 viewProjection(const Camera& camera, const Scene& scene, double aspect);
// The clip transform m seen through lens point (u, v) (stochastic/coverage.h's thin lens).
glm::mat4 throughLens(glm::mat4 m, const stochastic::ThinLens& lens, float u, float v);

}  // namespace penumbra::engine
