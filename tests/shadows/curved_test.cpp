// V on curved and touching geometry, where it is known exactly (docs/techniques/reference.md):
//   - a convex faceted sphere alone under a rectangular light: every ray leaving a facet above its
//     plane misses the sphere, so V = horizonFraction(light, x, facet normal), the clipped-polygon
//     fraction, exactly (the terminator);
//   - a receiver plane tilted so its tangent plane cuts the light, nothing else: V = the same
//     fraction (no self-shadowing acne at any slope);
//   - a cube resting on a plane: on the ground at the foot of a face, the cube hides every light
//     point behind the face's plane, so V tends to the fraction of the light in front of it
//     (contact: no light leaking under the cube).
// The reference is held to its sampling error, every technique to a bound measured here (x1.3 +
// 0.005 margins, as shadow_render_test.cpp's): a regression of the shared bias blocks fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "shadows/area_light.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  Geometry geometry() const { return {positions, indices}; }
  void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // counter-clockwise seen from outside
    const auto base = static_cast<uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c, d});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
};

// A UV sphere (planar quads in two triangles: a convex polyhedron), triangles counter-clockwise
// seen from outside.
Mesh sphere(glm::vec3 c, float radius, int rings, int segments) {
  Mesh m;
  const auto at = [&](int i, int j) {
    const double theta = std::numbers::pi * i / rings, phi = 2.0 * std::numbers::pi * (j % segments) / segments;
    return c + radius * glm::vec3(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                                  static_cast<float>(std::sin(theta) * std::sin(phi)));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const glm::vec3 a = at(i, j), b = at(i + 1, j), cc = at(i + 1, j + 1), d = at(i, j + 1);
      const auto base = static_cast<uint32_t>(m.positions.size());
      m.positions.insert(m.positions.end(), {a, d, cc, b});  // d then c: counter-clockwise from outside
      if (i > 0) m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
      if (i < rings - 1) m.indices.insert(m.indices.end(), {base, base + 2, base + 3});
    }
  return m;
}

// One receiver per triangle of `m` (its centroid and unit face normal) that faces `eye`, in a
// square-ish image; the rest of the image is background.
ReceiverImage facetReceivers(const Mesh& m, glm::vec3 eye) {
  std::vector<Receiver> list;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    const glm::vec3 x = (a + b + c) / 3.0f;
    if (glm::dot(n, eye - x) > 0.0f) list.push_back({x, n, 1u});
  }
  const int w = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(list.size()))));
  ReceiverImage img(w, w);
  for (size_t i = 0; i < list.size(); ++i) img.at(static_cast<int>(i % static_cast<size_t>(w)), static_cast<int>(i / static_cast<size_t>(w))) = list[i];
  return img;
}

raster::ImageFloat run(const TechniqueInfo& t, const ShadowInputs& in, const std::string& params = "") {
  raster::Rasterizer raster({.threads = 2});
  ParamSet p(t.params);
  EXPECT_FALSE(p.setAll(params));
  const ShadowResult r = computeShadows(raster, in, t, p);
  EXPECT_FALSE(r.skipped) << t.name << ": " << r.skipReason;
  return r.visibility;
}

struct Error {
  double rmse = 0, bias = 0, worst = 0;
  size_t n = 0;
};
// Against exact(x, y) over the valid receivers.
template <class Exact>
Error against(const raster::ImageFloat& v, const ReceiverImage& rec, Exact exact) {
  Error e;
  double sq = 0, sum = 0;
  for (int y = 0; y < rec.height(); ++y)
    for (int x = 0; x < rec.width(); ++x) {
      if (!rec.at(x, y).valid) continue;
      const double d = static_cast<double>(v.at(x, y)) - static_cast<double>(exact(rec.at(x, y)));
      sq += d * d, sum += d, e.worst = std::max(e.worst, std::fabs(d));
      ++e.n;
    }
  if (e.n > 0) e.rmse = std::sqrt(sq / static_cast<double>(e.n)), e.bias = sum / static_cast<double>(e.n);
  return e;
}

// Measured RMSE per (case, technique) with the defaults; printed when missing.
struct Bound {
  const char* test;
  const char* technique;
  double rmse;
};
const std::vector<Bound> kBounds = {
#include "curved_bounds.inc"
};

void checkBound(const char* test, const std::string& technique, const Error& e) {
  for (const Bound& b : kBounds)
    if (std::string(b.test) == test && technique == b.technique) {
      EXPECT_LE(e.rmse, b.rmse * 1.3 + 0.005) << test << " / " << technique << " (bias " << e.bias << ")";
      return;
    }
  std::printf("  {\"%s\", \"%s\", %.4f},  // bias %+.4f, worst %.3f\n", test, technique.c_str(), e.rmse, e.bias, e.worst);
  ADD_FAILURE() << "no measured bound for " << test << " / " << technique;
}

// The light: 1.2 x 0.8 at (1.5, 3, 0.5), facing the origin: it lights the sphere from the side, so
// the terminator crosses the visible half.
RectLight sideLight() {
  RectLight l;
  EXPECT_TRUE(makeRectLight({1.5f, 3.0f, 0.5f}, {-1.5f, -3.0f, -0.5f}, {1, 0, 0}, 1.2f, 0.8f, glm::vec3(1), 1, l));
  return l;
}

TEST(CurvedExact, ConvexSphereAloneIsTheClippedPolygonFraction) {
  const Mesh ball = sphere({0, 0, 0}, 1.0f, 48, 96);
  const ReceiverImage rec = facetReceivers(ball, {2.0f, 1.0f, 4.0f});
  ShadowInputs in{.casters = ball.geometry(), .receivers = &rec, .light = sideLight()};
  const auto exact = [&](const Receiver& r) { return horizonFraction(in.light, r.position, r.normal); };
  size_t terminator = 0;
  for (int y = 0; y < rec.height(); ++y)
    for (int x = 0; x < rec.width(); ++x)
      if (rec.at(x, y).valid && exact(rec.at(x, y)) > 0.0f && exact(rec.at(x, y)) < 1.0f) ++terminator;
  EXPECT_GT(terminator, 50u);  // the case does exercise the terminator
  const Error ref = against(run(*findTechnique("reference"), in, "samples=1024"), rec, exact);
  EXPECT_LE(ref.rmse, 0.004) << "worst " << ref.worst;
  EXPECT_LE(ref.worst, 0.03);
  for (const TechniqueInfo& t : registry())
    if (!t.isReference && t.name != "hard") checkBound("sphere", t.name, against(run(t, in), rec, exact));
}

TEST(CurvedExact, TiltedPlaneWhoseTangentPlaneCutsTheLight) {
  // A 6 x 6 plane through the origin tilted 70 degrees about z: the light (centred above x = 0.3)
  // is partly behind it. Receivers on a grid over its middle.
  const float a = 70.0f * std::numbers::pi_v<float> / 180.0f;
  const glm::vec3 u(std::cos(a), std::sin(a), 0.0f), w(0, 0, 1), n = glm::cross(w, u);  // n = (-sin, cos, 0)
  Mesh plane;
  plane.quad(-3.0f * u - 3.0f * w, -3.0f * u + 3.0f * w, 3.0f * u + 3.0f * w, 3.0f * u - 3.0f * w);
  RectLight light;
  ASSERT_TRUE(makeRectLight({0.3f, 3.0f, 0.0f}, {0, -1, 0}, {1, 0, 0}, 2.0f, 1.0f, glm::vec3(1), 1, light));
  ReceiverImage rec(40, 40);
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i)
      rec.at(i, j) = {(-1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / 40.0f) * u +
                          (-1.0f + 2.0f * (static_cast<float>(j) + 0.5f) / 40.0f) * w,
                      n, 1u};
  ShadowInputs in{.casters = plane.geometry(), .receivers = &rec, .light = light};
  const auto exact = [&](const Receiver& r) { return horizonFraction(light, r.position, r.normal); };
  const float mid = exact(rec.at(20, 20));
  EXPECT_GT(mid, 0.1f);
  EXPECT_LT(mid, 0.9f);
  const Error ref = against(run(*findTechnique("reference"), in, "samples=1024"), rec, exact);
  EXPECT_LE(ref.rmse, 0.004);
  for (const TechniqueInfo& t : registry())
    if (!t.isReference && t.name != "hard") checkBound("tilted", t.name, against(run(t, in), rec, exact));
}

TEST(CurvedExact, CubeOnAPlaneHidesTheLightBehindItsFaceAtContact) {
  // A unit cube on the ground y = 0, its face x = 0.5; the light (1 x 1 at height 3, centred over
  // x = 0.3) spans x in [-0.2, 0.8]. Ground receivers at the foot of the face (x = 0.5 + 0.002)
  // see the light points in front of the face's plane, 0.3 of the light; the cube's top (y = 1)
  // hides none of them.
  Mesh m;
  const float h = 0.5f;
  m.quad({-8, 0, 8}, {8, 0, 8}, {8, 0, -8}, {-8, 0, -8});                  // ground, facing +y
  m.quad({h, 0, h}, {h, 0, -h}, {h, 1, -h}, {h, 1, h});                    // +x face
  m.quad({-h, 0, -h}, {-h, 0, h}, {-h, 1, h}, {-h, 1, -h});                // -x face
  m.quad({-h, 1, -h}, {-h, 1, h}, {h, 1, h}, {h, 1, -h});                  // top
  m.quad({-h, 0, h}, {h, 0, h}, {h, 1, h}, {-h, 1, h});                    // +z face
  m.quad({h, 0, -h}, {-h, 0, -h}, {-h, 1, -h}, {h, 1, -h});                // -z face
  RectLight light;
  ASSERT_TRUE(makeRectLight({0.3f, 3.0f, 0.0f}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1, light));
  // The ground in front of the face is a receiver (so that the maps cover a neighbourhood, as in a
  // real frame); the contact row at x = 0.502 is compared.
  ReceiverImage rec(32, 24);
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 32; ++i)
      rec.at(i, j) = {{h + 0.002f + 1.0f * static_cast<float>(j) / 24.0f, 0.0f,
                       -0.3f + 0.6f * (static_cast<float>(i) + 0.5f) / 32.0f},
                      {0, 1, 0},
                      1u};
  ShadowInputs in{.casters = m.geometry(), .receivers = &rec, .light = light};
  const glm::vec3 faceNormal(1, 0, 0);
  const auto exact = [&](const Receiver& r) { return horizonFraction(light, r.position, faceNormal); };
  EXPECT_NEAR(exact(rec.at(0, 0)), 0.298f, 0.003f);
  const auto contactRow = [&](const raster::ImageFloat& v) {
    raster::ImageFloat row(32, 1);
    for (int i = 0; i < 32; ++i) row.at(i, 0) = v.at(i, 0);
    return row;
  };
  ReceiverImage contact(32, 1);
  for (int i = 0; i < 32; ++i) contact.at(i, 0) = rec.at(i, 0);
  const Error ref = against(contactRow(run(*findTechnique("reference"), in, "samples=1024")), contact, exact);
  EXPECT_LE(ref.rmse, 0.01);
  for (const TechniqueInfo& t : registry()) {
    if (t.isReference || t.name == "hard") continue;
    const Error e = against(contactRow(run(t, in)), contact, exact);
    checkBound("contact", t.name, e);
    // The contact goal. The summed-area-table techniques miss it (issue 12's pages: the ESM tail
    // and the Chebyshev bound both leak within a few texels of contact); their measured leak is
    // held instead, so that it cannot grow unnoticed.
    const bool satFamily = t.name == "essm" || t.name == "vssm" || t.name == "savsm" || t.name == "cssm";
    EXPECT_LE(e.bias, satFamily ? 0.35 : 0.1) << t.name << ": light leaking under the cube";
  }
}

}  // namespace
}  // namespace penumbra::shadows
