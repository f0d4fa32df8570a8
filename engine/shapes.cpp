#include "engine/shapes.h"

#include <algorithm>
#include <cassert>
#include <bit>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <unordered_map>
#include <utility>

namespace penumbra::engine {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The angle of step k of n around a circle. k == n gives exactly the values of k == 0, so seam
// vertices are bit-identical to the first column.
struct Angle {
  float s, c;
};
Angle circleStep(int k, int n) {
  const double a = kTwoPi * (k % n) / n;
  return {static_cast<float>(std::sin(a)), static_cast<float>(std::cos(a))};
}

uint32_t u32(int v) { return static_cast<uint32_t>(v); }

void addTriangle(Mesh& m, int a, int b, int c) { m.indices.insert(m.indices.end(), {u32(a), u32(b), u32(c)}); }

int addVertex(Mesh& m, glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
  m.positions.push_back(p);
  m.normals.push_back(n);
  m.texcoords.push_back(uv);
  return static_cast<int>(m.positions.size()) - 1;
}

Mesh finish(Mesh m, const char* name) {
  m.name = name;
  computeBounds(m);
  return m;
}

float toUnit(int k, int n) { return static_cast<float>(k) / static_cast<float>(n); }

}  // namespace

Mesh makePlane(float sx, float sz, int div) {
  assert(sx > 0.0f && sz > 0.0f && div >= 1);
  div = std::max(div, 1);
  Mesh m;
  const int n = div + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float u = toUnit(i, div), v = toUnit(j, div);
      addVertex(m, {(u - 0.5f) * sx, 0.0f, (v - 0.5f) * sz}, {0.0f, 1.0f, 0.0f}, {u, v});
    }
  // Seen from +y, +z then +x is counter-clockwise: cross(+z, +x) = +y.
  for (int j = 0; j < div; ++j)
    for (int i = 0; i < div; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      addTriangle(m, a, c, b);
      addTriangle(m, b, c, d);
    }
  return finish(std::move(m), "plane");
}

Mesh makeBox(glm::vec3 size) {
  assert(size.x > 0.0f && size.y > 0.0f && size.z > 0.0f);
  Mesh m;
  const glm::vec3 h = size * 0.5f;
  // Per face: outward normal n and in-face axes u, v with cross(u, v) = n.
  struct Face {
    glm::vec3 n, u, v;
  };
  const Face faces[6] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  };
  for (const Face& f : faces) {
    int corner[2][2];
    for (int t = 0; t < 2; ++t)
      for (int s = 0; s < 2; ++s) {
        const float su = s ? 1.0f : -1.0f, sv = t ? 1.0f : -1.0f;
        // Each coordinate is exactly +-h or 0 (products with 0), so corners shared by three faces
        // have identical positions.
        const glm::vec3 p = f.n * h + f.u * h * su + f.v * h * sv;
        corner[t][s] = addVertex(m, p, f.n, {static_cast<float>(s), static_cast<float>(1 - t)});
      }
    addTriangle(m, corner[0][0], corner[0][1], corner[1][1]);
    addTriangle(m, corner[0][0], corner[1][1], corner[1][0]);
  }
  return finish(std::move(m), "box");
}

Mesh makeSphere(float radius, int rings, int segments) {
  assert(radius > 0.0f && rings >= 2 && segments >= 3);
  rings = std::max(rings, 2);
  segments = std::max(segments, 3);
  Mesh m;
  const int cols = segments + 1;
  // Vertex (i, j): polar angle theta = pi i / rings from +y, azimuth phi = 2 pi j / segments from +z
  // towards +x: direction (sin theta sin phi, cos theta, sin theta cos phi).
  for (int i = 0; i <= rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    const float st = i == 0 || i == rings ? 0.0f : static_cast<float>(std::sin(theta));
    const float ct = i == 0 ? 1.0f : i == rings ? -1.0f : static_cast<float>(std::cos(theta));
    for (int j = 0; j <= segments; ++j) {
      const Angle phi = circleStep(j, segments);
      const glm::vec3 d = i == 0 || i == rings ? glm::vec3(0.0f, ct, 0.0f) : glm::vec3(st * phi.s, ct, st * phi.c);
      // A pole vertex serves one triangle: its u is the middle of that triangle's slice.
      float u = toUnit(j, segments);
      // (The pole vertices j = 0 at the north and j = segments at the south serve none.)
      if (i == 0) u = std::max(0.0f, (static_cast<float>(j) - 0.5f) / static_cast<float>(segments));
      if (i == rings) u = std::min(1.0f, (static_cast<float>(j) + 0.5f) / static_cast<float>(segments));
      addVertex(m, d * radius, d, {u, toUnit(i, rings)});
    }
  }
  // Going down (+i) then around (+j) is counter-clockwise seen from outside.
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * cols + j, b = a + 1, c = a + cols, d = c + 1;
      if (i != 0) addTriangle(m, a, c, b);          // degenerate at the north pole (a, b coincide)
      if (i != rings - 1) addTriangle(m, b, c, d);  // degenerate at the south pole (c, d coincide)
    }
  return finish(std::move(m), "sphere");
}

Mesh makeCylinder(float radius, float height, int segments) {
  assert(radius > 0.0f && height > 0.0f && segments >= 3);
  segments = std::max(segments, 3);
  Mesh m;
  const float top = 0.5f * height, bottom = -0.5f * height;
  auto rim = [&](int j, float y) {
    const Angle phi = circleStep(j, segments);
    return glm::vec3(radius * phi.s, y, radius * phi.c);
  };
  // Side: two rows (top, bottom) of segments + 1 vertices, radial normals.
  const int cols = segments + 1;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j <= segments; ++j) {
      const Angle phi = circleStep(j, segments);
      addVertex(m, rim(j, i == 0 ? top : bottom), {phi.s, 0.0f, phi.c}, {toUnit(j, segments), static_cast<float>(i)});
    }
  for (int j = 0; j < segments; ++j) {
    const int a = j, b = j + 1, c = cols + j, d = c + 1;
    addTriangle(m, a, c, b);
    addTriangle(m, b, c, d);
  }
  // Caps: a center and a rim of `segments` vertices each, facing +y and -y.
  for (int cap = 0; cap < 2; ++cap) {
    const float y = cap == 0 ? top : bottom;
    const glm::vec3 n(0.0f, cap == 0 ? 1.0f : -1.0f, 0.0f);
    const int center = addVertex(m, {0.0f, y, 0.0f}, n, {0.5f, 0.5f});
    const int first = static_cast<int>(m.positions.size());
    for (int j = 0; j < segments; ++j) {
      const Angle phi = circleStep(j, segments);
      addVertex(m, rim(j, y), n, {0.5f + 0.5f * phi.s, 0.5f - 0.5f * phi.c * n.y});
    }
    for (int j = 0; j < segments; ++j) {
      const int p = first + j, q = first + (j + 1) % segments;
      if (cap == 0) addTriangle(m, center, p, q);
      else addTriangle(m, center, q, p);
    }
  }
  return finish(std::move(m), "cylinder");
}

Mesh makeTorus(float majorRadius, float minorRadius, int rings, int segments) {
  assert(minorRadius > 0.0f && majorRadius > minorRadius && rings >= 3 && segments >= 3);
  rings = std::max(rings, 3);
  segments = std::max(segments, 3);
  Mesh m;
  const int cols = segments + 1;
  // Vertex (i, j): major angle phi_i around y (from +z towards +x), minor angle psi_j around the
  // tube (from the outer equator towards +y). p = R d + r (cos psi d + sin psi y), d = (sin phi, 0, cos phi).
  for (int i = 0; i <= rings; ++i) {
    const Angle phi = circleStep(i, rings);
    const glm::vec3 d(phi.s, 0.0f, phi.c);
    for (int j = 0; j <= segments; ++j) {
      const Angle psi = circleStep(j, segments);
      const glm::vec3 n = d * psi.c + glm::vec3(0.0f, psi.s, 0.0f);
      addVertex(m, d * majorRadius + n * minorRadius, n, {toUnit(i, rings), toUnit(j, segments)});
    }
  }
  // Along the major circle (+i) then around the tube (+j) is counter-clockwise seen from outside.
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * cols + j, b = a + 1, c = a + cols, d = c + 1;
      addTriangle(m, a, c, b);
      addTriangle(m, c, d, b);
    }
  return finish(std::move(m), "torus");
}

Mesh makeRadialSurface(int div, float (*radius)(glm::vec3 direction)) {
  assert(div >= 1);
  div = std::max(div, 1);
  Mesh m;
  const int n = div + 1;
  // Equal-angle coordinate k of n on a cube face: exactly -1 and 1 at the ends, so the faces'
  // shared edges compute the same points.
  std::vector<float> coord(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k)
    coord[static_cast<size_t>(k)] =
        k == 0 ? -1.0f : k == div ? 1.0f
                                  : static_cast<float>(std::tan(std::numbers::pi / 4.0 * (-1.0 + 2.0 * k / div)));
  for (int axis = 0; axis < 3; ++axis)
    for (const float side : {-1.0f, 1.0f}) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const int first = static_cast<int>(m.positions.size());
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          glm::vec3 c(0.0f);
          c[axis] = side;
          c[a] = coord[static_cast<size_t>(i)];
          c[b] = coord[static_cast<size_t>(j)];
          const glm::vec3 d = glm::normalize(c);
          addVertex(m, d * radius(d), d, {toUnit(i, div), toUnit(j, div)});
        }
      // (+a, +b) is counter-clockwise seen from outside when cross(e_a, e_b) = e_axis points out.
      const bool ccw = side > 0.0f;
      for (int j = 0; j < div; ++j)
        for (int i = 0; i < div; ++i) {
          const int v00 = first + j * n + i, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
          if (ccw) {
            addTriangle(m, v00, v10, v11);
            addTriangle(m, v00, v11, v01);
          } else {
            addTriangle(m, v00, v11, v10);
            addTriangle(m, v00, v01, v11);
          }
        }
    }
  computeWeldedNormals(m);
  return finish(std::move(m), "radial surface");
}

Mesh makeTorusKnot(int p, int q, float majorRadius, float minorRadius, float tube, int segments, int sides) {
  assert(majorRadius > minorRadius && minorRadius > 0.0f && tube > 0.0f && segments >= 3 && sides >= 3);
  segments = std::max(segments, 3);
  sides = std::max(sides, 3);
  Mesh m;
  const double R = majorRadius, r = minorRadius;
  for (int i = 0; i < segments; ++i) {
    const double t = kTwoPi * i / segments;
    const double ring = R + r * std::cos(q * t);
    const glm::dvec3 c(ring * std::cos(p * t), r * std::sin(q * t), ring * std::sin(p * t));
    const glm::dvec3 dc(-r * q * std::sin(q * t) * std::cos(p * t) - ring * p * std::sin(p * t), r * q * std::cos(q * t),
                        -r * q * std::sin(q * t) * std::sin(p * t) + ring * p * std::cos(p * t));
    const glm::dvec3 tan = glm::normalize(dc);
    const glm::dvec3 nrm = glm::normalize(glm::dvec3(0, 1, 0) - tan.y * tan);
    const glm::dvec3 bin = glm::cross(tan, nrm);
    for (int j = 0; j < sides; ++j) {
      const double phi = kTwoPi * j / sides;
      const glm::dvec3 out = std::cos(phi) * nrm + std::sin(phi) * bin;
      addVertex(m, glm::vec3(c + static_cast<double>(tube) * out), glm::vec3(out), {toUnit(i, segments), toUnit(j, sides)});
    }
  }
  // Around the tube (+j, from nrm towards bin = tan x nrm) then along the curve (+i) is
  // counter-clockwise seen from outside: cross(bin, tan) = nrm points out.
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      const int a = i * sides + j, b = i * sides + (j + 1) % sides, c = ((i + 1) % segments) * sides + j,
                d = ((i + 1) % segments) * sides + (j + 1) % sides;
      addTriangle(m, a, b, c);
      addTriangle(m, c, b, d);
    }
  return finish(std::move(m), "torus knot");
}

void computeWeldedNormals(Mesh& mesh) {
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return (static_cast<size_t>(k.x) * 0x9e3779b97f4a7c15ULL) ^ (static_cast<size_t>(k.y) * 0xbf58476d1ce4e5b9ULL) ^
             (static_cast<size_t>(k.z) * 0x94d049bb133111ebULL);
    }
  };
  const auto bits = [](float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); };  // -0 welds to +0
  std::unordered_map<Key, uint32_t, KeyHash> first;
  std::vector<uint32_t> weld(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    weld[i] = first.try_emplace(Key{bits(p.x), bits(p.y), bits(p.z)}, static_cast<uint32_t>(i)).first->second;
  }
  std::vector<glm::dvec3> acc(mesh.positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
    const glm::dvec3 n = glm::cross(pb - pa, pc - pa);  // length = twice the area
    acc[weld[a]] += n, acc[weld[b]] += n, acc[weld[c]] += n;
  }
  mesh.normals.resize(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3 n = acc[weld[i]];
    const double len = glm::length(n);
    mesh.normals[i] = len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

}  // namespace penumbra::engine
