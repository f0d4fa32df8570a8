// Renderer: plans and renders one frame of a Scene on the raster/ pipeline, pass after pass, each
// in its own file with its inputs explicit:
//
//   options     resolveOptions (render_options.h): every option checked once, at the edge
//   plan        planFrame (frame_plan.h): camera, lens, instances culled by the view frustum, which
//               instances take the ordinary and which the stochastic pass
//   G-buffer    drawGBuffer (gbuffer_pass.h): the ordinary instances, world position, normal,
//               albedo, material per pixel
//   stochastic  runStochasticPass (stochastic_pass.h): moving (with a lens: all) instances through
//               the stochastic rasterizer; the G-buffer becomes up to three layers per pixel
//   shadows     runShadowPass (shadow_pass.h): per area light V at every layer's receivers from
//               the chosen technique (shadows/)
//   shading     shadeFrame (shading.h): lights times V, layers blended by their sample counts
//
// --stats prints the plan and what each pass did and skipped (FrameStats::report, frame.h).
// Conventions: world space right-handed, y up; clip space zero-to-one depth, depth test less.
// Thread-safety: a Renderer is not thread-safe (one frame at a time); frames are deterministic,
// byte-identical whatever the thread count.
#pragma once

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/render_options.h"
#include "engine/scene.h"
#include "raster/pipeline.h"

namespace penumbra::engine {

class Renderer {
 public:
  explicit Renderer(int threads = 0);
  // Renders with options already resolved (cannot fail on them).
  Frame render(const Scene& scene, const ResolvedOptions& options);
  // Resolves the options first: an Error names the bad one.
  Result<Frame> render(const Scene& scene, const RenderOptions& options);
  raster::Rasterizer& rasterizer() { return raster_; }

 private:
  raster::Rasterizer raster_;
};

// The accumulation-buffer reference of motion blur and depth of field (Haeberli and Akeley 1990):
// the average of n pinhole frames (RenderOptions::at) at the 3D point set t_i = (i + 0.5) / n,
// (u_i, v_i) = the concentric disk map of the radical inverses of i in bases 2 and 3. Linear
// radiance; each pixel summed in double in frame order (deterministic). n in [1, 65536].
Result<raster::ImageFloat4> accumulationReference(Renderer& renderer, const Scene& scene, RenderOptions options,
                                                  int n);

}  // namespace penumbra::engine
