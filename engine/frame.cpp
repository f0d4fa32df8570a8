#include "engine/frame.h"

#include <cstdio>

namespace penumbra::engine {

std::string FrameStats::report() const {
  std::string s;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "frame: %.2f ms (cull %.2f, G-buffer %.2f, shadows %.2f, shade %.2f); camera %s: eye (%.4g, %.4g, "
                "%.4g), target (%.4g, %.4g, %.4g), vertical fov %.4g deg%s\n"
                "  instances %zu: culled by view frustum before vertex work %zu (%zu triangles skipped), drawn %zu "
                "(%zu triangles)\n",
                msTotal, msCull, msGbuffer, msShadows, msShade, cameraSource.c_str(), static_cast<double>(camera.eye.x),
                static_cast<double>(camera.eye.y), static_cast<double>(camera.eye.z), static_cast<double>(camera.target.x),
                static_cast<double>(camera.target.y), static_cast<double>(camera.target.z),
                static_cast<double>(camera.fovYDegrees), camera.apertureRadius > 0.0f ? ", thin lens" : "",
                instances, instancesCulled,
                trianglesSkippedByCulling, instances - instancesCulled, trianglesSubmitted);
  s += buf;
  if (!culledNames.empty()) {
    s += "  culled:";
    for (const std::string& n : culledNames) s += " '" + n + "'";
    if (instancesCulled > culledNames.size()) s += " ...";
    s += "\n";
  }
  if (!lighting.empty()) s += "  lighting: " + lighting + "\n";
  s += gbuffer.report("G-buffer pass");
  for (size_t i = 0; i < shadows.size(); ++i) {
    const LightShadowStats& l = shadows[i];
    std::snprintf(buf, sizeof buf,
                  "  area light %zu: %s%s%s: %.2f ms (flatten %.2f, fit %.2f, maps %.2f, filter %.2f, evaluate %.2f)\n"
                  "    receivers in front %zu (beyond the views' 84-degree limit %zu), behind the light %zu; "
                  "instances culled by the light's region %zu; triangles flattened %zu, culled per triangle %zu, "
                  "kept %zu\n",
                  i, l.technique.c_str(), l.params.empty() ? "" : " ", l.params.c_str(),
                  l.msFlatten + l.msFit + l.times.total(), l.msFlatten, l.msFit, l.times.msMaps, l.times.msFilter,
                  l.times.msEvaluate, l.receivers, l.receiversOutside, l.receiversBehind, l.instancesCulled,
                  l.trianglesFlattened,
                  l.trianglesCulled, l.trianglesFlattened - l.trianglesCulled);
    s += buf;
    if (l.times.msPoints > 0 || l.times.msSplat > 0) {
      std::snprintf(buf, sizeof buf, "    maps: point generation %.2f ms, clearing and splatting %.2f ms\n",
                    l.times.msPoints, l.times.msSplat);
      s += buf;
    }
    if (l.trianglesMoving > 0) {
      std::snprintf(
          buf, sizeof buf,
          "    moving casters: %zu triangles, sampled over the whole shutter (motion-blurred shadows); "
          "receivers on moving surfaces at t = %.2f\n",
          l.trianglesMoving, static_cast<double>(l.casterTime));
      s += buf;
    }
    if (l.skipped) s += "    skipped: no shadow pass (" + l.skipReason + "); V = 1 in front of the light\n";
    for (const std::string& n : l.notes) s += "    " + n + "\n";
    if (l.maps.trianglesIn > 0) s += "  " + l.maps.report("shadow map passes (summed)");
  }
  std::snprintf(buf, sizeof buf, "  ordinary G-buffer pass: %zu instances (%zu triangles)\n", instancesOrdinary,
                trianglesOrdinary);
  s += buf;
  if (!msaaPlan.empty()) {
    s += "  multisampling: " + msaaPlan;
    if (msaa > 1) s += "; pixels whose samples of one instance joined another's layer (more triangles than layers): " + std::to_string(msaaPixelsMerged);
    s += "\n";
  }
  if (stochastic) {
    std::snprintf(buf, sizeof buf,
                  "  stochastic pass: %s; %zu instances (%zu triangles) through it, %.2f ms (the tiles include "
                  "the layers' G-buffer)\n",
                  stochasticPlan.c_str(), instancesStochastic, trianglesStochastic, msStochastic);
    s += buf;
    s += stoch.report(boundMethod);
  }
  std::string skipped;
  if (shadows.empty()) skipped += "shadow maps (no area light)";
  if (!stochastic) skipped += (skipped.empty() ? "" : ", ") + std::string("stochastic pass (") + stochasticPlan + ")";
  if (!linearImage) skipped += (skipped.empty() ? "" : ", ") + std::string("linear radiance image (only the 8-bit one is written)");
  if (!skipped.empty()) s += "  skipped passes: " + skipped + "\n";
  return s;
}

}  // namespace penumbra::engine
