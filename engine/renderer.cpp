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

// Is the box entirely outside one plane of the clip volume (-w<=x<=w, -w<=y<=w, 0<=z<=w)?
bool outsideFrustum(const glm::mat4& viewProj, const glm::vec3& lo, const glm::vec3& hi) {
  glm::vec4 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = viewProj * glm::vec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0f);
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
  std::string skipped;
  if (shadows.empty()) skipped += "shadow maps (no area light), ";
  skipped += "stochastic pass (no motion, pinhole camera)";
  s += "  skipped passes: " + skipped + "\n";
  return s;
}

Renderer::Renderer(int threads) : raster_({.threads = threads}) {}

namespace {

// V of one area light over the G-buffer, with the instance-level culling and flattening that turn
// the Scene into what shadows/ consumes.
raster::ImageFloat shadowVisibility(raster::Rasterizer& raster, const Scene& scene, const shadows::ReceiverImage& rec,
                                    const shadows::RectLight& light, const RenderOptions& options,
                                    const shadows::TechniqueInfo* info, const shadows::ParamSet& params,
                                    LightShadowStats& st) {
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
    glm::vec3 corners[8];
    for (int c = 0; c < 8; ++c)
      corners[c] = glm::vec3(inst.transform * glm::vec4((c & 1) ? m.boundsMax.x : m.boundsMin.x,
                                                        (c & 2) ? m.boundsMax.y : m.boundsMin.y,
                                                        (c & 4) ? m.boundsMax.z : m.boundsMin.z, 1.0f));
    if (m.indices.empty()) continue;
    if (options.shadowCulling && !region.mayShadow(light, corners)) {
      ++st.instancesCulled;
      continue;
    }
    const uint32_t base = static_cast<uint32_t>(positions.size());
    for (const glm::vec3& p : m.positions) positions.push_back(glm::vec3(inst.transform * glm::vec4(p, 1.0f)));
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

Frame Renderer::render(const Scene& scene, const RenderOptions& options) {
  const auto t0 = Clock::now();
  Frame frame;
  FrameStats& st = frame.stats;
  const int w = options.width, h = options.height;
  const Camera cam = chooseCamera(scene, options, &st.cameraSource);
  frame.viewProj = viewProjection(cam, scene, static_cast<double>(w) / h);
  const glm::mat4 viewProj = frame.viewProj;

  // Cull instances against the view frustum before any vertex work.
  std::vector<size_t> visible;
  st.instances = scene.instances.size();
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const size_t tris = scene.meshes[static_cast<size_t>(inst.mesh)].indices.size() / 3;
    glm::vec3 lo, hi;
    instanceBounds(scene, inst, lo, hi);
    if (outsideFrustum(viewProj, lo, hi)) {
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
  }
  st.msCull = msSince(t0);

  // G-buffer pass.
  const auto t1 = Clock::now();
  frame.depth.resize(w, h, 1.0f);
  frame.gbuffer.resize(w, h);
  raster_.clear(frame.depth, 1.0f);
  const Material defaultMaterial{};
  const float pixelAngle = 2.0f * std::tan(0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f) / static_cast<float>(h);
  for (size_t vi : visible) {
    const Instance& inst = scene.instances[vi];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    const int matIndex = mesh.material;
    const Material& mat = matIndex >= 0 ? scene.materials[static_cast<size_t>(matIndex)] : defaultMaterial;
    const Texture* tex = mat.baseColorTexture >= 0 ? &scene.textures[static_cast<size_t>(mat.baseColorTexture)] : nullptr;
    const glm::mat4 mvp = viewProj * inst.transform;
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    const bool hasUv = !mesh.texcoords.empty();
    // Texture level of detail: texels per world unit from each triangle's uv and world areas,
    // times the world size of a pixel at the fragment's distance (isotropic approximation).
    std::vector<float> texelsPerUnit;
    if (tex && hasUv) {
      const float texSize = static_cast<float>(tex->mips[0].width() * tex->mips[0].height());
      texelsPerUnit.resize(mesh.indices.size() / 3);
      for (size_t t = 0; t < texelsPerUnit.size(); ++t) {
        const uint32_t a = mesh.indices[t * 3], b = mesh.indices[t * 3 + 1], c = mesh.indices[t * 3 + 2];
        const glm::vec3 pa(inst.transform * glm::vec4(mesh.positions[a], 1)), pb(inst.transform * glm::vec4(mesh.positions[b], 1)),
            pc(inst.transform * glm::vec4(mesh.positions[c], 1));
        const float worldArea = glm::length(glm::cross(pb - pa, pc - pa));
        const glm::vec2 ua = mesh.texcoords[a], ub = mesh.texcoords[b], uc = mesh.texcoords[c];
        const float uvArea = std::abs((ub.x - ua.x) * (uc.y - ua.y) - (ub.y - ua.y) * (uc.x - ua.x)) * texSize;
        texelsPerUnit[t] = worldArea > 0.0f ? std::sqrt(uvArea / worldArea) : 0.0f;
      }
    }
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
    desc.indices = mesh.indices;
    desc.varyings = 8;  // world position, world normal, uv
    desc.cull = raster::CullMode::None;
    st.gbuffer += raster_.draw(
        desc, frame.depth,
        [&](uint32_t i, float* v) {
          const glm::vec4 wp = inst.transform * glm::vec4(mesh.positions[i], 1.0f);
          const glm::vec3 n = normalMatrix * mesh.normals[i];
          v[0] = wp.x, v[1] = wp.y, v[2] = wp.z;
          v[3] = n.x, v[4] = n.y, v[5] = n.z;
          const glm::vec2 uv = hasUv ? mesh.texcoords[i] : glm::vec2(0.0f);
          v[6] = uv.x, v[7] = uv.y;
          return mvp * glm::vec4(mesh.positions[i], 1.0f);
        },
        [&](const raster::Fragment& f) {
          GBufferTexel& g = frame.gbuffer.at(f.x, f.y);
          g.position = glm::vec3(f.varyings[0], f.varyings[1], f.varyings[2]);
          glm::vec3 n(f.varyings[3], f.varyings[4], f.varyings[5]);
          const float len = glm::length(n);
          n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);
          const glm::vec3 toEye = cam.eye - g.position;
          if (glm::dot(n, toEye) < 0.0f) n = -n;  // two-sided: the normal faces the viewer
          g.normal = n;
          glm::vec4 base = mat.baseColorFactor;
          if (tex) {
            float lod = 0.0f;
            if (!texelsPerUnit.empty()) {
              const float pixelWorld = glm::length(toEye) * pixelAngle /
                                       std::max(std::abs(glm::dot(n, glm::normalize(toEye))), 0.25f);
              const float texels = texelsPerUnit[f.primitive] * pixelWorld;
              lod = texels > 0.0f ? std::max(std::log2(texels), 0.0f) : 0.0f;
            }
            base *= sampleBilinear(*tex, glm::vec2(f.varyings[6], f.varyings[7]), lod);
          }
          g.albedo = glm::vec3(base);
          g.material = matIndex < 0 ? static_cast<int32_t>(scene.materials.size()) : matIndex;
        });
  }
  st.msGbuffer = msSince(t1);

  // Area-light visibility.
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
    shadows::ReceiverImage rec(w, h);
    raster_.run([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const GBufferTexel& g = frame.gbuffer.at(x, y);
            rec.at(x, y) = {g.position, g.normal, g.material >= 0 ? 1u : 0u};
          }
      });
    });
    for (const shadows::RectLight& light : scene.areaLights) {
      LightShadowStats ls;
      ls.technique = info ? info->name : "none";
      ls.params = info ? params.changed() : "";
      frame.visibility.push_back(shadowVisibility(raster_, scene, rec, light, options, info, params, ls));
      st.shadows.push_back(std::move(ls));
    }
  }
  st.msShadows = msSince(tShadow);

  // Shading pass, tile-parallel over rows of pixels.
  const auto t2 = Clock::now();
  frame.linear.resize(w, h);
  frame.color.resize(w, h);
  raster_.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const GBufferTexel& g = frame.gbuffer.at(x, y);
          glm::vec3 c = scene.background;
          float alpha = 0.0f;
          if (g.material >= 0) {
            const Material& mat = g.material < static_cast<int32_t>(scene.materials.size())
                                      ? scene.materials[static_cast<size_t>(g.material)]
                                      : defaultMaterial;
            const glm::vec3 v = glm::normalize(cam.eye - g.position);
            c = scene.ambient * g.albedo;
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
            for (const DirectionalLight& dl : scene.directionalLights)
              light(-glm::normalize(dl.direction), dl.color * dl.intensity);
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
              const glm::vec3 e = al.color * (al.intensity * factor * frame.visibility[li].at(x, y));
              c += g.albedo * e * (1.0f / std::numbers::pi_v<float>);
              // Specular: Blinn-Phong towards the light's centre, scaled by the same E.
              const glm::vec3 toLight = glm::normalize(al.center - g.position);
              if (mat.specular > 0.0f && glm::dot(g.normal, toLight) > 0.0f) {
                const glm::vec3 hv = glm::normalize(toLight + v);
                c += e * (mat.specular * std::pow(std::max(glm::dot(g.normal, hv), 0.0f), mat.shininess) /
                          std::numbers::pi_v<float>);
              }
            }
            alpha = 1.0f;
          }
          frame.linear.at(x, y) = raster::Float4{c.x, c.y, c.z, alpha};
          frame.color.at(x, y) = raster::Rgba8{linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z), 255};
        }
    });
  });
  st.msShade = msSince(t2);
  st.msTotal = msSince(t0);
  return frame;
}

}  // namespace penumbra::engine
