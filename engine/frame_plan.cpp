#include "engine/frame_plan.h"

#include <algorithm>
#include <cmath>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>
#include <span>

#include "raster/timing.h"

namespace penumbra::engine {

namespace {

// World-space bounding box of a mesh under a transform.
void transformedBounds(const Mesh& m, const glm::mat4& transform, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? m.boundsMax.x : m.boundsMin.x, (c & 2) ? m.boundsMax.y : m.boundsMin.y,
                      (c & 4) ? m.boundsMax.z : m.boundsMin.z);
    const glm::vec3 w(transform * glm::vec4(p, 1.0f));
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
}

// Is the box entirely outside one plane of the clip volume (-w<=x<=w, -w<=y<=w, 0<=z<=w) in every
// one of the views? (One plane for all views together: the views of a lens's corners move a point's
// plane distances linearly, so a box outside one plane in all of them is outside it for every lens
// point; outside different planes in different views proves nothing.)
bool outsideFrustum(std::span<const glm::mat4> views, const glm::vec3& lo, const glm::vec3& hi) {
  std::vector<glm::vec4> c;
  for (const glm::mat4& viewProj : views)
    for (int i = 0; i < 8; ++i)
      c.push_back(viewProj * glm::vec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0f));
  auto allOut = [&](auto dist) {
    for (const glm::vec4& p : c)
      if (dist(p) >= 0.0f) return false;
    return true;
  };
  return allOut([](const glm::vec4& p) { return p.w + p.x; }) || allOut([](const glm::vec4& p) { return p.w - p.x; }) ||
         allOut([](const glm::vec4& p) { return p.w + p.y; }) || allOut([](const glm::vec4& p) { return p.w - p.y; }) ||
         allOut([](const glm::vec4& p) { return p.z; }) || allOut([](const glm::vec4& p) { return p.w - p.z; });
}

// Instances outside every view of the frame are culled before any vertex work; the rest are
// listed in `visible`.
void cullInstances(const Scene& scene, const FramePlan& plan, FrameStats& st, std::vector<size_t>& visible) {
  glm::mat4 views[4] = {plan.viewProj, plan.viewProj, plan.viewProj, plan.viewProj};
  if (plan.lensActive)
    for (int c = 0; c < 4; ++c)
      views[c] = throughLens(plan.viewProj, plan.lens, (c & 1) ? 1.0f : -1.0f, (c & 2) ? 1.0f : -1.0f);
  st.instances = scene.instances.size();
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    const size_t tris = mesh.indices.size() / 3;
    glm::mat4 ta, tb;
    plan.transforms(inst, ta, tb);
    glm::vec3 lo, hi, lo1, hi1;
    transformedBounds(mesh, ta, lo, hi);
    transformedBounds(mesh, tb, lo1, hi1);
    lo = glm::min(lo, lo1), hi = glm::max(hi, hi1);
    if (outsideFrustum(std::span<const glm::mat4>(views, plan.lensActive ? 4 : 1), lo, hi)) {
      ++st.instancesCulled;
      st.trianglesSkippedByCulling += tris;
      if (st.culledNames.size() < 8) {
        std::string name = inst.name;
        if (name.empty()) name.append("#").append(std::to_string(i));
        st.culledNames.push_back(std::move(name));
      }
      continue;
    }
    if (tris == 0) continue;  // nothing to draw (an empty index list would mean "non-indexed")
    visible.push_back(i);
    st.trianglesSubmitted += tris;
    if (!plan.at && inst.moves()) ++st.instancesMoving;
  }
}

}  // namespace

void FramePlan::transforms(const Instance& inst, glm::mat4& open, glm::mat4& close) const {
  if (at) {
    open = close = inst.transformAt(at->t);
  } else {
    open = inst.transform;
    close = inst.moves() ? *inst.transformClose : inst.transform;
  }
}

Camera chooseCamera(const Scene& scene, const RenderOptions& options, std::string* source) {
  if (options.camera) {
    if (source) *source = "options";
    return *options.camera;
  }
  if (scene.camera) {
    if (source) *source = "scene";
    return *scene.camera;
  }
  if (source) *source = "fitted to the objects' bounds";
  Camera cam;
  glm::vec3 lo, hi;
  if (!scene.objectBounds(lo, hi)) return cam;  // a ground far larger than the objects is left out
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
  // From the front, 25 degrees above, 30 degrees to the side; the bounding sphere fills the view in
  // its narrower direction (the horizontal one in a portrait image).
  const float el = 25.0f * std::numbers::pi_v<float> / 180.0f, az = 30.0f * std::numbers::pi_v<float> / 180.0f;
  const glm::vec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  cam.fovYDegrees = 40.0f;
  const float halfY = 0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f;
  const float aspect = options.height > 0 ? static_cast<float>(options.width) / static_cast<float>(options.height) : 1.0f;
  const float halfX = std::atan(std::tan(halfY) * aspect);
  const float dist = radius / std::sin(std::min(halfY, halfX));
  cam.eye = centre + dir * dist;
  cam.target = centre;
  return cam;
}

glm::mat4 viewProjection(const Camera& camera, const Scene& scene, double aspect) {
  float znear = camera.znear, zfar = camera.zfar;
  if (znear <= 0.0f || zfar <= 0.0f) {
    glm::vec3 lo, hi;
    float nearest = 0.01f, farthest = 100.0f;
    if (scene.worldBounds(lo, hi)) {
      // Distances along the view direction to the bounding sphere, with a margin.
      const glm::vec3 fwd = glm::normalize(camera.target - camera.eye);
      const glm::vec3 centre = (lo + hi) * 0.5f;
      const float radius = glm::length(hi - lo) * 0.5f;
      const float d = glm::dot(centre - camera.eye, fwd);
      farthest = std::max(d + radius * 1.01f, 1e-3f);
      nearest = std::max(d - radius * 1.01f, farthest * 1e-4f);
    }
    if (znear <= 0.0f) znear = nearest;
    if (zfar <= 0.0f) zfar = farthest;
  }
  glm::vec3 up = camera.up;
  const glm::vec3 fwd = glm::normalize(camera.target - camera.eye);
  if (std::abs(glm::dot(glm::normalize(up), fwd)) > 0.999f) up = std::abs(fwd.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const float fovy = camera.fovYDegrees * std::numbers::pi_v<float> / 180.0f;
  return glm::perspectiveRH_ZO(fovy, static_cast<float>(aspect), znear, zfar) * glm::lookAtRH(camera.eye, camera.target, up);
}

// x += u kx (w - F), y += v ky (w - F), with w = row 3 of the matrix and F times the point's
// homogeneous 1.
glm::mat4 throughLens(glm::mat4 m, const stochastic::ThinLens& lens, float u, float v) {
  if (!lens.active()) return m;
  for (int c = 0; c < 4; ++c) {
    const float w = m[c][3] - (c == 3 ? lens.focusW : 0.0f);
    m[c][0] += u * lens.kx * w;
    m[c][1] += v * lens.ky * w;
  }
  return m;
}

FramePlan planFrame(const Scene& scene, const ResolvedOptions& resolved, FrameStats& st) {
  const auto t0 = raster::Clock::now();
  const RenderOptions& options = resolved.options;
  FramePlan plan;
  plan.width = options.width;
  plan.height = options.height;
  plan.camera = chooseCamera(scene, options, &st.cameraSource);
  st.camera = plan.camera;
  if (scene.defaultLighting)
    st.lighting = "the scene has no light: a default key area light and a sky ambient were added (--no-default-light)";
  const Camera& cam = plan.camera;
  const double aspect = static_cast<double>(plan.width) / plan.height;
  const glm::mat4 pinholeViewProj = viewProjection(cam, scene, aspect);
  // The thin lens in clip space (stochastic/coverage.h): P00 and P11 of the projection.
  plan.tanHalf = std::tan(0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f);
  const float focus = cam.focusDistance > 0.0f ? cam.focusDistance : glm::length(cam.target - cam.eye);
  plan.lens = stochastic::makeThinLens(1.0f / (static_cast<float>(aspect) * plan.tanHalf), 1.0f / plan.tanHalf,
                                       cam.apertureRadius, focus);
  plan.at = options.at;
  plan.viewProj = plan.at ? throughLens(pinholeViewProj, plan.lens, plan.at->u, plan.at->v) : pinholeViewProj;
  plan.lensActive = plan.lens.active() && !plan.at;
  plan.pixelAngle = 2.0f * plan.tanHalf / static_cast<float>(plan.height);
  plan.casterTime = plan.at ? plan.at->t : 0.5f;
  plan.exposureScale = static_cast<float>(std::exp2(options.exposure));
  plan.toneMap = options.toneMap;
  plan.linearImage = options.linearImage;

  std::vector<size_t> visible;
  cullInstances(scene, plan, st, visible);
  st.msCull = raster::msSince(t0);

  // A stochastic pass only for motion or a lens; static instances seen through a pinhole keep the
  // ordinary pass.
  plan.stochasticPass = !plan.at && (st.instancesMoving > 0 || plan.lensActive || options.forceStochastic);
  st.stochastic = plan.stochasticPass;
  if (plan.at) {
    st.stochasticPlan = "skipped: a fixed-sample frame (t, u, v given)";
  } else if (!plan.stochasticPass) {
    st.stochasticPlan = "skipped: no visible instance moves and the camera is a pinhole";
  } else {
    st.stochasticPlan = std::to_string(st.instancesMoving) + " moving instance(s)" +
                        (plan.lensActive ? ", a lens (every instance defocused)" : ", a pinhole") +
                        (options.forceStochastic && st.instancesMoving == 0 && !plan.lensActive ? ", forced" : "");
  }
  for (size_t i : visible) {
    const bool viaStochastic =
        plan.stochasticPass && (plan.lensActive || !options.staticPath || scene.instances[i].moves());
    (viaStochastic ? plan.stochastic : plan.ordinary).push_back(i);
  }
  return plan;
}

}  // namespace penumbra::engine
