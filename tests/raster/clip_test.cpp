// Clipping: near-plane and guard-band crossings against the homogeneous reference.
#include <gtest/gtest.h>

#include <cmath>

#include "raster/reference.h"
#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

constexpr int kW = 80, kH = 64;

// Fast-path coverage equals the homogeneous reference on every pixel the reference is sure of.
void expectMatchesHomogeneous(Rasterizer& r, const glm::vec4 v[3], const char* what, int iter, uint64_t* mismatches) {
  const uint32_t idx[3] = {0, 1, 2};
  const auto got = test::drawCount(r, kW, kH, std::span(v, 3), idx);
  const auto ref = reference::homogeneousCoverage(v, kW, kH, 1e-4);
  for (size_t p = 0; p < got.size(); ++p) {
    ASSERT_LE(got[p], 1u);
    if (ref[p] == 2) continue;
    if (got[p] != ref[p]) ++*mismatches;
    ASSERT_EQ(got[p], ref[p]) << what << " iteration " << iter << " pixel " << p % kW << "," << p / kW;
  }
}

TEST(Clip, NearPlaneCrossingsMatchTheHomogeneousReference) {
  Rasterizer r({.threads = 2, .tileLog2 = 5});
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  uint64_t mismatches = 0;
  for (int iter = 0; iter < 400; ++iter) {
    glm::vec4 v[3];
    for (auto& p : v) {
      // w in [-2, 3]: some vertices behind the eye; z within the depth range at w > 0.
      const float w = static_cast<float>(0.5 + 2.5 * u(rng));
      p = glm::vec4(static_cast<float>(u(rng) * 2.0), static_cast<float>(u(rng) * 2.0),
                    static_cast<float>((0.5 + 0.45 * u(rng))) * w, w);
    }
    expectMatchesHomogeneous(r, v, "near", iter, &mismatches);
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST(Clip, GuardBandCrossingsMatchTheHomogeneousReference) {
  Rasterizer r({.threads = 2});
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  uint64_t mismatches = 0;
  PassStats total;
  for (int iter = 0; iter < 300; ++iter) {
    glm::vec4 v[3];
    for (auto& p : v) {
      // NDC up to +-5000 (hundreds of thousands of pixels): far outside the guard band.
      const double scale = (iter % 2) ? 5000.0 : 300.0;
      const float w = static_cast<float>(1.0 + 0.5 * u(rng));
      p = glm::vec4(static_cast<float>(u(rng) * scale) * w, static_cast<float>(u(rng) * scale) * w, 0.5f * w, w);
    }
    expectMatchesHomogeneous(r, v, "guard band", iter, &mismatches);
    PassStats st;
    const uint32_t idx[3] = {0, 1, 2};
    test::drawCount(r, kW, kH, std::span(v, 3), idx, CullMode::None, &st);
    total += st;
  }
  EXPECT_GT(total.trianglesClipped, 50u);
}

TEST(Clip, GuardBandIntersectionsStayAccurateWithLargeWRatios) {
  // One vertex far away (large w), two near the eye and far off to the side: the guard-band
  // intersection lies close to the near vertices, where a float interpolation from the far vertex
  // loses most of its precision (review finding: such triangles used to be dropped).
  Rasterizer r({.threads = 2});
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  uint64_t mismatches = 0;
  for (int iter = 0; iter < 300; ++iter) {
    const float far = static_cast<float>(std::pow(10.0, 3.0 + 2.0 * (u(rng) + 1.0)));
    glm::vec4 v[3];
    v[0] = glm::vec4(static_cast<float>(u(rng)) * far * 0.1f, static_cast<float>(u(rng)) * far * 0.1f, 0.99f * far, far);
    for (int k = 1; k < 3; ++k)
      v[k] = glm::vec4(static_cast<float>(u(rng) * 3000.0), static_cast<float>(u(rng) * 3000.0), 0.9f, 1.0f);
    expectMatchesHomogeneous(r, v, "large w ratio", iter, &mismatches);
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST(Clip, ReviewCaseAtFullHd) {
  // The reported case: fovy 60, near 0.1, far 1e5, 1920x1080.
  const int w = 1920, h = 1080;
  const glm::vec4 v[3] = {{0.0f, 0.0f, 89999.99f, 90000.0f}, {194.8557f, 0.0f, 0.9f, 1.0f}, {0.0f, -3.4641f, 0.9f, 1.0f}};
  Rasterizer r({.threads = 2});
  const uint32_t idx[3] = {0, 1, 2};
  const auto got = test::drawCount(r, w, h, v, idx);
  const auto ref = reference::homogeneousCoverage(v, w, h, 1e-4);
  uint64_t covered = 0;
  for (size_t p = 0; p < got.size(); ++p) {
    covered += got[p];
    if (ref[p] != 2) {
      ASSERT_EQ(got[p], ref[p]) << "pixel " << p % w << "," << p / w;
    }
  }
  EXPECT_GT(covered, uint64_t{w} * h / 8);
}

TEST(Clip, TrianglesBehindTheCameraProduceNothing) {
  Rasterizer r({.threads = 1});
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int iter = 0; iter < 200; ++iter) {
    glm::vec4 v[3];
    for (auto& p : v) {
      const float w = static_cast<float>(-0.01 - 3.0 * (u(rng) + 1.0));  // w < 0: behind
      p = glm::vec4(static_cast<float>(u(rng)) * w, static_cast<float>(u(rng)) * w, 0.5f * w, w);
    }
    const uint32_t idx[3] = {0, 1, 2};
    const auto c = test::drawCount(r, kW, kH, std::span(v, 3), idx);
    for (uint32_t x : c) ASSERT_EQ(x, 0u) << "iteration " << iter;
  }
}

TEST(Clip, BeyondTheFarPlaneProducesNothing) {
  Rasterizer r({.threads = 1});
  const glm::vec4 v[3] = {{-1, -1, 1.5f, 1}, {1, -1, 1.2f, 1}, {0, 1, 1.01f, 1}};
  const uint32_t idx[3] = {0, 1, 2};
  PassStats st;
  const auto c = test::drawCount(r, kW, kH, v, idx, CullMode::None, &st);
  for (uint32_t x : c) ASSERT_EQ(x, 0u);
  EXPECT_EQ(st.trianglesCulledFrustum, 1u);
}

TEST(Clip, DepthStaysInRangeAfterClipping) {
  // A triangle crossing both the near and far planes writes depths within [0, 1] only.
  Rasterizer r({.threads = 1});
  const glm::vec4 v[3] = {{-1, -1, -0.5f, 1}, {1, -1, 1.5f, 1}, {0, 1, 0.5f, 1}};
  DepthTarget depth(kW, kH, 2.0f);
  DrawDesc d;
  d.vertexCount = 3;
  d.depthFunc = DepthFunc::Always;
  PassStats st = r.drawDepth(d, depth, [&](uint32_t i) { return v[i]; });
  EXPECT_EQ(st.trianglesClipped, 1u);
  int written = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float z = depth.at(x, y);
      if (z == 2.0f) continue;
      ++written;
      ASSERT_GE(z, 0.0f);
      ASSERT_LE(z, 1.0f);
    }
  EXPECT_GT(written, 100);
}

}  // namespace
}  // namespace penumbra::raster
