// The fast pipeline against the scalar reference rasterizer, bit for bit, on every SIMD target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "raster/reference.h"
#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

enum class Kind { Random, Sliver, SubPixel, Huge, OnCentres, AxisAligned };

// A random triangle of the given kind, in screen pixels.
void randomTriangle(std::mt19937_64& rng, Kind kind, int width, int height, double p[3][2]) {
  std::uniform_real_distribution<double> ux(-8.0, width + 8.0), uy(-8.0, height + 8.0), unit(0.0, 1.0);
  switch (kind) {
    case Kind::Random:
      for (auto& v : std::span(p, 3)) v[0] = ux(rng), v[1] = uy(rng);
      break;
    case Kind::Sliver: {
      const double x0 = ux(rng), y0 = uy(rng), x1 = ux(rng), y1 = uy(rng), t = unit(rng), off = (unit(rng) - 0.5) * 0.05;
      p[0][0] = x0, p[0][1] = y0, p[1][0] = x1, p[1][1] = y1;
      p[2][0] = x0 + t * (x1 - x0) - off * (y1 - y0), p[2][1] = y0 + t * (y1 - y0) + off * (x1 - x0);
      break;
    }
    case Kind::SubPixel: {
      const double cx = ux(rng), cy = uy(rng);
      for (auto& v : std::span(p, 3)) v[0] = cx + unit(rng) * 1.2, v[1] = cy + unit(rng) * 1.2;
      break;
    }
    case Kind::Huge: {
      std::uniform_real_distribution<double> big(-20000.0, 20000.0);
      for (auto& v : std::span(p, 3)) v[0] = big(rng), v[1] = big(rng);
      break;
    }
    case Kind::OnCentres: {
      // Vertices exactly on pixel centres, so edges pass exactly through many centres.
      std::uniform_int_distribution<int> ix(-2, width + 2), iy(-2, height + 2);
      for (auto& v : std::span(p, 3)) v[0] = ix(rng) + 0.5, v[1] = iy(rng) + 0.5;
      break;
    }
    case Kind::AxisAligned: {
      std::uniform_int_distribution<int> ix(-2, width + 2), iy(-2, height + 2);
      const double x0 = ix(rng) + 0.5, y0 = iy(rng) + 0.5, x1 = ix(rng) + 0.5, y1 = iy(rng) + 0.5;
      const bool upper = unit(rng) < 0.5;
      p[0][0] = x0, p[0][1] = y0, p[1][0] = x1, p[1][1] = upper ? y0 : y1, p[2][0] = upper ? x1 : x0, p[2][1] = y1;
      break;
    }
  }
}

struct Case {
  Kind kind;
  int count;
};

void compareAgainstReference(int64_t target) {
  const int width = 67, height = 53;  // not multiples of 8: exercises partial blocks and tiles
  Rasterizer r({.threads = 2, .tileLog2 = 4, .simd = {.tile = target}});
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> uw(0.5, 4.0), uz(0.05, 0.95);
  const Case cases[] = {{Kind::Random, 600}, {Kind::Sliver, 600}, {Kind::SubPixel, 600},
                        {Kind::Huge, 200},   {Kind::OnCentres, 600}, {Kind::AxisAligned, 400}};
  for (const Case& c : cases) {
    for (int n = 0; n < c.count; ++n) {
      double p[3][2];
      randomTriangle(rng, c.kind, width, height, p);
      glm::vec4 v[3];
      for (int k = 0; k < 3; ++k) v[k] = test::clipFromScreen(p[k][0], p[k][1], uz(rng), uw(rng), width, height);
      std::vector<uint32_t> ref(static_cast<size_t>(width * height), 0);
      reference::coverage(reference::snap(v, width, height), width, height, ref);
      const uint32_t idx[3] = {0, 1, 2};
      const auto got = test::drawCount(r, width, height, v, idx);
      ASSERT_EQ(got, ref) << "target " << simdTargetName(target) << " kind " << static_cast<int>(c.kind)
                          << " triangle " << n << ": (" << p[0][0] << "," << p[0][1] << ") (" << p[1][0] << ","
                          << p[1][1] << ") (" << p[2][0] << "," << p[2][1] << ")";
      // The depth-only path covers the same pixels.
      DepthTarget depth(width, height, 1.0f);
      DrawDesc d;
      d.vertexCount = 3;
      d.depthFunc = DepthFunc::Always;
      r.drawDepth(d, depth, [&](uint32_t i) { return v[i]; });
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          ASSERT_EQ(depth.at(x, y) != 1.0f || ref[static_cast<size_t>(y * width + x)] == 0, true)
              << "depth-only wrote an uncovered pixel " << x << "," << y;
    }
  }
}

TEST(Coverage, MatchesReferenceOnEverySimdTarget) {
  const auto targets = supportedSimdTargets();
  ASSERT_FALSE(targets.empty());
  for (int64_t t : targets) compareAgainstReference(t);
}

// The depth-tested pipeline against a scalar model, for every depth test and write mode on every
// SIMD target: triangles from below a pixel to 40 pixels wide (the tile stage's tiny one-block,
// small box of up to 2 x 2 blocks, its block-by-block fallback where coarse depth hides one of
// them, and large paths), crossing block and tile borders, drawn in order over each
// other. The model takes coverage from the reference rasterizer and each pixel's depth from the
// set-up plane (depthAt), tests and writes pixel by pixel; the fast path must leave the same depth
// image, shade the same pixels the same number of times and count the same passes (and, with no
// depth test, the same covered pixels); every target counts the same blocks and pixels.
TEST(DepthTest, EqualsAScalarModelForEveryFunctionOnEverySimdTarget) {
  const int width = 67, height = 53;
  const Viewport vp{width, height};
  const GuardPlanes guard = guardPlanes(vp);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<glm::vec4> verts;
  const double sizes[] = {0.8, 2.0, 3.5, 6.0, 7.9, 12.0, 40.0};
  for (int n = 0; n < 1400; ++n) {
    const double size = sizes[n % 7], cx = unit(rng) * (width + 8) - 4, cy = unit(rng) * (height + 8) - 4;
    const double z = 0.05 + 0.9 * unit(rng), w = 0.5 + 3.0 * unit(rng);
    for (int k = 0; k < 3; ++k)
      verts.push_back(test::clipFromScreen(cx + (unit(rng) - 0.5) * size, cy + (unit(rng) - 0.5) * size,
                                           std::clamp(z + (unit(rng) - 0.5) * 0.1, 0.0, 1.0), w, width,
                                           height));
  }
  std::vector<uint32_t> idx(verts.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<uint32_t>(i);

  for (const DepthFunc func : {DepthFunc::Less, DepthFunc::Greater, DepthFunc::Always})
    for (const bool write : {true, false}) {
      const float clearValue = func == DepthFunc::Greater ? 0.0f : 1.0f;
      // The model.
      std::vector<float> depth(static_cast<size_t>(width * height), clearValue);
      std::vector<uint32_t> passes(depth.size(), 0);
      uint64_t passed = 0, covered = 0;
      for (size_t t = 0; t < verts.size(); t += 3) {
        ScreenVert sv[3];
        for (int k = 0; k < 3; ++k) {
          const glm::vec4& c = verts[t + static_cast<size_t>(k)];
          sv[k] = projectVertex(c.x, c.y, c.z, c.w, vp, guard);
          ASSERT_EQ(sv[k].flags & (kNeedsClip | kNonFinite), 0u);
        }
        SetupTri st;
        int order[3];
        if (setupTriangle(sv[0], sv[1], sv[2], CullMode::None, vp, st, nullptr, order) != SetupResult::Ok)
          continue;
        std::vector<uint32_t> cov(depth.size(), 0);
        reference::coverage(reference::snap(&verts[t], width, height), width, height, cov);
        for (int y = 0; y < height; ++y)
          for (int x = 0; x < width; ++x) {
            const size_t i = static_cast<size_t>(y * width + x);
            if (cov[i] == 0) continue;
            ++covered;
            const float zp = depthAt(st, x, y);
            const bool pass =
                func == DepthFunc::Always || (func == DepthFunc::Less ? zp < depth[i] : zp > depth[i]);
            if (!pass) continue;
            ++passes[i];
            ++passed;
            if (write) depth[i] = zp;
          }
      }
      std::optional<PassStats> first;  // the first target's counters, which every target must repeat
      for (int64_t target : supportedSimdTargets()) {
        Rasterizer r({.threads = 2, .tileLog2 = 4, .simd = {.tile = target}});
        DrawDesc d;
        d.vertexCount = static_cast<uint32_t>(verts.size());
        d.indices = idx;
        d.depthFunc = func;
        d.depthWrite = write;
        DepthTarget dt(width, height, clearValue);
        const PassStats st = r.drawDepth(d, dt, [&](uint32_t i) { return verts[i]; });
        EXPECT_EQ(st.pixelsDepthPassed, passed) << simdTargetName(target);
        // Without a depth test no block is hidden, so every covered pixel is counted once.
        if (func == DepthFunc::Always) {
          EXPECT_EQ(st.pixelsCovered, covered) << simdTargetName(target);
        }
        if (!first) first = st;
        EXPECT_EQ(st.blocksRejectedEdge, first->blocksRejectedEdge) << simdTargetName(target);
        EXPECT_EQ(st.blocksRejectedDepth, first->blocksRejectedDepth) << simdTargetName(target);
        EXPECT_EQ(st.blocksAccepted, first->blocksAccepted) << simdTargetName(target);
        EXPECT_EQ(st.blocksPartial, first->blocksPartial) << simdTargetName(target);
        EXPECT_EQ(st.pixelsTested, first->pixelsTested) << simdTargetName(target);
        EXPECT_EQ(st.pixelsCovered, first->pixelsCovered) << simdTargetName(target);
        for (int y = 0; y < height; ++y)
          for (int x = 0; x < width; ++x)
            ASSERT_EQ(dt.at(x, y), depth[static_cast<size_t>(y * width + x)])
                << simdTargetName(target) << " func " << static_cast<int>(func) << " write " << write
                << " at " << x << "," << y;
        DepthTarget dt2(width, height, clearValue);
        std::vector<uint32_t> shaded(depth.size(), 0);
        r.draw(
            d, dt2, [&](uint32_t i, float*) { return verts[i]; },
            [&](const Fragment& f) { ++shaded[static_cast<size_t>(f.y * width + f.x)]; });
        EXPECT_EQ(shaded, passes) << simdTargetName(target) << " func " << static_cast<int>(func) << " write "
                                  << write;
      }
    }
}

TEST(Coverage, FaceCulling) {
  const int width = 32, height = 32;
  Rasterizer r({.threads = 1});
  // Counter-clockwise in NDC: front-facing.
  const glm::vec4 ccw[3] = {{-0.8f, -0.8f, 0.5f, 1.0f}, {0.8f, -0.8f, 0.5f, 1.0f}, {0.0f, 0.8f, 0.5f, 1.0f}};
  const glm::vec4 cw[3] = {ccw[0], ccw[2], ccw[1]};
  const uint32_t idx[3] = {0, 1, 2};
  auto covered = [&](const glm::vec4* v, CullMode m) {
    const auto c = test::drawCount(r, width, height, std::span(v, 3), idx, m);
    uint64_t n = 0;
    for (uint32_t x : c) n += x;
    return n;
  };
  EXPECT_GT(covered(ccw, CullMode::Back), 0u);
  EXPECT_EQ(covered(ccw, CullMode::Front), 0u);
  EXPECT_EQ(covered(cw, CullMode::Back), 0u);
  EXPECT_GT(covered(cw, CullMode::Front), 0u);
  EXPECT_EQ(covered(ccw, CullMode::None), covered(cw, CullMode::None));
}

TEST(Coverage, ExactAreaOfAxisAlignedRectangle) {
  // A rectangle with corners between pixel centres covers exactly its area in pixels.
  const int width = 40, height = 30;
  Rasterizer r({.threads = 2});
  const glm::vec4 v[4] = {test::clipFromScreen(3, 4, 0.5, 1, width, height), test::clipFromScreen(23, 4, 0.5, 1, width, height),
                          test::clipFromScreen(23, 17, 0.5, 1, width, height), test::clipFromScreen(3, 17, 0.5, 1, width, height)};
  const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  const auto c = test::drawCount(r, width, height, v, idx);
  uint64_t n = 0;
  for (uint32_t x : c) {
    EXPECT_LE(x, 1u);
    n += x;
  }
  EXPECT_EQ(n, 20u * 13u);
}

TEST(Coverage, NonFiniteVerticesAreDroppedAndCounted) {
  const int width = 16, height = 16;
  Rasterizer r({.threads = 1});
  const float nan = std::nanf("");
  const glm::vec4 v[4] = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {0, 1, 0.5f, 1}, {nan, 0, 0.5f, 1}};
  const uint32_t idx[9] = {0, 1, 2, 0, 1, 3, 0, 1, 7};  // second uses NaN, third an out-of-range index
  PassStats st;
  test::drawCount(r, width, height, v, idx, CullMode::None, &st);
  EXPECT_EQ(st.verticesNonFinite, 1u);
  EXPECT_EQ(st.trianglesDroppedInvalid, 2u);
  EXPECT_EQ(st.trianglesBinned, 1u);
}

}  // namespace
}  // namespace penumbra::raster
