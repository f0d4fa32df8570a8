// Procedural shapes: closed 2-manifolds (after welding equal positions), outward winding agreeing
// with the normals, volumes and areas against their closed forms.
#include "engine/shapes.h"

#include "engine/builtin_scenes.h"
#include "engine/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <numbers>
#include <set>
#include <tuple>
#include <utility>

namespace penumbra::engine {
namespace {

// Ids of distinct positions (exact comparison: seams must be bit-identical).
std::vector<int> weld(const Mesh& m, int& distinct) {
  std::map<std::tuple<float, float, float>, int> ids;
  std::vector<int> out;
  for (const glm::vec3& p : m.positions) {
    const auto [it, inserted] = ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<int>(ids.size()));
    out.push_back(it->second);
  }
  distinct = static_cast<int>(ids.size());
  return out;
}

struct Topology {
  int vertices = 0;
  std::map<std::pair<int, int>, int> directed;  // welded directed edge -> uses
  int degenerate = 0;                           // triangles with two equal welded vertices
};

Topology topology(const Mesh& m) {
  Topology t;
  const std::vector<int> id = weld(m, t.vertices);
  for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    const int v[3] = {id[m.indices[i]], id[m.indices[i + 1]], id[m.indices[i + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      ++t.degenerate;
      continue;
    }
    for (int k = 0; k < 3; ++k) ++t.directed[{v[k], v[(k + 1) % 3]}];
  }
  return t;
}

// Every edge used by exactly two triangles, in opposite directions.
void expectClosed(const Mesh& m) {
  const Topology t = topology(m);
  EXPECT_EQ(t.degenerate, 0);
  int bad = 0;
  for (const auto& [edge, uses] : t.directed) {
    const auto reverse = t.directed.find({edge.second, edge.first});
    if (uses != 1 || reverse == t.directed.end() || reverse->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0) << m.name << ": edges not shared by exactly two opposite triangles";
}

int eulerCharacteristic(const Mesh& m) {
  const Topology t = topology(m);
  const int edges = static_cast<int>(t.directed.size()) / 2;
  const int faces = static_cast<int>(m.indices.size() / 3) - t.degenerate;
  return t.vertices - edges + faces;
}

// Divergence theorem: V = sum over triangles of dot(a, cross(b, c)) / 6; > 0 when wound outward.
double signedVolume(const Mesh& m) {
  double v = 0.0;
  for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    const glm::dvec3 a(m.positions[m.indices[i]]), b(m.positions[m.indices[i + 1]]), c(m.positions[m.indices[i + 2]]);
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v;
}

// Winding agrees with the vertex normals, normals are unit length, texcoords in [0, 1].
void expectConsistentAttributes(const Mesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.texcoords.size(), m.positions.size());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (const glm::vec2& uv : m.texcoords) {
    EXPECT_GE(uv.x, 0.0f);
    EXPECT_LE(uv.x, 1.0f);
    EXPECT_GE(uv.y, 0.0f);
    EXPECT_LE(uv.y, 1.0f);
  }
  int disagree = 0;
  for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    const uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
    const glm::vec3 g = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
    const glm::vec3 n = m.normals[a] + m.normals[b] + m.normals[c];
    if (!(glm::dot(g, n) > 0.0f)) ++disagree;
  }
  EXPECT_EQ(disagree, 0) << m.name << ": triangles wound against their normals";
}

void expectBounds(const Mesh& m, glm::vec3 lo, glm::vec3 hi) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.boundsMin[k], lo[k], 1e-5f);
    EXPECT_NEAR(m.boundsMax[k], hi[k], 1e-5f);
  }
}

TEST(Shapes, BoxIsClosedOutwardAndExact) {
  const Mesh m = makeBox({2.0f, 3.0f, 4.0f});
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.indices.size(), 36u);
  expectConsistentAttributes(m);
  expectClosed(m);
  EXPECT_EQ(eulerCharacteristic(m), 2);
  EXPECT_NEAR(signedVolume(m), 24.0, 1e-4);
  expectBounds(m, {-1.0f, -1.5f, -2.0f}, {1.0f, 1.5f, 2.0f});
  // Flat faces: each normal is an axis and the vertex lies on that face.
  for (size_t i = 0; i < m.positions.size(); ++i)
    EXPECT_NEAR(glm::dot(m.positions[i], m.normals[i]), std::abs(glm::dot(glm::vec3(1.0f, 1.5f, 2.0f), m.normals[i])), 1e-6f);
}

TEST(Shapes, SphereIsClosedOutwardAndConverges) {
  for (auto [rings, segments] : {std::pair{2, 3}, std::pair{3, 4}, std::pair{16, 32}, std::pair{7, 13}}) {
    SCOPED_TRACE(testing::Message() << rings << " rings, " << segments << " segments");
    const Mesh m = makeSphere(1.5f, rings, segments);
    expectConsistentAttributes(m);
    expectClosed(m);
    EXPECT_EQ(eulerCharacteristic(m), 2);
    EXPECT_EQ(m.indices.size() / 3, static_cast<size_t>(2 * segments * (rings - 1)));
    EXPECT_GT(signedVolume(m), 0.0);
    for (size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(m.positions[i]), 1.5f, 1e-5f);
      EXPECT_NEAR(glm::dot(m.normals[i], m.positions[i] / 1.5f), 1.0f, 1e-5f);
    }
  }
  // An inscribed polyhedron: volume below the sphere's, within 2% at 64 x 128.
  const double exact = 4.0 / 3.0 * std::numbers::pi * 1.5 * 1.5 * 1.5;
  const double v = signedVolume(makeSphere(1.5f, 64, 128));
  EXPECT_LT(v, exact);
  EXPECT_GT(v, 0.98 * exact);
  expectBounds(makeSphere(1.5f, 16, 32), {-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f});
}

TEST(Shapes, CylinderIsClosedOutwardAndConverges) {
  for (int segments : {3, 4, 17, 64}) {
    SCOPED_TRACE(segments);
    const Mesh m = makeCylinder(0.5f, 2.0f, segments);
    expectConsistentAttributes(m);
    expectClosed(m);
    EXPECT_EQ(eulerCharacteristic(m), 2);
    EXPECT_EQ(m.indices.size() / 3, static_cast<size_t>(4 * segments));
    // An inscribed prism: n/2 r^2 sin(2 pi / n) h exactly.
    const double prism = segments / 2.0 * 0.25 * std::sin(2.0 * std::numbers::pi / segments) * 2.0;
    EXPECT_NEAR(signedVolume(m), prism, 1e-5);
  }
  expectBounds(makeCylinder(0.5f, 2.0f, 64), {-0.5f, -1.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
}

TEST(Shapes, TorusIsClosedOutwardAndConverges) {
  for (auto [rings, segments] : {std::pair{3, 3}, std::pair{32, 16}, std::pair{9, 5}}) {
    SCOPED_TRACE(testing::Message() << rings << " rings, " << segments << " segments");
    const Mesh m = makeTorus(1.0f, 0.25f, rings, segments);
    expectConsistentAttributes(m);
    expectClosed(m);
    EXPECT_EQ(eulerCharacteristic(m), 0);  // genus 1
    EXPECT_GT(signedVolume(m), 0.0);
  }
  const double exact = 2.0 * std::numbers::pi * std::numbers::pi * 1.0 * 0.25 * 0.25;
  const double v = signedVolume(makeTorus(1.0f, 0.25f, 128, 64));
  EXPECT_NEAR(v, exact, 0.01 * exact);
  expectBounds(makeTorus(1.0f, 0.25f, 32, 16), {-1.25f, -0.25f, -1.25f}, {1.25f, 0.25f, 1.25f});
}

float unitRadius(glm::vec3) { return 1.0f; }
float bumpyRadius(glm::vec3 d) { return 1.0f + 0.3f * std::exp((d.y - 1.0f) / 0.01f); }  // a thin spike up

TEST(Shapes, RadialSurfaceIsClosedOutwardAndConverges) {
  for (int div : {1, 3, 16}) {
    SCOPED_TRACE(testing::Message() << div << " cells per face");
    for (auto radius : {unitRadius, bumpyRadius}) {
      const Mesh m = makeRadialSurface(div, radius);
      EXPECT_EQ(m.indices.size() / 3, radialSurfaceTriangles(div));
      expectConsistentAttributes(m);
      expectClosed(m);
      EXPECT_EQ(eulerCharacteristic(m), 2);  // a sphere
      EXPECT_GT(signedVolume(m), 0.0);
    }
  }
  const double exact = 4.0 / 3.0 * std::numbers::pi;
  EXPECT_NEAR(signedVolume(makeRadialSurface(64, unitRadius)), exact, 0.002 * exact);
}

TEST(Shapes, TorusKnotIsClosedOutwardAndTheTubeHasItsVolume) {
  for (auto [segments, sides] : {std::pair{48, 6}, std::pair{300, 16}}) {
    SCOPED_TRACE(testing::Message() << segments << " segments, " << sides << " sides");
    const Mesh m = makeTorusKnot(2, 3, 1.0f, 0.42f, 0.16f, segments, sides);
    EXPECT_EQ(m.indices.size(), size_t{6} * static_cast<size_t>(segments) * static_cast<size_t>(sides));
    expectConsistentAttributes(m);
    expectClosed(m);
    EXPECT_EQ(eulerCharacteristic(m), 0);  // a tube closed on itself
    EXPECT_GT(signedVolume(m), 0.0);
  }
  // A tube of radius r along a curve of length L holds pi r^2 L (Pappus), the curve's length
  // summed over fine steps.
  double length = 0.0;
  const auto curve = [](double t) {
    const double ring = 1.0 + 0.42 * std::cos(3 * t);
    return glm::dvec3(ring * std::cos(2 * t), 0.42 * std::sin(3 * t), ring * std::sin(2 * t));
  };
  for (int i = 0; i < 100000; ++i)
    length += glm::length(curve(2 * std::numbers::pi * (i + 1) / 100000) - curve(2 * std::numbers::pi * i / 100000));
  const double exact = std::numbers::pi * 0.16 * 0.16 * length;
  EXPECT_NEAR(signedVolume(makeTorusKnot(2, 3, 1.0f, 0.42f, 0.16f, 1536, 48)), exact, 0.01 * exact);
}

// meshIsClosed (scene.h), which lets shadow techniques cull the back faces of closed meshes:
// every closed shape, and the built-in scenes' curved meshes, are closed; a plane, a shape wound
// inside out, one with a triangle missing and one with a face turned over are not.
TEST(Shapes, MeshIsClosedOnlyForClosedOutwardSurfaces) {
  const Mesh shapes[] = {makeBox(glm::vec3(1.0f, 2.0f, 0.5f)), makeSphere(0.7f, 12, 24), makeCylinder(0.4f, 1.5f, 20),
                         makeTorus(1.0f, 0.3f, 16, 12), makeTorusKnot(2, 3, 1.0f, 0.42f, 0.16f, 96, 12)};
  for (const Mesh& m : shapes) {
    EXPECT_TRUE(meshIsClosed(m)) << m.name;
    Mesh flipped = m;
    for (size_t t = 0; t < flipped.indices.size(); t += 3) std::swap(flipped.indices[t + 1], flipped.indices[t + 2]);
    EXPECT_FALSE(meshIsClosed(flipped)) << m.name << " inside out";
    Mesh holed = m;
    holed.indices.resize(holed.indices.size() - 3);
    EXPECT_FALSE(meshIsClosed(holed)) << m.name << " with a triangle missing";
    Mesh turned = m;
    std::swap(turned.indices[1], turned.indices[2]);
    EXPECT_FALSE(meshIsClosed(turned)) << m.name << " with a face turned over";
  }
  EXPECT_FALSE(meshIsClosed(makePlane(2.0f, 2.0f, 3)));
  EXPECT_FALSE(meshIsClosed(Mesh{}));
  for (const char* name : {"creature", "knot", "menagerie"}) {
    const Scene s = makeBuiltinScene(name).value();
    int closed = 0;
    for (const Mesh& m : s.meshes) closed += m.closed ? 1 : 0;
    EXPECT_EQ(closed, static_cast<int>(s.meshes.size()) - 1) << name << ": all but the ground";
  }
}

TEST(Shapes, PlaneFacesUpWithOneBoundaryLoop) {
  const Mesh m = makePlane(4.0f, 2.0f, 3);
  expectConsistentAttributes(m);
  EXPECT_EQ(m.positions.size(), 16u);
  EXPECT_EQ(m.indices.size() / 3, 18u);
  double area = 0.0;
  for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    const glm::vec3 a = m.positions[m.indices[i]], b = m.positions[m.indices[i + 1]], c = m.positions[m.indices[i + 2]];
    const glm::vec3 g = glm::cross(b - a, c - a);
    EXPECT_GT(g.y, 0.0f);  // counter-clockwise seen from +y
    area += 0.5 * static_cast<double>(glm::length(g));
  }
  EXPECT_NEAR(area, 8.0, 1e-5);
  // Open surface: interior edges are shared by two opposite triangles, the 4 * 3 boundary edges by one.
  const Topology t = topology(m);
  int boundary = 0;
  for (const auto& [edge, uses] : t.directed) {
    EXPECT_EQ(uses, 1);
    if (!t.directed.count({edge.second, edge.first})) ++boundary;
  }
  EXPECT_EQ(boundary, 12);
  expectBounds(m, {-2.0f, 0.0f, -1.0f}, {2.0f, 0.0f, 1.0f});
}

}  // namespace
}  // namespace penumbra::engine
