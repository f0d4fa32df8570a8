#include "engine/gbuffer_pass.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "engine/texture.h"
#include "raster/timing.h"

namespace penumbra::engine {

namespace {
const Material kDefaultMaterial{};  // for meshes without one (immutable)
}  // namespace

InstanceShading prepareInstance(const Scene& scene, const Instance& inst, const glm::mat4& t0, const glm::mat4& t1) {
  InstanceShading sh;
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  sh.mesh = &mesh;
  sh.instance = static_cast<int32_t>(&inst - scene.instances.data());
  const int matIndex = mesh.material;
  sh.mat = matIndex >= 0 ? &scene.materials[static_cast<size_t>(matIndex)] : &kDefaultMaterial;
  sh.tex = sh.mat->baseColorTexture >= 0 ? &scene.textures[static_cast<size_t>(sh.mat->baseColorTexture)] : nullptr;
  sh.material = matIndex < 0 ? static_cast<int32_t>(scene.materials.size()) : matIndex;
  sh.t0 = t0, sh.t1 = t1;
  sh.moves = t0 != t1;
  sh.n0 = glm::transpose(glm::inverse(glm::mat3(t0)));
  sh.n1 = sh.moves ? glm::transpose(glm::inverse(glm::mat3(t1))) : sh.n0;
  sh.hasUv = !mesh.texcoords.empty();
  sh.hasColor = !mesh.colors.empty();
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
  if (sh.hasColor) {
    const glm::vec3& c = mesh.colors[i];
    v[8] = c.x, v[9] = c.y, v[10] = c.z;
  }
}

glm::vec3 faceNormal(const InstanceShading& sh, uint32_t primitive, float t, const glm::vec3& pointOn,
                     const glm::vec3& towards, const glm::vec3& fallback) {
  glm::vec3 p[3];
  for (int j = 0; j < 3; ++j) {
    const glm::vec4 o(sh.mesh->positions[sh.mesh->indices[static_cast<size_t>(primitive) * 3 + static_cast<size_t>(j)]],
                      1.0f);
    glm::vec4 wp = sh.t0 * o;
    if (sh.moves) {  // the same straight line as vertexVaryings
      const glm::vec4 wp1 = sh.t1 * o;
      wp = glm::vec4(wp.x + (wp1.x - wp.x) * t, wp.y + (wp1.y - wp.y) * t, wp.z + (wp1.z - wp.z) * t, 1.0f);
    }
    p[j] = glm::vec3(wp);
  }
  // In double: the cross product of a fine mesh's short edges loses float precision.
  const glm::dvec3 e1 = glm::dvec3(p[1]) - glm::dvec3(p[0]), e2 = glm::dvec3(p[2]) - glm::dvec3(p[0]);
  const glm::dvec3 c = glm::cross(e1, e2);
  const double len = glm::length(c);
  if (!(len > 0.0) || !std::isfinite(len)) return fallback;
  glm::vec3 n(c / len);
  if (glm::dot(n, towards - pointOn) < 0.0f) n = -n;
  return n;
}

GBufferTexel gbufferTexel(const InstanceShading& sh, const raster::Fragment& f, float t, const glm::vec3& eye,
                          float pixelAngle) {
  GBufferTexel g;
  g.position = glm::vec3(f.varyings[0], f.varyings[1], f.varyings[2]);
  glm::vec3 n(f.varyings[3], f.varyings[4], f.varyings[5]);
  const float len = glm::length(n);
  n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);
  const glm::vec3 toEye = eye - g.position;
  if (glm::dot(n, toEye) < 0.0f) n = -n;  // two-sided: the normal faces the viewer
  g.normal = n;
  g.geometricNormal = faceNormal(sh, f.primitive, t, g.position, eye, n);
  g.instance = sh.instance;
  g.triangle = static_cast<int32_t>(f.primitive);
  g.bary = glm::vec3(f.b0, f.b1, f.b2);
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
  if (sh.hasColor) base *= glm::vec4(f.varyings[8], f.varyings[9], f.varyings[10], 1.0f);
  g.albedo = glm::vec3(base);
  g.material = sh.material;
  return g;
}

const Material& gbufferMaterial(const Scene& scene, int32_t material) {
  return material >= 0 && material < static_cast<int32_t>(scene.materials.size())
             ? scene.materials[static_cast<size_t>(material)]
             : kDefaultMaterial;
}

void drawGBuffer(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan, Frame& frame) {
  const auto t0 = raster::Clock::now();
  FrameStats& st = frame.stats;
  raster.run([&] {  // first touched by every thread (Image::resizeParallel)
    frame.depth.resizeParallel(plan.width, plan.height, 1.0f);
    frame.gbuffer.resizeParallel(plan.width, plan.height);
  });
  for (size_t vi : plan.ordinary) {
    const Instance& inst = scene.instances[vi];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    glm::mat4 ta, tb;
    plan.transforms(inst, ta, tb);
    // A fixed-sample frame interpolates positions and normals between the two transforms as the
    // stochastic pass does (its reference must shade like it); otherwise the instance is static.
    const float shadeTime = plan.at ? plan.at->t : 0.0f;
    const InstanceShading sh =
        plan.at ? prepareInstance(scene, inst, inst.transform, inst.moves() ? *inst.transformClose : inst.transform)
                : prepareInstance(scene, inst, ta, ta);
    const glm::mat4 mvp = plan.viewProj * ta;
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
    desc.indices = mesh.indices;
    desc.varyings = sh.varyings();
    desc.cull = raster::CullMode::None;
    st.gbuffer += raster.draw(
        desc, frame.depth,
        [&](uint32_t i, float* v) {
          vertexVaryings(mesh, sh, i, shadeTime, v);
          return mvp * glm::vec4(mesh.positions[i], 1.0f);
        },
        [&](const raster::Fragment& f) {
          frame.gbuffer.at(f.x, f.y) = gbufferTexel(sh, f, shadeTime, plan.camera.eye, plan.pixelAngle);
        });
    ++st.instancesOrdinary;
    st.trianglesOrdinary += mesh.indices.size() / 3;
  }
  st.msGbuffer = raster::msSince(t0);
}

}  // namespace penumbra::engine
