#include "engine/shapes.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
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

}  // namespace penumbra::engine
