// Multisampling (Rasterizer::drawSamples): per-sample coverage against the scalar reference at
// every sample count, watertightness per sample, depth and barycentrics at the sample position,
// the same bytes at any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "raster/reference.h"
#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

// Per sample s, per pixel: how many fragments the pass produced (depth test off).
std::vector<std::vector<uint32_t>> sampleCounts(Rasterizer& r, int samples, int w, int h,
                                                std::span<const glm::vec4> verts,
                                                std::span<const uint32_t> idx) {
  std::vector<DepthTarget> depth(static_cast<size_t>(samples), DepthTarget(w, h, 1.0f));
  std::vector<std::vector<uint32_t>> count(
      static_cast<size_t>(samples),
      std::vector<uint32_t>(static_cast<size_t>(w) * static_cast<size_t>(h), 0));
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(verts.size());
  d.indices = idx;
  d.depthFunc = DepthFunc::Always;
  d.depthWrite = false;
  r.drawSamples(
      d, depth, [&](uint32_t i, float*) { return verts[i]; },
      [&](const Fragment& f) {
        ++count[static_cast<size_t>(f.sample)]
               [static_cast<size_t>(f.y) * static_cast<size_t>(w) + static_cast<size_t>(f.x)];
      });
  return count;
}

TEST(Msaa, SamplePatternsAreTheStandardOnes) {
  for (int n : {1, 2, 4, 8}) {
    ASSERT_EQ(samplePattern(n).size(), static_cast<size_t>(n));
    // Distinct positions strictly inside the pixel, centred on average for n > 1 (the standard
    // patterns are), multiples of 1/16 pixel.
    int sx = 0, sy = 0;
    for (int i = 0; i < n; ++i) {
      const SampleOffset a = samplePattern(n)[static_cast<size_t>(i)];
      EXPECT_TRUE(a.dx > -8 && a.dx < 8 && a.dy > -8 && a.dy < 8);
      sx += a.dx, sy += a.dy;
      for (int j = 0; j < i; ++j)
        EXPECT_FALSE(a.dx == samplePattern(n)[static_cast<size_t>(j)].dx &&
                     a.dy == samplePattern(n)[static_cast<size_t>(j)].dy);
    }
    EXPECT_EQ(sx, 0);
    EXPECT_EQ(sy, 0);
  }
  EXPECT_TRUE(samplePattern(3).empty());
  EXPECT_TRUE(samplePattern(16).empty());
}

TEST(Msaa, CoverageEqualsTheReferenceAtEverySample) {
  constexpr int kW = 41, kH = 29;
  Rasterizer r({.threads = 2, .tileLog2 = 4});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n : {1, 2, 4, 8}) {
    for (int iter = 0; iter < 120; ++iter) {
      glm::vec4 v[3];
      for (glm::vec4& p : v) {
        // Vertices often on sample positions and pixel centres, so edges run through samples.
        double sx = u(rng) * (kW + 10) - 5, sy = u(rng) * (kH + 10) - 5;
        if (iter % 3 == 0) {
          const SampleOffset o = samplePattern(n)[static_cast<size_t>(iter / 3) % static_cast<size_t>(n)];
          sx = std::floor(sx) + 0.5 + o.dx / 16.0, sy = std::floor(sy) + 0.5 + o.dy / 16.0;
        }
        p = test::clipFromScreen(sx, sy, u(rng), 0.5 + 2.0 * u(rng), kW, kH);
      }
      if (iter % 4 == 1)
        v[2] = test::clipFromScreen(kW * 0.5, -30.0, 0.5, 1.0, kW, kH);  // long thin triangles
      const uint32_t idx[3] = {0, 1, 2};
      const auto fast = sampleCounts(r, n, kW, kH, v, idx);
      const reference::SnappedTriangle t = reference::snap(v, kW, kH);
      for (int s = 0; s < n; ++s) {
        std::vector<uint32_t> ref(static_cast<size_t>(kW) * kH, 0);
        reference::coverage(t, kW, kH, ref, samplePattern(n)[static_cast<size_t>(s)].dx,
                            samplePattern(n)[static_cast<size_t>(s)].dy);
        ASSERT_EQ(fast[static_cast<size_t>(s)], ref)
            << n << " samples, sample " << s << ", iteration " << iter;
      }
    }
  }
}

TEST(Msaa, ClosedTessellationsCoverEverySampleOnce) {
  constexpr int kW = 70, kH = 54;
  Rasterizer r({.threads = 3, .tileLog2 = 4});
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n : {2, 4, 8}) {
    for (int iter = 0; iter < 40; ++iter) {
      // A jittered grid over more than the screen, each cell split along a random diagonal, some
      // vertices exactly on sample positions.
      // Cells of 7 pixels and more, vertices moved by at most 2.1 pixels: no cell folds over.
      const int g = 3 + static_cast<int>(u(rng) * 8);
      std::vector<glm::vec4> v;
      for (int j = 0; j <= g; ++j)
        for (int i = 0; i <= g; ++i) {
          const bool border = i == 0 || j == 0 || i == g || j == g;
          double sx = -2.0 + (i + (border ? 0.0 : (u(rng) - 0.5) * 0.3)) * (kW + 4.0) / g;
          double sy = -2.0 + (j + (border ? 0.0 : (u(rng) - 0.5) * 0.3)) * (kH + 4.0) / g;
          if (!border && u(rng) < 0.3) {
            const SampleOffset o = samplePattern(n)[static_cast<size_t>(i + j) % static_cast<size_t>(n)];
            sx = std::floor(sx) + 0.5 + o.dx / 16.0, sy = std::floor(sy) + 0.5 + o.dy / 16.0;
          }
          v.push_back(test::clipFromScreen(sx, sy, u(rng), 0.5 + u(rng), kW, kH));
        }
      std::vector<uint32_t> idx;
      const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (g + 1) + i); };
      for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
          if (u(rng) < 0.5)
            idx.insert(idx.end(),
                       {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
          else
            idx.insert(idx.end(),
                       {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
      const auto c = sampleCounts(r, n, kW, kH, v, idx);
      for (int s = 0; s < n; ++s)
        for (size_t p = 0; p < c[static_cast<size_t>(s)].size(); ++p)
          ASSERT_EQ(c[static_cast<size_t>(s)][p], 1u) << n << " samples, sample " << s << ", pixel " << p;
    }
  }
}

// Depth and barycentrics are those at the sample position: the clip position the barycentrics
// interpolate projects onto it, and the depth is its z / w.
TEST(Msaa, DepthAndBarycentricsAtTheSamplePosition) {
  constexpr int kW = 48, kH = 36;
  Rasterizer r({.threads = 2});
  const glm::vec4 v[3] = {test::clipFromScreen(3.2, 2.7, 0.2, 0.7, kW, kH),
                          test::clipFromScreen(44.6, 9.1, 0.6, 2.1, kW, kH),
                          test::clipFromScreen(12.3, 33.8, 0.9, 1.3, kW, kH)};
  std::vector<DepthTarget> depth(8, DepthTarget(kW, kH, 1.0f));
  DrawDesc d;
  d.vertexCount = 3;
  size_t checked = 0;
  double worst = 0, worstZ = 0;
  r.drawSamples(
      d, depth, [&](uint32_t i, float*) { return v[i]; },
      [&](const Fragment& f) {
        const glm::dvec4 p = glm::dvec4(v[0]) * double{f.b0} + glm::dvec4(v[1]) * double{f.b1} +
                             glm::dvec4(v[2]) * double{f.b2};
        const SampleOffset o = kSamples8[f.sample];
        const double sx = (p.x / p.w * 0.5 + 0.5) * kW, sy = (0.5 - p.y / p.w * 0.5) * kH;
        worst = std::max(
            {worst, std::abs(sx - (f.x + 0.5 + o.dx / 16.0)), std::abs(sy - (f.y + 0.5 + o.dy / 16.0))});
        worstZ = std::max(worstZ, std::abs(p.z / p.w - double{f.depth}));
        ++checked;
      });
  EXPECT_GT(checked, 8u * 400u);
  EXPECT_LT(worst, 1.0 / 256.0);  // the vertices' snapping to 1/256 pixel
  EXPECT_LT(worstZ, 1e-3);
}

TEST(Msaa, SameSamplesAtAnyThreadCount) {
  constexpr int kW = 150, kH = 110;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::vec4> v;
  for (int i = 0; i < 3000; ++i)
    v.push_back(test::clipFromScreen(u(rng) * kW, u(rng) * kH, u(rng), 0.5 + u(rng), kW, kH));
  std::vector<uint32_t> idx;
  for (int i = 0; i < 2000; ++i)
    for (int k = 0; k < 3; ++k) idx.push_back(static_cast<uint32_t>((i + k * 7) % 3000));
  std::vector<uint64_t> first;
  for (int threads : {1, 2, 5}) {
    Rasterizer r({.threads = threads, .tileLog2 = 5});
    std::vector<DepthTarget> depth(4, DepthTarget(kW, kH, 1.0f));
    std::vector<uint64_t> out(4 * kW * kH, 0);
    DrawDesc d;
    d.vertexCount = static_cast<uint32_t>(v.size());
    d.indices = idx;
    r.drawSamples(
        d, depth, [&](uint32_t i, float*) { return v[i]; },
        [&](const Fragment& f) {
          uint32_t bits;
          std::memcpy(&bits, &f.b1, 4);
          out[static_cast<size_t>(f.sample) * kW * kH + static_cast<size_t>(f.y) * kW +
              static_cast<size_t>(f.x)] = (uint64_t{f.primitive} << 32) | bits;
        });
    for (const DepthTarget& t : depth)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const float zf = t.at(x, y);
          uint32_t z;
          std::memcpy(&z, &zf, 4);
          out.push_back(z);
        }
    if (first.empty())
      first = out;
    else
      EXPECT_EQ(out, first) << threads << " threads";
  }
}

TEST(Msaa, BadSampleCountsAndSizesThrow) {
  Rasterizer r({.threads = 1});
  DrawDesc d;
  std::vector<DepthTarget> three(3, DepthTarget(8, 8));
  const auto vs = [](uint32_t, float*) { return glm::vec4(0); };
  const auto fs = [](const Fragment&) {};
  EXPECT_THROW(r.drawSamples(d, three, vs, fs), std::invalid_argument);
  std::vector<DepthTarget> mixed{DepthTarget(8, 8), DepthTarget(9, 8)};
  EXPECT_THROW(r.drawSamples(d, mixed, vs, fs), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::raster
