// Watertightness: closed tessellations cover every pixel exactly once (or, for closed surfaces
// drawn without culling, an even number of times), under random sub-pixel offsets and rotations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

constexpr int kW = 96, kH = 80;

TEST(Watertight, FansAroundASharedVertex) {
  Rasterizer r({.threads = 2, .tileLog2 = 5});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int iter = 0; iter < 300; ++iter) {
    // Centre anywhere (often exactly on a pixel centre or edge), a fan of n triangles closing a
    // polygon that contains the whole screen, so every pixel must be covered exactly once.
    const double cx = (iter % 3 == 0) ? std::floor(u(rng) * kW) + 0.5 : u(rng) * kW;
    const double cy = (iter % 5 == 0) ? std::floor(u(rng) * kH) : u(rng) * kH;
    const int n = 3 + static_cast<int>(u(rng) * 40);
    const double rot = u(rng) * 2.0 * std::numbers::pi;
    std::vector<glm::vec4> v;
    v.push_back(test::clipFromScreen(cx, cy, 0.5, 1.0 + u(rng), kW, kH));
    for (int i = 0; i < n; ++i) {
      const double a = rot + 2.0 * std::numbers::pi * i / n;
      const double rad = 400.0 * (1.0 + 0.3 * u(rng));
      v.push_back(test::clipFromScreen(cx + rad * std::cos(a), cy + rad * std::sin(a), 0.5, 0.5 + u(rng), kW, kH));
    }
    std::vector<uint32_t> idx;
    for (int i = 0; i < n; ++i) idx.insert(idx.end(), {0u, 1u + static_cast<uint32_t>(i), 1u + static_cast<uint32_t>((i + 1) % n)});
    const auto c = test::drawCount(r, kW, kH, v, idx);
    for (size_t p = 0; p < c.size(); ++p) ASSERT_EQ(c[p], 1u) << "iteration " << iter << " pixel " << p;
  }
}

TEST(Watertight, RandomTriangulationOfTheScreen) {
  // A jittered grid, each cell split along a random diagonal, covering more than the screen.
  Rasterizer r({.threads = 3, .tileLog2 = 4});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int iter = 0; iter < 60; ++iter) {
    const int gx = 4 + static_cast<int>(u(rng) * 20), gy = 4 + static_cast<int>(u(rng) * 20);
    const double ox = u(rng), oy = u(rng);
    std::vector<glm::vec4> v;
    for (int j = 0; j <= gy; ++j)
      for (int i = 0; i <= gx; ++i) {
        const bool border = i == 0 || j == 0 || i == gx || j == gy;
        const double jx = border ? 0.0 : (u(rng) - 0.5) * 0.5, jy = border ? 0.0 : (u(rng) - 0.5) * 0.5;
        const double sx = -3.0 + ox + (i + jx) * (kW + 6.0) / gx, sy = -3.0 + oy + (j + jy) * (kH + 6.0) / gy;
        // Snap some vertices onto pixel centres so edges run exactly through samples.
        const bool centre = u(rng) < 0.3;
        v.push_back(test::clipFromScreen(centre ? std::floor(sx) + 0.5 : sx, centre ? std::floor(sy) + 0.5 : sy,
                                         u(rng), 0.5 + 2.0 * u(rng), kW, kH));
      }
    std::vector<uint32_t> idx;
    auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (gx + 1) + i); };
    for (int j = 0; j < gy; ++j)
      for (int i = 0; i < gx; ++i) {
        if (u(rng) < 0.5)
          idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        else
          idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    const auto c = test::drawCount(r, kW, kH, v, idx);
    for (size_t p = 0; p < c.size(); ++p) ASSERT_EQ(c[p], 1u) << "iteration " << iter << " pixel " << p;
  }
}

// A UV sphere as a closed indexed mesh (shared vertices, outward counter-clockwise winding).
void uvSphere(int rings, int segs, std::vector<glm::dvec3>& pos, std::vector<uint32_t>& idx) {
  pos.clear();
  idx.clear();
  pos.push_back({0, 1, 0});
  for (int k = 1; k < rings; ++k)
    for (int s = 0; s < segs; ++s) {
      const double th = std::numbers::pi * k / rings, ph = 2.0 * std::numbers::pi * s / segs;
      pos.push_back({std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)});
    }
  pos.push_back({0, -1, 0});
  auto ring = [&](int k, int s) { return static_cast<uint32_t>(1 + (k - 1) * segs + (s % segs)); };
  const auto south = static_cast<uint32_t>(pos.size() - 1);
  for (int s = 0; s < segs; ++s) idx.insert(idx.end(), {0u, ring(1, s + 1), ring(1, s)});
  for (int k = 1; k < rings - 1; ++k)
    for (int s = 0; s < segs; ++s)
      idx.insert(idx.end(), {ring(k, s), ring(k, s + 1), ring(k + 1, s + 1), ring(k, s), ring(k + 1, s + 1), ring(k + 1, s)});
  for (int s = 0; s < segs; ++s) idx.insert(idx.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});
}

// Perspective projection of world points (camera at the origin looking down -z).
glm::vec4 project(const glm::dvec3& p, double f, double aspect, double n, double far) {
  const double a = far / (n - far), b = n * far / (n - far);  // z_clip = a z + b, w = -z (zero-to-one)
  return glm::vec4(static_cast<float>(p.x * f / aspect), static_cast<float>(p.y * f), static_cast<float>(a * p.z + b),
                   static_cast<float>(-p.z));
}

glm::dmat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  glm::dvec3 a(g(rng), g(rng), g(rng)), b(g(rng), g(rng), g(rng));
  a = glm::normalize(a);
  b = glm::normalize(b - a * glm::dot(a, b));
  return glm::dmat3(a, b, glm::cross(a, b));
}

TEST(Watertight, TessellatedSphereUnderRandomRotations) {
  Rasterizer r({.threads = 2});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> pos;
  std::vector<uint32_t> idx;
  for (int iter = 0; iter < 40; ++iter) {
    uvSphere(4 + iter % 17, 6 + iter % 23, pos, idx);
    const glm::dmat3 rot = randomRotation(rng);
    // Sub-pixel offsets: move the sphere by a random fraction of a pixel.
    const glm::dvec3 centre((u(rng) - 0.5) * 0.8, (u(rng) - 0.5) * 0.8, -3.0 - u(rng));
    std::vector<glm::vec4> v;
    for (const auto& p : pos) v.push_back(project(centre + rot * p * 0.9, 1.5, double(kW) / kH, 0.1, 100.0));
    // Closed surface, no culling: each ray enters and leaves, so every count is even.
    const auto all = test::drawCount(r, kW, kH, v, idx, CullMode::None);
    uint64_t covered = 0;
    for (size_t p = 0; p < all.size(); ++p) {
      ASSERT_EQ(all[p] % 2, 0u) << "iteration " << iter << " pixel " << p << " covered " << all[p] << " times";
      covered += all[p] != 0;
    }
    EXPECT_GT(covered, 100u);
    // Front faces only: each pixel inside the silhouette exactly once.
    const auto front = test::drawCount(r, kW, kH, v, idx, CullMode::Back);
    for (size_t p = 0; p < front.size(); ++p) ASSERT_EQ(front[p], all[p] / 2) << "iteration " << iter << " pixel " << p;
  }
}

TEST(Watertight, FarFromTheOriginWithNearPlaneAndGuardBandCrossings) {
  // A unit sphere 1e3 .. 1e6 from the origin, in float world coordinates (imprecise vertices, but
  // shared vertices snap identically, so no crack), seen from inside, from just outside (the near
  // plane cuts it) and from close by (guard band clipping). The number of surfaces a pixel's ray
  // crosses between the near and far planes is odd exactly when the ray starts inside the sphere.
  Rasterizer r({.threads = 2});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> pos;
  std::vector<uint32_t> idx;
  uvSphere(24, 48, pos, idx);
  PassStats total;
  uint64_t checked = 0;
  for (int iter = 0; iter < 40; ++iter) {
    const double offset = std::pow(10.0, 3.0 + 3.0 * u(rng));
    const glm::dmat3 rot = randomRotation(rng);
    const double dists[4] = {0.4 * u(rng), 1.0 + 0.02 * u(rng), 1.05 + u(rng), 1.001};
    const double dist = dists[iter % 4];
    const double f = (iter % 4 == 3) ? 0.3 : 1.2, aspect = double(kW) / kH, n = 0.01 + 0.04 * u(rng), far = 10.0;
    const glm::dvec3 world(offset, -offset, offset);
    const glm::dvec3 camera = world + glm::dvec3(0, 0, dist);
    std::vector<glm::vec4> v;
    for (const auto& p : pos) {
      const glm::vec3 wp = glm::vec3(world + rot * p);  // float world position, as a scene holds it
      v.push_back(project(glm::dvec3(wp) - camera, f, aspect, n, far));
    }
    PassStats st;
    const auto all = test::drawCount(r, kW, kH, v, idx, CullMode::None, &st);
    total += st;
    // Float positions at 1e6 are quantised to 1/16: skip pixels whose ray starts near the surface.
    const double margin = 0.15;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const double nx = (x + 0.5) / kW * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / kH * 2.0;
        const glm::dvec3 start = camera + glm::dvec3(nx * aspect / f, ny / f, -1.0) * n;
        const double rad = glm::length(start - world);
        if (std::abs(rad - 1.0) < margin) continue;
        ++checked;
        ASSERT_EQ(all[static_cast<size_t>(y * kW + x)] % 2, rad < 1.0 ? 1u : 0u)
            << "iteration " << iter << " pixel " << x << "," << y << " offset " << offset << " dist " << dist;
      }
  }
  EXPECT_GT(checked, 40u * kW * kH / 3);
  EXPECT_GT(total.trianglesClipped, 30u);
}

}  // namespace
}  // namespace penumbra::raster
