// Per-sample exactness: for a fixed (t, u, v), the stochastic test of a pixel's sample equals the
// main pipeline's coverage, depth and fragment when it renders the triangle at that time and lens
// position; for thousands of random triangles and motions, near-plane crossings included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "raster/pipeline.h"
#include "stochastic/coverage.h"
#include "stochastic/rasterizer.h"
#include "test_scenes.h"

namespace penumbra::stochastic {
namespace {

constexpr int kW = 40, kH = 30;

struct PipelinePixel {
  bool covered = false;
  float depth = 0.0f;
  raster::Fragment f{};
  float vary[raster::kMaxVaryings + 3] = {};
};

// The main pipeline's fragments for one triangle (depth test off), per pixel.
std::vector<PipelinePixel> pipelineFragments(raster::Rasterizer& r, const glm::vec4 c[3], const float vary[3][2]) {
  raster::DepthTarget depth(kW, kH, 1.0f);
  std::vector<PipelinePixel> px(kW * kH);
  raster::DrawDesc d;
  d.vertexCount = 3;
  d.varyings = 2;
  d.depthFunc = raster::DepthFunc::Always;
  d.depthWrite = false;
  r.draw(
      d, depth,
      [&](uint32_t i, float* v) {
        v[0] = vary[i][0], v[1] = vary[i][1];
        return c[i];
      },
      [&](const raster::Fragment& f) {
        PipelinePixel& p = px[static_cast<size_t>(f.y * kW + f.x)];
        EXPECT_FALSE(p.covered) << "a pixel shaded twice";
        p.covered = true;
        p.depth = f.depth;
        p.f = f;
        std::memcpy(p.vary, f.varyings, sizeof(float) * 5);
      });
  return px;
}

void expectSameBits(float a, float b, const char* what, int x, int y) {
  uint32_t ua, ub;
  std::memcpy(&ua, &a, 4);
  std::memcpy(&ub, &b, 4);
  EXPECT_EQ(ua, ub) << what << " at (" << x << ", " << y << "): " << a << " vs " << b;
}

struct Counts {
  int triangles = 0, clipped = 0, covered = 0;
};

// Renders `n` random triangles of a soup at random (t, u, v) both ways and compares every pixel.
void compareSoup(const test::MovingSoup& soup, const ThinLens& lens, uint32_t seed, Counts& n) {
  raster::Rasterizer r({.threads = 1});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const SampleTarget target = makeSampleTarget(kW, kH, raster::CullMode::None);
  for (size_t tri = 0; tri < soup.indices.size() / 3; ++tri) {
    const float t = unit(rng);
    float u = unit(rng) * 2.0f - 1.0f, v = unit(rng) * 2.0f - 1.0f;
    if (u * u + v * v > 1.0f) u *= 0.7f, v *= 0.7f;
    glm::vec4 c[3];
    bool clipped = false;
    for (int k = 0; k < 3; ++k) {
      c[k] = clipAt(soup.clip0[tri * 3 + k], soup.clip1[tri * 3 + k], t, u, v, lens);
      clipped |= c[k].z < 0.0f;
    }
    const float vary[3][2] = {{1.0f, 0.25f}, {-3.0f, 7.5f}, {0.5f, 100.0f}};
    const std::vector<PipelinePixel> ref = pipelineFragments(r, c, vary);
    const float* vp[3] = {vary[0], vary[1], vary[2]};
    ++n.triangles;
    n.clipped += clipped ? 1 : 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const PipelinePixel& p = ref[static_cast<size_t>(y * kW + x)];
        float depth = -1.0f;
        const bool cov = sampleCoverage(c, target, x, y, depth);
        ASSERT_EQ(cov, p.covered) << "triangle " << tri << " pixel (" << x << ", " << y << ") t=" << t << " u=" << u
                                  << " v=" << v;
        if (!cov) continue;
        ++n.covered;
        expectSameBits(depth, p.depth, "depth", x, y);
        raster::Fragment f{};
        float out[raster::kMaxVaryings + 3];
        ASSERT_TRUE(sampleFragment(c, vp, 2, target, x, y, f, out));
        expectSameBits(f.depth, p.f.depth, "fragment depth", x, y);
        expectSameBits(f.b0, p.f.b0, "b0", x, y);
        expectSameBits(f.b1, p.f.b1, "b1", x, y);
        expectSameBits(f.b2, p.f.b2, "b2", x, y);
        expectSameBits(f.varyings[0], p.vary[0], "varying 0", x, y);
        expectSameBits(f.varyings[1], p.vary[1], "varying 1", x, y);
        EXPECT_EQ(f.frontFacing, p.f.frontFacing);
      }
  }
}

TEST(StochasticCoverage, MotionMatchesMainPipelinePerSample) {
  std::mt19937 rng(11);
  const glm::mat4 proj = test::testProjection(kW, kH);
  const test::MovingSoup soup = test::randomSoup(rng, 1500, proj, 0.5f, 20.0f, 1.5f, 3.0f);
  Counts n;
  compareSoup(soup, ThinLens{}, 1, n);
  EXPECT_GT(n.covered, 20000);
}

TEST(StochasticCoverage, NearPlaneCrossingsDuringTheShutterMatchMainPipeline) {
  std::mt19937 rng(12);
  const glm::mat4 proj = test::testProjection(kW, kH);
  // Depths from behind the camera to in front, moving by up to 4 units: many vertices cross the
  // camera plane and the near plane while the shutter is open.
  const test::MovingSoup soup = test::randomSoup(rng, 1500, proj, -3.0f, 4.0f, 2.0f, 4.0f);
  Counts n;
  compareSoup(soup, ThinLens{}, 2, n);
  EXPECT_GT(n.clipped, 300);
  EXPECT_GT(n.covered, 10000);
}

TEST(StochasticCoverage, DefocusAndBothMatchMainPipelinePerSample) {
  std::mt19937 rng(13);
  const glm::mat4 proj = test::testProjection(kW, kH);
  const ThinLens lens = makeThinLens(proj[0][0], proj[1][1], 0.4f, 5.0f);
  const test::MovingSoup still = test::randomSoup(rng, 800, proj, 0.3f, 20.0f, 1.5f, 0.0f);
  const test::MovingSoup moving = test::randomSoup(rng, 800, proj, -2.0f, 20.0f, 1.5f, 3.0f);
  Counts a, b;
  compareSoup(still, lens, 3, a);
  compareSoup(moving, lens, 4, b);
  EXPECT_GT(a.covered + b.covered, 10000);
}

// The quick reject on the largest target (16384 x 16384, where its error bound is widest): never
// true for a pixel centre the exact snapped triangle covers. Vertices a few sub-pixel units from
// pixel centres, edges through centres, vertices far off screen inside the guard band.
TEST(StochasticCoverage, QuickRejectNeverRejectsACoveredSampleOnTheLargestTarget) {
  constexpr int kSize = raster::kMaxTargetSize;
  const SampleTarget target = makeSampleTarget(kSize, kSize, raster::CullMode::None);
  std::mt19937 rng(31);
  std::uniform_int_distribution<int> pixel(-12000, kSize + 12000), jitter(-3, 3), choice(0, 3);
  std::uniform_real_distribution<float> wdist(0.05f, 50.0f);
  // Exact: the pipeline's snapped coordinates and its integer edge test with the top-left rule.
  auto exactInside = [&](const glm::vec4 c[3], int px, int py) {
    raster::ScreenVert s[3];
    for (int k = 0; k < 3; ++k) {
      s[k] = raster::projectVertexXY(c[k].x, c[k].y, c[k].z, c[k].w, target.vp, target.guard);
      if (s[k].flags & (raster::kNeedsClip | raster::kNonFinite)) return false;  // (not a quick-reject case)
    }
    const int64_t area = (int64_t{s[1].x} - s[0].x) * (int64_t{s[2].y} - s[0].y) - (int64_t{s[1].y} - s[0].y) * (int64_t{s[2].x} - s[0].x);
    if (area == 0) return false;
    const int o[3] = {0, area < 0 ? 2 : 1, area < 0 ? 1 : 2};
    for (int k = 0; k < 3; ++k) {
      const raster::ScreenVert& a = s[o[k]];
      const raster::ScreenVert& b = s[o[(k + 1) % 3]];
      const int64_t dx = int64_t{b.x} - a.x, dy = int64_t{b.y} - a.y;
      const int64_t bias = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1;
      if (-dy * (int64_t{px} * 256 - a.x) + dx * (int64_t{py} * 256 - a.y) - bias < 0) return false;
    }
    return true;
  };
  // Clip position of sub-pixel point (sx, sy) (units of 1/256 pixel, pixel centres at 256 i) at w.
  auto clipOf = [&](int64_t sx, int64_t sy, float w) {
    const double nx = ((static_cast<double>(sx) + 128.0) / 256.0) / kSize * 2.0 - 1.0;
    const double ny = 1.0 - ((static_cast<double>(sy) + 128.0) / 256.0) / kSize * 2.0;
    return glm::vec4(static_cast<float>(nx * double{w}), static_cast<float>(ny * double{w}), 0.5f * w, w);
  };
  int rejected = 0, covered = 0;
  for (int tri = 0; tri < 20000; ++tri) {
    glm::vec4 c[3];
    int64_t vx[3], vy[3];
    for (int k = 0; k < 3; ++k) {
      vx[k] = int64_t{pixel(rng)} * 256 + jitter(rng);
      vy[k] = int64_t{pixel(rng)} * 256 + jitter(rng);
      c[k] = clipOf(vx[k], vy[k], wdist(rng));
    }
    // Pixels near the vertices and on the edges' midpoints (where edges pass near centres).
    for (int k = 0; k < 3; ++k) {
      const int64_t mx = choice(rng) == 0 ? vx[k] : (vx[k] + vx[(k + 1) % 3]) / 2;
      const int64_t my = choice(rng) == 0 ? vy[k] : (vy[k] + vy[(k + 1) % 3]) / 2;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int px = static_cast<int>(std::clamp<int64_t>(mx / 256 + dx, 0, kSize - 1));
          const int py = static_cast<int>(std::clamp<int64_t>(my / 256 + dy, 0, kSize - 1));
          const bool inside = exactInside(c, px, py);
          const bool quick = certainlyOutside(c, target, px, py);
          ASSERT_FALSE(inside && quick) << "triangle " << tri << " pixel (" << px << ", " << py << ")";
          rejected += quick ? 1 : 0;
          covered += inside ? 1 : 0;
        }
    }
  }
  EXPECT_GT(rejected, 100000) << "the quick reject should decide most misses";
  EXPECT_GT(covered, 50000);
}

TEST(StochasticCoverage, ClipAtKeepsStaticVerticesAndPinholesExact) {
  const glm::vec4 a(0.1f, -0.3f, 0.7f, 1.3f);
  const ThinLens lens = makeThinLens(1.7f, 1.7f, 0.2f, 4.0f);
  for (float t : {0.0f, 0.123f, 0.999f}) {
    const glm::vec4 p = clipAt(a, a, t, 0.0f, 0.0f, ThinLens{});
    EXPECT_EQ(std::memcmp(&p, &a, sizeof p), 0);
    const glm::vec4 q = clipAt(a, a, t, 0.0f, 0.0f, lens);
    EXPECT_EQ(std::memcmp(&q, &a, sizeof q), 0);
  }
  // On the focus plane (w = F) the lens moves nothing.
  const glm::vec4 f(0.3f, 0.2f, 3.0f, 4.0f);
  const glm::vec4 g = clipAt(f, f, 0.5f, 0.9f, -0.4f, lens);
  EXPECT_EQ(g.x, f.x);
  EXPECT_EQ(g.y, f.y);
}

// The whole stochastic rasterizer at one fixed (t, u, v) for every sample equals the main pipeline
// drawing the triangles at that time and lens position with a depth test: same triangle and depth
// in every sample.
TEST(StochasticRasterizer, FixedSampleFrameEqualsMainPipeline) {
  std::mt19937 rng(21);
  const glm::mat4 proj = test::testProjection(kW, kH);
  const test::MovingSoup soup = test::randomSoup(rng, 300, proj, -1.0f, 12.0f, 1.5f, 2.0f);
  const ThinLens lens = makeThinLens(proj[0][0], proj[1][1], 0.3f, 4.0f);
  raster::Rasterizer r({.threads = 2});
  for (const Sample at : {Sample{0.0f, 0.0f, 0.0f}, Sample{0.37f, 0.5f, -0.25f}, Sample{0.99f, -0.7f, 0.6f}}) {
    std::vector<glm::vec4> c(soup.clip0.size());
    for (size_t i = 0; i < c.size(); ++i) c[i] = clipAt(soup.clip0[i], soup.clip1[i], at.t, at.u, at.v, lens);
    raster::DepthTarget depth(kW, kH, 1.0f);
    std::vector<uint32_t> prim(kW * kH, kNoTriangle);
    raster::DrawDesc d;
    d.vertexCount = static_cast<uint32_t>(c.size());
    r.draw(d, depth, [&](uint32_t i, float*) { return c[i]; },
           [&](const raster::Fragment& f) { prim[static_cast<size_t>(f.y * kW + f.x)] = f.primitive; });

    for (BoundMethod m : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace}) {
      StochasticRasterizer sr(r);
      StochasticInput in{soup.clip0, soup.clip1, soup.indices, soup.surface, raster::CullMode::None, lens, true};
      StochasticConfig cfg;
      cfg.method = m;
      cfg.pattern.spp = 2;
      cfg.pattern.fixed = at;
      raster::Image<ResolvedPixel> out(kW, kH);
      std::vector<uint32_t> tri;
      std::vector<float> z;
      StochasticDebug dbg;
      dbg.sampleTriangle = &tri;
      dbg.sampleDepth = &z;
      sr.render(in, cfg, {}, out, dbg);
      for (int p = 0; p < kW * kH; ++p)
        for (int k = 0; k < 2; ++k) {
          ASSERT_EQ(tri[static_cast<size_t>(p * 2 + k)], prim[static_cast<size_t>(p)])
              << boundMethodName(m) << " pixel " << p << " t=" << at.t;
          expectSameBits(z[static_cast<size_t>(p * 2 + k)], depth.at(p % kW, p / kW), "depth", p % kW, p / kW);
        }
    }
  }
}

}  // namespace
}  // namespace penumbra::stochastic
