#include "engine/scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace penumbra::engine {

size_t Scene::triangleCount() const {
  size_t n = 0;
  for (const Instance& inst : instances) n += meshes[static_cast<size_t>(inst.mesh)].indices.size() / 3;
  return n;
}

glm::mat4 Instance::transformAt(float t) const {
  if (!transformClose) return transform;
  glm::mat4 m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m[c][r] = transform[c][r] + ((*transformClose)[c][r] - transform[c][r]) * t;
  return m;
}

namespace {

// World-space box of one instance over the shutter; false for an empty mesh.
bool instanceBox(const Scene& scene, const Instance& inst, glm::vec3& lo, glm::vec3& hi) {
  const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
  if (m.positions.empty()) return false;
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? m.boundsMax.x : m.boundsMin.x, (c & 2) ? m.boundsMax.y : m.boundsMin.y,
                      (c & 4) ? m.boundsMax.z : m.boundsMin.z);
    for (const glm::mat4* m2 : {&inst.transform, inst.transformClose ? &*inst.transformClose : &inst.transform}) {
      const glm::vec3 w = glm::vec3(*m2 * glm::vec4(p, 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
  return true;
}

}  // namespace

bool Scene::worldBounds(glm::vec3& lo, glm::vec3& hi) const {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  bool any = false;
  for (const Instance& inst : instances) {
    glm::vec3 a, b;
    if (!instanceBox(*this, inst, a, b)) continue;
    lo = glm::min(lo, a), hi = glm::max(hi, b);
    any = true;
  }
  return any;
}

std::vector<char> Scene::flatInstances() const {
  std::vector<char> flat(instances.size(), 0);
  for (size_t i = 0; i < instances.size(); ++i) {
    glm::vec3 lo, hi;
    if (!instanceBox(*this, instances[i], lo, hi)) continue;
    const glm::vec3 e = hi - lo;
    const float big = std::max({e.x, e.y, e.z}), small = std::min({e.x, e.y, e.z});
    flat[i] = small <= 1e-3f * big ? 1 : 0;
  }
  return flat;
}

bool Scene::objectBounds(glm::vec3& lo, glm::vec3& hi) const {
  // Flat instances: candidates for a ground or a backdrop.
  const std::vector<char> flat = flatInstances();
  std::vector<glm::vec3> los(instances.size()), his(instances.size());
  std::vector<char> has(instances.size(), 0);
  for (size_t i = 0; i < instances.size(); ++i) has[i] = instanceBox(*this, instances[i], los[i], his[i]) ? 1 : 0;
  glm::vec3 olo(std::numeric_limits<float>::max()), ohi = -olo;
  bool objects = false;
  for (size_t i = 0; i < instances.size(); ++i)
    if (has[i] && !flat[i]) olo = glm::min(olo, los[i]), ohi = glm::max(ohi, his[i]), objects = true;
  if (!objects) return worldBounds(lo, hi);
  // Flat instances at most twice the objects' size are part of what is shown (a card, a table top).
  const float size = glm::length(ohi - olo);
  lo = olo, hi = ohi;
  for (size_t i = 0; i < instances.size(); ++i)
    if (has[i] && flat[i] && glm::length(his[i] - los[i]) <= 2.0f * size)
      lo = glm::min(lo, los[i]), hi = glm::max(hi, his[i]);
  return true;
}

bool addDefaultLighting(Scene& scene) {
  if (!scene.directionalLights.empty() || !scene.pointLights.empty() || !scene.spotLights.empty() ||
      !scene.areaLights.empty())
    return false;
  glm::vec3 lo, hi;
  if (!scene.objectBounds(lo, hi)) return false;
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
  // Above, in front (the fitted camera looks from +z, +x) and to its left.
  const glm::vec3 dir = glm::normalize(glm::vec3(-0.5f, 1.2f, 0.6f));
  shadows::RectLight key;
  const float width = 0.35f * radius;
  if (!shadows::makeRectLight(centre + dir * (2.5f * radius), -dir, glm::vec3(1, 0, 0), width, width, glm::vec3(1.0f),
                              1.0f, key))
    return false;
  // Radiance such that a white surface at the centre, facing the light, reflects 0.8:
  // albedo / pi * E = 0.8 with E = radiance * irradianceFactor.
  const float factor = shadows::irradianceFactor(key, centre, dir);
  if (!(factor > 0.0f)) return false;
  key.intensity = 0.8f * std::numbers::pi_v<float> / factor;
  scene.areaLights.push_back(key);
  scene.sky = SkyLight{};
  scene.defaultLighting = true;
  return true;
}

void computeBounds(Mesh& mesh) {
  if (mesh.positions.empty()) {
    mesh.boundsMin = mesh.boundsMax = glm::vec3(0.0f);
    return;
  }
  mesh.boundsMin = mesh.boundsMax = mesh.positions[0];
  for (const glm::vec3& p : mesh.positions) {
    mesh.boundsMin = glm::min(mesh.boundsMin, p);
    mesh.boundsMax = glm::max(mesh.boundsMax, p);
  }
}

void computeNormals(Mesh& mesh) {
  std::vector<glm::dvec3> acc(mesh.positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
    const glm::dvec3 n = glm::cross(pb - pa, pc - pa);  // length = 2 * area: area weighting
    acc[a] += n;
    acc[b] += n;
    acc[c] += n;
  }
  mesh.normals.resize(mesh.positions.size());
  for (size_t i = 0; i < acc.size(); ++i) {
    const double len = glm::length(acc[i]);
    mesh.normals[i] = len > 0.0 ? glm::vec3(acc[i] / len) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

bool meshIsClosed(const Mesh& mesh) {
  const size_t nv = mesh.positions.size(), nt = mesh.indices.size() / 3;
  if (nt == 0) return false;
  // Weld: each vertex's id is the first vertex with its exact position (equal floats: -0 is +0; a
  // seam is welded only where the loader duplicated the vertex exactly).
  const auto key = [&](uint32_t i) {
    const glm::vec3 p = mesh.positions[i] + glm::vec3(0.0f);  // -0 + 0 = +0
    return std::array<uint32_t, 3>{std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z)};
  };
  std::vector<uint32_t> order(nv);
  for (uint32_t i = 0; i < nv; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return std::pair(key(a), a) < std::pair(key(b), b); });
  std::vector<uint32_t> weld(nv);
  for (size_t k = 0; k < nv; ++k)
    weld[order[k]] = (k > 0 && key(order[k]) == key(order[k - 1])) ? weld[order[k - 1]] : order[k];
  // Directed edges (a, b) as 64-bit keys: each exactly once, and its reverse present.
  std::vector<uint64_t> edges;
  edges.reserve(3 * nt);
  double volume = 0.0;
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t v[3] = {weld[mesh.indices[3 * t]], weld[mesh.indices[3 * t + 1]], weld[mesh.indices[3 * t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    for (int e = 0; e < 3; ++e) edges.push_back(uint64_t{v[e]} << 32 | v[(e + 1) % 3]);
    const glm::dvec3 a(mesh.positions[v[0]]), b(mesh.positions[v[1]]), c(mesh.positions[v[2]]);
    volume += glm::dot(a, glm::cross(b, c));  // 6 times the signed volume, summed in triangle order
  }
  if (edges.empty()) return false;
  std::sort(edges.begin(), edges.end());
  for (size_t k = 0; k < edges.size(); ++k) {
    if (k > 0 && edges[k] == edges[k - 1]) return false;  // an edge used twice in one direction
    const uint64_t reverse = edges[k] << 32 | edges[k] >> 32;
    if (!std::binary_search(edges.begin(), edges.end(), reverse)) return false;  // a border edge
  }
  return volume > 0.0;
}

Status validateScene(Scene& scene, const std::string& where) {
  for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    Mesh& m = scene.meshes[mi];
    const std::string what = "mesh " + std::to_string(mi) + (m.name.empty() ? "" : " '" + m.name + "'");
    if (m.indices.size() % 3 != 0) return Error{where, what + ": index count " + std::to_string(m.indices.size()) + " is not a multiple of 3"};
    for (size_t i = 0; i < m.indices.size(); ++i)
      if (m.indices[i] >= m.positions.size())
        return Error{where, what + ": index " + std::to_string(m.indices[i]) + " out of range (" +
                                std::to_string(m.positions.size()) + " vertices)"};
    for (const glm::vec3& p : m.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return Error{where, what + ": non-finite vertex position"};
    if (!m.texcoords.empty() && m.texcoords.size() != m.positions.size())
      return Error{where, what + ": texcoord count differs from position count"};
    if (!m.colors.empty() && m.colors.size() != m.positions.size())
      return Error{where, what + ": color count differs from position count"};
    for (const glm::vec3& c : m.colors)
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
        return Error{where, what + ": non-finite vertex color"};
    if (m.normals.size() != m.positions.size()) computeNormals(m);
    if (m.material >= static_cast<int>(scene.materials.size()))
      return Error{where, what + ": material index " + std::to_string(m.material) + " out of range"};
    computeBounds(m);
    m.closed = meshIsClosed(m);
  }
  for (const Material& mat : scene.materials)
    if (mat.baseColorTexture >= static_cast<int>(scene.textures.size()))
      return Error{where, "material '" + mat.name + "': texture index out of range"};
  for (const Instance& inst : scene.instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size()))
      return Error{where, "instance '" + inst.name + "': mesh index out of range"};
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(inst.transform[c][r]) || (inst.transformClose && !std::isfinite((*inst.transformClose)[c][r])))
          return Error{where, "instance '" + inst.name + "': non-finite transform"};
  }
  if (scene.camera) {
    const Camera& cam = *scene.camera;
    if (!(cam.fovYDegrees > 0.0f && cam.fovYDegrees < 180.0f))
      return Error{where, "camera field of view must be in (0, 180) degrees"};
    const bool finite = std::isfinite(cam.eye.x) && std::isfinite(cam.eye.y) && std::isfinite(cam.eye.z) &&
                        std::isfinite(cam.target.x) && std::isfinite(cam.target.y) && std::isfinite(cam.target.z) &&
                        std::isfinite(cam.up.x) && std::isfinite(cam.up.y) && std::isfinite(cam.up.z);
    if (!finite) return Error{where, "camera position, target or up is not finite"};
    if (!(cam.apertureRadius >= 0.0f) || !std::isfinite(cam.apertureRadius) || !(cam.focusDistance >= 0.0f) ||
        !std::isfinite(cam.focusDistance))
      return Error{where, "camera aperture and focus distance must be finite and >= 0"};
    if (!(glm::length(cam.target - cam.eye) > 0.0f)) return Error{where, "camera eye and target coincide"};
    if (!(cam.znear >= 0.0f) || !std::isfinite(cam.znear) || !(cam.zfar >= 0.0f) || !std::isfinite(cam.zfar) ||
        (cam.znear > 0.0f && cam.zfar > 0.0f && !(cam.zfar > cam.znear)))
      return Error{where, "camera near and far must be finite and >= 0 (0: fitted), far beyond near"};
  }
  return Ok{};
}

}  // namespace penumbra::engine
