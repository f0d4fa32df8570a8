#include "engine/renderer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <numbers>
#include <span>
#include <stdexcept>

#include "engine/texture.h"

namespace penumbra::engine {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// World-space bounding box of one instance.
void instanceBounds(const Scene& scene, const Instance& inst, glm::vec3& lo, glm::vec3& hi) {
  const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? m.boundsMax.x : m.boundsMin.x, (c & 2) ? m.boundsMax.y : m.boundsMin.y,
                      (c & 4) ? m.boundsMax.z : m.boundsMin.z);
    const glm::vec3 w(inst.transform * glm::vec4(p, 1.0f));
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

}  // namespace

Camera chooseCamera(const Scene& scene, const RenderOptions& options, std::string* source) {
  if (options.camera) {
    if (source) *source = "options";
    return *options.camera;
  }
  if (scene.camera) {
    if (source) *source = "scene";
    return *scene.camera;
  }
  if (source) *source = "fitted to bounds";
  Camera cam;
  glm::vec3 lo, hi;
  if (!scene.worldBounds(lo, hi)) return cam;
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
  // From the front, 25 degrees above, 30 degrees to the side; the bounding sphere fills the view.
  const float el = 25.0f * std::numbers::pi_v<float> / 180.0f, az = 30.0f * std::numbers::pi_v<float> / 180.0f;
  const glm::vec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  cam.fovYDegrees = 40.0f;
  const float dist = radius / std::sin(0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f);
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

std::string FrameStats::report() const {
  std::string s;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "frame: %.2f ms (cull %.2f, G-buffer %.2f, shadows %.2f, shade %.2f); camera %s\n"
                "  instances %zu: culled by view frustum before vertex work %zu (%zu triangles skipped), drawn %zu "
                "(%zu triangles)\n",
                msTotal, msCull, msGbuffer, msShadows, msShade, cameraSource.c_str(), instances, instancesCulled,
                trianglesSkippedByCulling, instances - instancesCulled, trianglesSubmitted);
  s += buf;
  if (!culledNames.empty()) {
    s += "  culled:";
    for (const std::string& n : culledNames) s += " '" + n + "'";
    if (instancesCulled > culledNames.size()) s += " ...";
    s += "\n";
  }
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
    if (l.skipped) s += "    skipped: no shadow pass (" + l.skipReason + "); V = 1 in front of the light\n";
    for (const std::string& n : l.notes) s += "    " + n + "\n";
    if (l.maps.trianglesIn > 0) s += "  " + l.maps.report("shadow map passes (summed)");
  }
  std::snprintf(buf, sizeof buf, "  ordinary G-buffer pass: %zu instances (%zu triangles)\n", instancesOrdinary,
                trianglesOrdinary);
  s += buf;
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
  if (!skipped.empty()) s += "  skipped passes: " + skipped + "\n";
  return s;
}

Renderer::Renderer(int threads) : raster_({.threads = threads}) {}

namespace {

// V of one area light over the G-buffer, with the instance-level culling and flattening that turn
// the Scene into what shadows/ consumes.
raster::ImageFloat shadowVisibility(raster::Rasterizer& raster, const Scene& scene, const shadows::ReceiverImage& rec,
                                    const shadows::RectLight& light, const RenderOptions& options,
                                    const shadows::TechniqueInfo* info, const shadows::ParamSet& params,
                                    float casterTime, LightShadowStats& st) {
  const auto t0 = Clock::now();
  shadows::LightRegion region;
  raster.run([&] { region = shadows::fitRegion(light, rec); });
  st.receivers = region.receivers;
  st.receiversBehind = region.receiversBehind;
  st.receiversOutside = region.receiversOutside;
  // Instances that may shadow a receiver, flattened to world space.
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  for (const Instance& inst : scene.instances) {
    const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
    const glm::mat4 transform = inst.moves() ? inst.transformAt(casterTime) : inst.transform;
    glm::vec3 corners[8];
    for (int c = 0; c < 8; ++c)
      corners[c] = glm::vec3(transform * glm::vec4((c & 1) ? m.boundsMax.x : m.boundsMin.x,
                                                        (c & 2) ? m.boundsMax.y : m.boundsMin.y,
                                                        (c & 4) ? m.boundsMax.z : m.boundsMin.z, 1.0f));
    if (m.indices.empty()) continue;
    if (options.shadowCulling && !region.mayShadow(light, corners)) {
      ++st.instancesCulled;
      continue;
    }
    const uint32_t base = static_cast<uint32_t>(positions.size());
    for (const glm::vec3& p : m.positions) positions.push_back(glm::vec3(transform * glm::vec4(p, 1.0f)));
    for (uint32_t i : m.indices) indices.push_back(base + i);
  }
  st.trianglesFlattened = indices.size() / 3;
  st.msFlatten = msSince(t0);
  if (!info) {  // "none": unshadowed
    raster::ImageFloat v(rec.width(), rec.height(), 1.0f);
    return v;
  }
  shadows::ShadowInputs in;
  in.casters = {positions, indices};
  in.receivers = &rec;
  in.light = light;
  in.cacheDir = options.cacheDir;
  in.cullCasters = options.shadowCulling;
  shadows::ShadowResult r = shadows::computeShadows(raster, in, *info, params);
  st.trianglesCulled = r.trianglesCulled;
  st.skipped = r.skipped;
  st.skipReason = r.skipReason;
  st.times = r.times;
  st.msFit = r.msFit;
  st.notes = std::move(r.notes);
  st.maps = r.mapPasses;
  return std::move(r.visibility);
}

}  // namespace

namespace {

// What the G-buffer needs of one instance: material, texture, normal matrices and the texture's
// texels per world unit of each triangle (its level of detail).
struct InstanceShading {
  const Material* mat = nullptr;
  const Texture* tex = nullptr;
  int32_t material = -1;  // the G-buffer's material index
  glm::mat4 t0{1.0f}, t1{1.0f};
  glm::mat3 n0{1.0f}, n1{1.0f};
  bool moves = false, hasUv = false;
  std::vector<float> texelsPerUnit;
};

InstanceShading prepareInstance(const Scene& scene, const Instance& inst, const glm::mat4& t0, const glm::mat4& t1,
                                const Material& defaultMaterial) {
  InstanceShading sh;
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  const int matIndex = mesh.material;
  sh.mat = matIndex >= 0 ? &scene.materials[static_cast<size_t>(matIndex)] : &defaultMaterial;
  sh.tex = sh.mat->baseColorTexture >= 0 ? &scene.textures[static_cast<size_t>(sh.mat->baseColorTexture)] : nullptr;
  sh.material = matIndex < 0 ? static_cast<int32_t>(scene.materials.size()) : matIndex;
  sh.t0 = t0, sh.t1 = t1;
  sh.moves = t0 != t1;
  sh.n0 = glm::transpose(glm::inverse(glm::mat3(t0)));
  sh.n1 = sh.moves ? glm::transpose(glm::inverse(glm::mat3(t1))) : sh.n0;
  sh.hasUv = !mesh.texcoords.empty();
  // Texture level of detail: texels per world unit from each triangle's uv and world areas (at
  // shutter open), times the world size of a pixel at the fragment's distance (isotropic).
  if (sh.tex && sh.hasUv) {
    const float texSize = static_cast<float>(sh.tex->mips[0].width() * sh.tex->mips[0].height());
    sh.texelsPerUnit.resize(mesh.indices.size() / 3);
    for (size_t t = 0; t < sh.texelsPerUnit.size(); ++t) {
      const uint32_t a = mesh.indices[t * 3], b = mesh.indices[t * 3 + 1], c = mesh.indices[t * 3 + 2];
      const glm::vec3 pa(t0 * glm::vec4(mesh.positions[a], 1)), pb(t0 * glm::vec4(mesh.positions[b], 1)),
          pc(t0 * glm::vec4(mesh.positions[c], 1));
      const float worldArea = glm::length(glm::cross(pb - pa, pc - pa));
      const glm::vec2 ua = mesh.texcoords[a], ub = mesh.texcoords[b], uc = mesh.texcoords[c];
      const float uvArea = std::abs((ub.x - ua.x) * (uc.y - ua.y) - (ub.y - ua.y) * (uc.x - ua.x)) * texSize;
      sh.texelsPerUnit[t] = worldArea > 0.0f ? std::sqrt(uvArea / worldArea) : 0.0f;
    }
  }
  return sh;
}

constexpr int kGbufferVaryings = 8;  // world position, world normal, uv
constexpr uint32_t kStochasticTriangleLimit = 0xFFFFFFF0u;  // above: kStaticSurface, kNoTriangle

// The G-buffer varyings of vertex i at shutter time t: positions and normals move on straight
// lines (a static instance gives the shutter-open values bit for bit).
void vertexVaryings(const Mesh& mesh, const InstanceShading& sh, uint32_t i, float t, float* v) {
  const glm::vec4 p(mesh.positions[i], 1.0f);
  glm::vec4 wp = sh.t0 * p;
  glm::vec3 n = sh.n0 * mesh.normals[i];
  if (sh.moves) {
    const glm::vec4 wp1 = sh.t1 * p;
    const glm::vec3 n1 = sh.n1 * mesh.normals[i];
    wp = glm::vec4(wp.x + (wp1.x - wp.x) * t, wp.y + (wp1.y - wp.y) * t, wp.z + (wp1.z - wp.z) * t, 1.0f);
    n = glm::vec3(n.x + (n1.x - n.x) * t, n.y + (n1.y - n.y) * t, n.z + (n1.z - n.z) * t);
  }
  v[0] = wp.x, v[1] = wp.y, v[2] = wp.z;
  v[3] = n.x, v[4] = n.y, v[5] = n.z;
  const glm::vec2 uv = sh.hasUv ? mesh.texcoords[i] : glm::vec2(0.0f);
  v[6] = uv.x, v[7] = uv.y;
}

// One G-buffer texel from a fragment (the ordinary pass and the stochastic layers alike).
GBufferTexel gbufferTexel(const InstanceShading& sh, const raster::Fragment& f, const glm::vec3& eye,
                          float pixelAngle) {
  GBufferTexel g;
  g.position = glm::vec3(f.varyings[0], f.varyings[1], f.varyings[2]);
  glm::vec3 n(f.varyings[3], f.varyings[4], f.varyings[5]);
  const float len = glm::length(n);
  n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);
  const glm::vec3 toEye = eye - g.position;
  if (glm::dot(n, toEye) < 0.0f) n = -n;  // two-sided: the normal faces the viewer
  g.normal = n;
  glm::vec4 base = sh.mat->baseColorFactor;
  if (sh.tex) {
    float lod = 0.0f;
    if (!sh.texelsPerUnit.empty()) {
      const float pixelWorld =
          glm::length(toEye) * pixelAngle / std::max(std::abs(glm::dot(n, glm::normalize(toEye))), 0.25f);
      const float texels = sh.texelsPerUnit[f.primitive] * pixelWorld;
      lod = texels > 0.0f ? std::max(std::log2(texels), 0.0f) : 0.0f;
    }
    base *= sampleBilinear(*sh.tex, glm::vec2(f.varyings[6], f.varyings[7]), lod);
  }
  g.albedo = glm::vec3(base);
  g.material = sh.material;
  return g;
}

// The clip transform seen through lens point (u, v): x += u kx (w - F), y += v ky (w - F), with
// w = row 3 of the matrix and F times the point's homogeneous 1.
glm::mat4 throughLens(glm::mat4 m, const stochastic::ThinLens& lens, float u, float v) {
  if (!lens.active()) return m;
  for (int c = 0; c < 4; ++c) {
    const float w = m[c][3] - (c == 3 ? lens.focusW : 0.0f);
    m[c][0] += u * lens.kx * w;
    m[c][1] += v * lens.ky * w;
  }
  return m;
}

}  // namespace

Frame Renderer::render(const Scene& scene, const RenderOptions& options) {
  if (options.spp < 1 || options.spp > stochastic::kMaxSpp)
    throw std::invalid_argument("samples per pixel must be in [1, " + std::to_string(stochastic::kMaxSpp) + "]");
  const auto t0 = Clock::now();
  Frame frame;
  FrameStats& st = frame.stats;
  const int w = options.width, h = options.height;
  const Camera cam = chooseCamera(scene, options, &st.cameraSource);
  const double aspect = static_cast<double>(w) / h;
  const glm::mat4 pinholeViewProj = viewProjection(cam, scene, aspect);
  // The thin lens in clip space (stochastic/coverage.h): P00 and P11 of the projection.
  const float tanHalf = std::tan(0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f);
  const float focus = cam.focusDistance > 0.0f ? cam.focusDistance : glm::length(cam.target - cam.eye);
  const stochastic::ThinLens lens =
      stochastic::makeThinLens(1.0f / (static_cast<float>(aspect) * tanHalf), 1.0f / tanHalf, cam.apertureRadius, focus);
  const bool fixedSample = options.at.has_value();
  frame.viewProj = fixedSample ? throughLens(pinholeViewProj, lens, options.at->u, options.at->v) : pinholeViewProj;
  const glm::mat4 viewProj = frame.viewProj;
  // Instance transforms at shutter open and close (one time only for a fixed-sample frame).
  auto transforms = [&](const Instance& inst, glm::mat4& a, glm::mat4& b) {
    if (fixedSample) {
      a = b = inst.transformAt(options.at->t);
    } else {
      a = inst.transform;
      b = inst.moves() ? *inst.transformClose : inst.transform;
    }
  };
  const bool lensActive = lens.active() && !fixedSample;

  // Cull instances against the view frustum before any vertex work: their bounds over the shutter,
  // against the frusta of the lens's four corners (the clip planes' distances are linear in u, v).
  glm::mat4 cullViews[4] = {viewProj, viewProj, viewProj, viewProj};
  if (lensActive)
    for (int c = 0; c < 4; ++c) cullViews[c] = throughLens(viewProj, lens, (c & 1) ? 1.0f : -1.0f, (c & 2) ? 1.0f : -1.0f);
  std::vector<size_t> visible;
  st.instances = scene.instances.size();
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const size_t tris = scene.meshes[static_cast<size_t>(inst.mesh)].indices.size() / 3;
    glm::mat4 ta, tb;
    transforms(inst, ta, tb);
    glm::vec3 lo, hi, lo1, hi1;
    Instance at0 = inst, at1 = inst;
    at0.transform = ta, at1.transform = tb;
    instanceBounds(scene, at0, lo, hi);
    instanceBounds(scene, at1, lo1, hi1);
    lo = glm::min(lo, lo1), hi = glm::max(hi, hi1);
    if (outsideFrustum(std::span<const glm::mat4>(cullViews, lensActive ? 4 : 1), lo, hi)) {
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
    if (!fixedSample && inst.moves()) ++st.instancesMoving;
  }
  st.msCull = msSince(t0);

  // The plan: a stochastic pass only for motion or a lens; static instances seen through a pinhole
  // keep the ordinary pass.
  st.stochastic = !fixedSample && (st.instancesMoving > 0 || lensActive || options.forceStochastic);
  if (fixedSample) {
    st.stochasticPlan = "skipped: a fixed-sample frame (t, u, v given)";
  } else if (!st.stochastic) {
    st.stochasticPlan = "skipped: no visible instance moves and the camera is a pinhole";
  } else {
    st.stochasticPlan = std::to_string(st.instancesMoving) + " moving instance(s)" +
                        (lensActive ? ", a lens (every instance defocused)" : ", a pinhole") +
                        (options.forceStochastic && st.instancesMoving == 0 && !lensActive ? ", forced" : "");
  }
  std::vector<size_t> ordinary, stochasticSet;
  for (size_t i : visible) {
    const bool viaStochastic =
        st.stochastic && (lensActive || !options.staticPath || scene.instances[i].moves());
    (viaStochastic ? stochasticSet : ordinary).push_back(i);
  }

  // G-buffer pass (ordinary path).
  const auto t1 = Clock::now();
  frame.depth.resize(w, h, 1.0f);
  frame.gbuffer.resize(w, h);
  raster_.clear(frame.depth, 1.0f);
  const Material defaultMaterial{};
  const float pixelAngle = 2.0f * tanHalf / static_cast<float>(h);
  for (size_t vi : ordinary) {
    const Instance& inst = scene.instances[vi];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    glm::mat4 ta, tb;
    transforms(inst, ta, tb);
    // A fixed-sample frame interpolates positions and normals between the two transforms as the
    // stochastic pass does (its reference must shade like it); otherwise the instance is static.
    const float shadeTime = fixedSample ? options.at->t : 0.0f;
    const InstanceShading sh = fixedSample ? prepareInstance(scene, inst, inst.transform,
                                                             inst.moves() ? *inst.transformClose : inst.transform,
                                                             defaultMaterial)
                                           : prepareInstance(scene, inst, ta, ta, defaultMaterial);
    const glm::mat4 mvp = viewProj * ta;
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
    desc.indices = mesh.indices;
    desc.varyings = kGbufferVaryings;
    desc.cull = raster::CullMode::None;
    st.gbuffer += raster_.draw(
        desc, frame.depth,
        [&](uint32_t i, float* v) {
          vertexVaryings(mesh, sh, i, shadeTime, v);
          return mvp * glm::vec4(mesh.positions[i], 1.0f);
        },
        [&](const raster::Fragment& f) { frame.gbuffer.at(f.x, f.y) = gbufferTexel(sh, f, cam.eye, pixelAngle); });
    ++st.instancesOrdinary;
    st.trianglesOrdinary += mesh.indices.size() / 3;
  }
  st.msGbuffer = msSince(t1);

  // Stochastic pass over the moving (or, with a lens, all) instances, on top of the ordinary
  // pass's depth; then the layers of the G-buffer from each pixel's resolved surfaces.
  int layers = 1;
  // Shadow receivers of the layers: a moving surface is looked up where the same surface point is
  // at the casters' time (mid-shutter), so that it is not shadowed by its own mid-shutter copy.
  const float casterTime = fixedSample ? options.at->t : 0.5f;
  std::vector<raster::Image<shadows::Receiver>> layerReceivers;
  if (st.stochastic) {
    const auto ts = Clock::now();
    std::vector<glm::vec4> clip0, clip1;
    std::vector<uint32_t> indices, surface, triStart;
    std::vector<InstanceShading> shading;
    bool anyMotion = false;
    for (size_t vi : stochasticSet) {
      const Instance& inst = scene.instances[vi];
      const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
      glm::mat4 ta, tb;
      transforms(inst, ta, tb);
      shading.push_back(prepareInstance(scene, inst, ta, tb, defaultMaterial));
      anyMotion |= shading.back().moves;
      const glm::mat4 m0 = viewProj * ta, m1 = viewProj * tb;
      const uint32_t base = static_cast<uint32_t>(clip0.size());
      for (const glm::vec3& p : mesh.positions) {
        clip0.push_back(m0 * glm::vec4(p, 1.0f));
        clip1.push_back(m1 * glm::vec4(p, 1.0f));
      }
      triStart.push_back(static_cast<uint32_t>(indices.size() / 3));
      for (uint32_t i : mesh.indices) indices.push_back(base + i);
      surface.resize(indices.size() / 3, static_cast<uint32_t>(vi));
    }
    triStart.push_back(static_cast<uint32_t>(indices.size() / 3));
    st.instancesStochastic = stochasticSet.size();
    st.trianglesStochastic = indices.size() / 3;
    raster::Image<uint8_t> covered(w, h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) covered.at(x, y) = frame.gbuffer.at(x, y).material >= 0 ? 1 : 0;
    stochastic::StochasticInput in{clip0, clip1, indices, surface, raster::CullMode::None, lensActive ? lens : stochastic::ThinLens{},
                                   anyMotion};
    stochastic::StochasticConfig cfg;
    cfg.method = options.bounds;
    cfg.timeStrata = options.timeStrata;
    cfg.lensStrata = options.lensStrata;
    cfg.pattern.spp = options.spp;
    cfg.pattern.frame = options.frame;
    cfg.staticShortcut = options.staticShortcut;
    cfg.dualBlock = options.dualBlock;
    frame.resolved.resize(w, h);
    frame.spp = options.spp;
    layers = stochastic::kMaxLayers;
    raster::Image<GBufferTexel> layer0(w, h);
    frame.extraLayers.assign(static_cast<size_t>(layers - 1), raster::Image<GBufferTexel>(w, h));
    layerReceivers.assign(static_cast<size_t>(layers), raster::Image<shadows::Receiver>(w, h));
    const stochastic::SampleTarget target = stochastic::makeSampleTarget(w, h, raster::CullMode::None);
    // Each layer's texel: the G-buffer attributes of its samples, averaged (a defocused or moving
    // texture is blurred like the edges); a value every sample agrees on is kept as it is, so a
    // static surface gives the ordinary pass's bits.
    const stochastic::PixelSink sink = [&](int x, int y, const stochastic::ResolvedPixel& rp, const uint32_t* ref,
                                           const stochastic::Sample* samples) {
      for (int l = 0; l < rp.layers; ++l) {
        const stochastic::ResolvedLayer& L = rp.layer[l];
        GBufferTexel& g = l == 0 ? layer0.at(x, y) : frame.extraLayers[static_cast<size_t>(l - 1)].at(x, y);
        shadows::Receiver& rcv = layerReceivers[static_cast<size_t>(l)].at(x, y);
        if (L.surface == stochastic::kStaticSurface) {
          g = frame.gbuffer.at(x, y);
          rcv = {g.position, g.normal, g.material >= 0 ? 1u : 0u};
          continue;
        }
        const size_t k = static_cast<size_t>(std::upper_bound(triStart.begin(), triStart.end(), L.triangle) -
                                             triStart.begin() - 1);
        const InstanceShading& sh = shading[k];
        const Mesh& mesh = scene.meshes[static_cast<size_t>(scene.instances[stochasticSet[k]].mesh)];
        // The shadow receiver is the layer's median-time sample itself (a point on the surface: an
        // average of points on a curved surface lies inside it and would shadow itself); only that
        // sample's mid-shutter position is computed.
        glm::vec3 sumP(0.0f), sumN(0.0f), sumA(0.0f);
        GBufferTexel first;
        bool same = true;
        int n = 0;
        for (int s2 = 0; s2 < frame.spp; ++s2) {
          const uint32_t tri = ref[s2];
          if (tri >= kStochasticTriangleLimit || surface[tri] != L.surface) continue;
          const stochastic::Sample& at = samples[s2];
          const uint32_t prim = tri - triStart[k];
          glm::vec4 c[3];
          float vary[3][kGbufferVaryings];
          const float* vp[3];
          for (int j = 0; j < 3; ++j) {
            const uint32_t vtx = indices[static_cast<size_t>(tri) * 3 + static_cast<size_t>(j)];
            c[j] = stochastic::clipAt(clip0[vtx], anyMotion ? clip1[vtx] : clip0[vtx], at.t, at.u, at.v, in.lens);
            vertexVaryings(mesh, sh, mesh.indices[static_cast<size_t>(prim) * 3 + static_cast<size_t>(j)], at.t, vary[j]);
            vp[j] = vary[j];
          }
          raster::Fragment f{};
          float out[raster::kMaxVaryings + 3];
          if (!stochastic::sampleFragment(c, vp, kGbufferVaryings, target, x, y, f, out)) continue;
          f.primitive = prim;
          const GBufferTexel t = gbufferTexel(sh, f, cam.eye, pixelAngle);
          if (s2 == L.sample) {
            // Shadow receiver: the layer's median-time sample; a moving surface at the same
            // barycentric point at the casters' time.
            glm::vec3 rp3 = t.position, rn3 = t.normal;
            if (sh.moves) {
              rp3 = glm::vec3(0.0f), rn3 = glm::vec3(0.0f);
              const float b[3] = {f.b0, f.b1, f.b2};
              for (int j = 0; j < 3; ++j) {
                float v[kGbufferVaryings];
                vertexVaryings(mesh, sh, mesh.indices[static_cast<size_t>(prim) * 3 + static_cast<size_t>(j)], casterTime, v);
                rp3 += glm::vec3(v[0], v[1], v[2]) * b[j];
                rn3 += glm::vec3(v[3], v[4], v[5]) * b[j];
              }
              const float len = glm::length(rn3);
              rn3 = len > 0.0f ? rn3 / len : t.normal;
              if (glm::dot(rn3, t.normal) < 0.0f) rn3 = -rn3;
            }
            rcv = {rp3, rn3, 1u};
          }
          if (n == 0) first = t;
          same &= t.position == first.position && t.normal == first.normal && t.albedo == first.albedo;
          sumP += t.position, sumN += t.normal, sumA += t.albedo;
          ++n;
        }
        if (n == 0) {  // cannot happen (the resolve found these samples covered): blend as background
          g.material = -1;
          continue;
        }
        if (same && !sh.moves) {
          g = first;
          rcv = {g.position, g.normal, 1u};
          continue;
        }
        const float inv = 1.0f / static_cast<float>(n);
        g.position = sumP * inv;
        const float ln = glm::length(sumN);
        g.normal = ln > 0.0f ? sumN / ln : first.normal;
        g.albedo = sumA * inv;
        g.material = first.material;
      }
    };
    stochastic::StochasticRasterizer sr(raster_);
    st.stoch = sr.render(in, cfg, {&frame.depth, &covered}, frame.resolved, options.debug, &sink);
    st.boundMethod = stochastic::boundMethodName(options.bounds);
    st.msStochastic = msSince(ts);
    frame.gbuffer = std::move(layer0);
  }
  auto layerTexel = [&](int l, int x, int y) -> const GBufferTexel& {
    return l == 0 ? frame.gbuffer.at(x, y) : frame.extraLayers[static_cast<size_t>(l - 1)].at(x, y);
  };

  // Area-light visibility, for every layer's receivers (layer l in rows [l h, (l + 1) h)).
  const auto tShadow = Clock::now();
  const shadows::TechniqueInfo* info = nullptr;
  shadows::ParamSet params;
  if (options.shadow != "none") {
    info = shadows::findTechnique(options.shadow);
    if (!info)
      throw std::invalid_argument("unknown shadow technique '" + options.shadow + "' (known: none, " +
                                  shadows::techniqueNames() + ")");
    params = shadows::ParamSet(info->params);
    if (auto err = params.setAll(options.shadowParams)) throw std::invalid_argument(*err);
  }
  if (!scene.areaLights.empty()) {
    shadows::ReceiverImage rec(w, h * layers);
    raster_.run([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            if (!st.stochastic) {
              const GBufferTexel& g = frame.gbuffer.at(x, y);
              rec.at(x, y) = {g.position, g.normal, g.material >= 0 ? 1u : 0u};
              continue;
            }
            const int n = frame.resolved.at(x, y).layers;
            for (int l = 0; l < layers; ++l) {
              shadows::Receiver r = layerReceivers[static_cast<size_t>(l)].at(x, y);
              if (l >= n) r.valid = 0;
              rec.at(x, y + l * h) = r;
            }
          }
      });
    });
    // Casters at mid-shutter (or the fixed sample's time).
    for (const shadows::RectLight& light : scene.areaLights) {
      LightShadowStats ls;
      ls.technique = info ? info->name : "none";
      ls.params = info ? params.changed() : "";
      frame.visibility.push_back(shadowVisibility(raster_, scene, rec, light, options, info, params, casterTime, ls));
      st.shadows.push_back(std::move(ls));
    }
  }
  st.msShadows = msSince(tShadow);

  // Shading pass, tile-parallel over rows of pixels.
  const auto t2 = Clock::now();
  frame.linear.resize(w, h);
  frame.color.resize(w, h);
  auto shadeTexel = [&](const GBufferTexel& g, int x, int vy) {
    const Material& mat = g.material >= 0 && g.material < static_cast<int32_t>(scene.materials.size())
                              ? scene.materials[static_cast<size_t>(g.material)]
                              : defaultMaterial;
    const glm::vec3 v = glm::normalize(cam.eye - g.position);
    glm::vec3 c = scene.ambient * g.albedo;
    auto light = [&](const glm::vec3& l, const glm::vec3& radiance) {
      const float ndl = glm::dot(g.normal, l);
      if (ndl <= 0.0f) return;
      glm::vec3 contrib = g.albedo * ndl;
      if (mat.specular > 0.0f) {
        const glm::vec3 hv = glm::normalize(l + v);
        contrib += glm::vec3(mat.specular * std::pow(std::max(glm::dot(g.normal, hv), 0.0f), mat.shininess) * ndl);
      }
      c += contrib * radiance;
    };
    for (const DirectionalLight& dl : scene.directionalLights) light(-glm::normalize(dl.direction), dl.color * dl.intensity);
    for (const PointLight& pl : scene.pointLights) {
      const glm::vec3 d = pl.position - g.position;
      const float d2 = std::max(glm::dot(d, d), 1e-8f);
      light(d / std::sqrt(d2), pl.color * (pl.intensity / d2));
    }
    for (size_t li = 0; li < scene.areaLights.size(); ++li) {
      const shadows::RectLight& al = scene.areaLights[li];
      // Diffuse: rho / pi * E with E = radiance * irradianceFactor (exact, unshadowed), times V.
      const float factor = shadows::irradianceFactor(al, g.position, g.normal);
      if (factor <= 0.0f) continue;
      const glm::vec3 e = al.color * (al.intensity * factor * frame.visibility[li].at(x, vy));
      c += g.albedo * e * (1.0f / std::numbers::pi_v<float>);
      // Specular: Blinn-Phong towards the light's centre, scaled by the same E.
      const glm::vec3 toLight = glm::normalize(al.center - g.position);
      if (mat.specular > 0.0f && glm::dot(g.normal, toLight) > 0.0f) {
        const glm::vec3 hv = glm::normalize(toLight + v);
        c += e * (mat.specular * std::pow(std::max(glm::dot(g.normal, hv), 0.0f), mat.shininess) /
                  std::numbers::pi_v<float>);
      }
    }
    return c;
  };
  raster_.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          glm::vec3 c = scene.background;
          float alpha = 0.0f;
          if (!st.stochastic) {
            const GBufferTexel& g = frame.gbuffer.at(x, y);
            if (g.material >= 0) {
              c = shadeTexel(g, x, y);
              alpha = 1.0f;
            }
          } else {
            // Box filter: each surface weighted by the share of the pixel's samples it holds.
            const stochastic::ResolvedPixel& rp = frame.resolved.at(x, y);
            if (rp.layers == 1 && rp.layer[0].count == frame.spp && frame.gbuffer.at(x, y).material >= 0) {
              c = shadeTexel(frame.gbuffer.at(x, y), x, y);  // one surface: no blending, exact
              alpha = 1.0f;
            } else if (rp.layers > 0) {
              const float inv = 1.0f / static_cast<float>(frame.spp);
              c = scene.background * (static_cast<float>(rp.background) * inv);
              for (int l = 0; l < rp.layers; ++l) {
                const float wgt = static_cast<float>(rp.layer[l].count) * inv;
                const GBufferTexel& g = layerTexel(l, x, y);
                if (g.material < 0) {
                  c += scene.background * wgt;
                  continue;
                }
                c += shadeTexel(g, x, y + l * h) * wgt;
                alpha += wgt;
              }
            }
          }
          frame.linear.at(x, y) = raster::Float4{c.x, c.y, c.z, alpha};
          frame.color.at(x, y) = raster::Rgba8{linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z), 255};
        }
    });
  });
  // Callers see layer 0's visibility.
  if (layers > 1)
    for (raster::ImageFloat& v : frame.visibility) {
      raster::ImageFloat top(w, h);
      for (int y = 0; y < h; ++y) std::copy(v.row(y), v.row(y) + w, top.row(y));
      v = std::move(top);
    }
  st.msShade = msSince(t2);
  st.msTotal = msSince(t0);
  return frame;
}

raster::ImageFloat4 accumulationReference(Renderer& renderer, const Scene& scene, RenderOptions options, int n) {
  if (n < 1 || n > 65536) throw std::invalid_argument("accumulation frames must be in [1, 65536]");
  const int w = options.width, h = options.height;
  std::vector<glm::dvec4> sum(static_cast<size_t>(w) * static_cast<size_t>(h), glm::dvec4(0.0));
  auto radicalInverse = [](uint32_t i, uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    for (; i > 0; i /= base, f *= inv) r += f * (i % base);
    return r;
  };
  for (int i = 0; i < n; ++i) {
    stochastic::Sample at;
    at.t = static_cast<float>((i + 0.5) / n);
    // Concentric map of (a, b) in [0, 1)^2 to the unit disk (as the sample pattern does).
    const double a = 2.0 * radicalInverse(static_cast<uint32_t>(i), 2) - 1.0;
    const double b = 2.0 * radicalInverse(static_cast<uint32_t>(i), 3) - 1.0;
    double r = 0.0, phi = 0.0;
    if (a != 0.0 || b != 0.0) {
      if (std::abs(a) > std::abs(b)) {
        r = a, phi = std::numbers::pi / 4.0 * (b / a);
      } else {
        r = b, phi = std::numbers::pi / 2.0 - std::numbers::pi / 4.0 * (a / b);
      }
    }
    at.u = static_cast<float>(r * std::cos(phi));
    at.v = static_cast<float>(r * std::sin(phi));
    options.at = at;
    const Frame f = renderer.render(scene, options);
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
