// Perspective-correct varyings and depth against analytic values.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

TEST(Interpolation, PerspectiveCorrectAgainstRayPlaneIntersection) {
  // A tilted quad in view space, camera at the origin looking down -z. Varyings: the view-space
  // position itself. At each pixel the analytic value is the intersection of the pixel's ray with
  // the quad's plane; depth is the projection of that point.
  const int w = 120, h = 90;
  const double f = 1.0 / std::tan(0.5 * 1.0), aspect = double(w) / h, n = 0.5, far = 50.0;
  const double a = far / (n - far), b = n * far / (n - far);
  const glm::dvec3 p[4] = {{-2, -1.5, -2.0}, {2, -1.5, -9.0}, {2, 1.5, -9.0}, {-2, 1.5, -2.0}};
  std::vector<glm::vec4> clip;
  for (const auto& q : p)
    clip.emplace_back(static_cast<float>(q.x * f / aspect), static_cast<float>(q.y * f), static_cast<float>(a * q.z + b),
                      static_cast<float>(-q.z));
  const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  const glm::dvec3 normal = glm::normalize(glm::cross(p[1] - p[0], p[3] - p[0]));
  const double d0 = glm::dot(normal, p[0]);

  Rasterizer r({.threads = 2});
  DepthTarget depth(w, h, 1.0f);
  DrawDesc d;
  d.vertexCount = 4;
  d.indices = idx;
  d.varyings = 3;
  double maxVaryErr = 0, maxDepthErr = 0;
  int count = 0;
  r.draw(
      d, depth,
      [&](uint32_t i, float* vary) {
        vary[0] = static_cast<float>(p[i].x);
        vary[1] = static_cast<float>(p[i].y);
        vary[2] = static_cast<float>(p[i].z);
        return clip[i];
      },
      [&](const Fragment& frag) {
        // Ray through the pixel centre: direction (x_ndc * aspect / f, y_ndc / f, -1).
        const double nx = (frag.x + 0.5) / w * 2.0 - 1.0, ny = 1.0 - (frag.y + 0.5) / h * 2.0;
        const glm::dvec3 dir(nx * aspect / f, ny / f, -1.0);
        const glm::dvec3 hit = dir * (d0 / glm::dot(normal, dir));
        for (int c = 0; c < 3; ++c) maxVaryErr = std::max(maxVaryErr, std::abs(double{frag.varyings[c]} - hit[c]));
        const double zndc = (a * hit.z + b) / -hit.z;
        maxDepthErr = std::max(maxDepthErr, std::abs(double{frag.depth} - zndc));
        // Barycentrics reproduce the varyings too.
        const uint32_t* tri = &idx[frag.primitive * 3];
        const glm::dvec3 fromBary = double{frag.b0} * p[tri[0]] + double{frag.b1} * p[tri[1]] + double{frag.b2} * p[tri[2]];
        maxVaryErr = std::max(maxVaryErr, glm::length(fromBary - hit));
        ++count;
      });
  EXPECT_GT(count, w * h / 4);
  // Positions span ~10 units; the snap to 1/256 pixel bounds the achievable error.
  EXPECT_LT(maxVaryErr, 2e-3);
  EXPECT_LT(maxDepthErr, 1e-5);
}

TEST(Interpolation, ClippedTrianglesKeepSubmittedBarycentrics) {
  // One triangle crossing the near plane: its fragments' barycentrics must still refer to the
  // submitted vertices (sum to 1, reproduce the varyings).
  const int w = 64, h = 64;
  const glm::vec4 v[3] = {{-0.5f, -0.5f, 0.5f, 1.0f}, {0.5f, -0.5f, 0.5f, 1.0f}, {0.0f, 0.4f, -0.5f, 0.5f}};
  Rasterizer r({.threads = 1});
  DepthTarget depth(w, h, 1.0f);
  DrawDesc d;
  d.vertexCount = 3;
  d.varyings = 1;
  double maxErr = 0;
  int count = 0;
  PassStats st = r.draw(
      d, depth,
      [&](uint32_t i, float* vary) {
        vary[0] = static_cast<float>(i);
        return v[i];
      },
      [&](const Fragment& f) {
        maxErr = std::max(maxErr, double(std::abs(f.b0 + f.b1 + f.b2 - 1.0f)));
        maxErr = std::max(maxErr, double(std::abs(f.b1 * 1.0f + f.b2 * 2.0f - f.varyings[0])));
        ++count;
      });
  EXPECT_EQ(st.trianglesClipped, 1u);
  EXPECT_GT(count, 50);
  EXPECT_LT(maxErr, 1e-5);
}

TEST(Interpolation, DepthIsAffineInScreenSpaceAndMatchesTheVertices) {
  // Three vertices on pixel centres: depth there equals the vertex depth exactly.
  const int w = 32, h = 32;
  const glm::vec4 v[3] = {test::clipFromScreen(2.5, 2.5, 0.25, 1.0, w, h), test::clipFromScreen(28.5, 2.5, 0.75, 2.0, w, h),
                          test::clipFromScreen(2.5, 28.5, 0.5, 3.0, w, h)};
  Rasterizer r({.threads = 1});
  DepthTarget depth(w, h, 1.0f);
  DrawDesc d;
  d.vertexCount = 3;
  r.drawDepth(d, depth, [&](uint32_t i) { return v[i]; });
  EXPECT_NEAR(depth.at(2, 2), 0.25f, 1e-6f);
  // Top-left rule: (28, 2) is on the right end of the top edge... it lies on the edge v1-v2, not owned.
  EXPECT_NEAR(depth.at(15, 2), 0.25f + (0.75f - 0.25f) * 13.0f / 26.0f, 1e-6f);
  EXPECT_NEAR(depth.at(2, 15), 0.25f + (0.5f - 0.25f) * 13.0f / 26.0f, 1e-6f);
}

}  // namespace
}  // namespace penumbra::raster
