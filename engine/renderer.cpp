#include "engine/renderer.h"

#include <algorithm>
#include <cmath>
#include <glm/vec4.hpp>

#include "engine/gbuffer_pass.h"
#include "engine/msaa_pass.h"
#include "engine/shading.h"
#include "engine/shadow_pass.h"
#include "engine/stochastic_pass.h"
#include "raster/timing.h"
#include "stochastic/sample_pattern.h"

namespace penumbra::engine {

Renderer::Renderer(int threads) : raster_({.threads = threads}) {}

Result<Frame> Renderer::render(const Scene& scene, const RenderOptions& options) {
  Result<ResolvedOptions> r = resolveOptions(options);
  if (!r) return r.error();
  return render(scene, *r);
}

Frame Renderer::render(const Scene& scene, const ResolvedOptions& options) {
  const auto t0 = raster::Clock::now();
  Frame frame;
  const FramePlan plan = planFrame(scene, options, frame.stats);
  frame.viewProj = plan.viewProj;
  std::vector<raster::Image<shadows::Receiver>> layerReceivers;  // of a layered frame (msaa, stochastic)
  const int msaa = options.options.msaa;
  if (msaa > 1 && !plan.stochasticPass) {
    frame.stats.msaaPlan = std::to_string(msaa) + " samples per pixel, one shaded texel per triangle seen";
    drawGBufferMultisample(raster_, scene, plan, msaa, frame, layerReceivers);
  } else {
    if (msaa > 1) frame.stats.msaaPlan = "not applied: the stochastic pass samples every pixel spp times";
    drawGBuffer(raster_, scene, plan, frame);
  }
  if (plan.stochasticPass) runStochasticPass(raster_, scene, plan, options, frame, layerReceivers);
  std::vector<raster::ImageFloat> visibility;
  if (!scene.areaLights.empty()) {
    const shadows::ReceiverImage receivers = stackReceivers(raster_, frame, layerReceivers);
    visibility = runShadowPass(raster_, scene, plan, options, receivers, frame.stats);
  }
  shadeFrame(raster_, scene, plan, visibility, frame);
  // Callers see layer 0's visibility.
  for (raster::ImageFloat& v : visibility) {
    if (v.height() == plan.height) {
      frame.visibility.push_back(std::move(v));
      continue;
    }
    raster::ImageFloat top(plan.width, plan.height);
    for (int y = 0; y < plan.height; ++y) std::copy(v.row(y), v.row(y) + plan.width, top.row(y));
    frame.visibility.push_back(std::move(top));
  }
  frame.stats.msTotal = raster::msSince(t0);
  return frame;
}

Result<raster::ImageFloat4> accumulationReference(Renderer& renderer, const Scene& scene, RenderOptions options, int n) {
  if (n < 1 || n > 65536) return Error{"accumulation reference", "frames must be in [1, 65536], got " + std::to_string(n)};
  const int w = options.width, h = options.height;
  options.at = stochastic::Sample{};
  Result<ResolvedOptions> resolved = resolveOptions(options);
  if (!resolved) return resolved.error();
  std::vector<glm::dvec4> sum(static_cast<size_t>(w) * static_cast<size_t>(h), glm::dvec4(0.0));
  auto radicalInverse = [](uint32_t i, uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    for (; i > 0; i /= base, f *= inv) r += f * (i % base);
    return r;
  };
  for (int i = 0; i < n; ++i) {
    stochastic::Sample at;
    at.t = static_cast<float>((i + 0.5) / n);
    double u, v;
    stochastic::concentricDisk(radicalInverse(static_cast<uint32_t>(i), 2), radicalInverse(static_cast<uint32_t>(i), 3),
                               u, v);
    at.u = static_cast<float>(u);
    at.v = static_cast<float>(v);
    resolved->options.at = at;
    const Frame f = renderer.render(scene, *resolved);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const raster::Float4& c = f.linear.at(x, y);
        sum[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] += glm::dvec4(c.r, c.g, c.b, c.a);
      }
  }
  raster::ImageFloat4 out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::dvec4 m = sum[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] / static_cast<double>(n);
      out.at(x, y) = {static_cast<float>(m.x), static_cast<float>(m.y), static_cast<float>(m.z), static_cast<float>(m.w)};
    }
  return out;
}

}  // namespace penumbra::engine
