// The stochastic rasterizer: bounding methods agree bit for bit and differ only in test counts;
// determinism across thread counts; the static shortcut; the resolve; stress cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "stochastic/rasterizer.h"
#include "test_scenes.h"

namespace penumbra::stochastic {
namespace {

constexpr int kW = 96, kH = 64;

struct RunResult {
  StochasticStats stats;
  std::vector<uint32_t> tri;
  std::vector<float> depth;
  std::vector<uint8_t> resolved;  // the resolved pixels' bytes
};

RunResult render(const test::MovingSoup& s, const ThinLens& lens, BoundMethod m, int spp, int threads = 2,
           bool motion = true, bool shortcut = true, bool exhaustive = false, LensShape shape = LensShape::Disk,
           int blockStrata = 0) {
  raster::Rasterizer r({.threads = threads});
  StochasticRasterizer sr(r);
  StochasticInput in{s.clip0, s.clip1, s.indices, s.surface, raster::CullMode::None, lens, motion};
  StochasticConfig cfg;
  cfg.method = m;
  cfg.pattern.spp = spp;
  cfg.staticShortcut = shortcut;
  cfg.exhaustive = exhaustive;
  cfg.pattern.shape = shape;
  cfg.pattern.blockStrata = blockStrata;
  raster::Image<ResolvedPixel> out(kW, kH);
  RunResult run;
  StochasticDebug dbg;
  dbg.sampleTriangle = &run.tri;
  dbg.sampleDepth = &run.depth;
  run.stats = sr.render(in, cfg, {}, out, dbg);
  for (int y = 0; y < kH; ++y) {
    const auto* row = reinterpret_cast<const uint8_t*>(out.row(y));
    run.resolved.insert(run.resolved.end(), row, row + sizeof(ResolvedPixel) * kW);
  }
  return run;
}

void expectSameImage(const RunResult& a, const RunResult& b, const char* what) {
  ASSERT_EQ(a.tri.size(), b.tri.size());
  EXPECT_EQ(a.tri, b.tri) << what;
  EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0) << what;
  EXPECT_EQ(a.resolved, b.resolved) << what;
}

struct Case {
  const char* name;
  test::MovingSoup soup;
  ThinLens lens;
};

std::vector<Case> cases() {
  const glm::mat4 proj = test::testProjection(kW, kH);
  std::vector<Case> c;
  std::mt19937 rng(5);
  c.push_back({"motion", test::randomSoup(rng, 120, proj, 2.0f, 12.0f, 0.6f, 2.5f), ThinLens{}});
  c.push_back({"defocus", test::randomSoup(rng, 120, proj, 1.0f, 15.0f, 0.6f, 0.0f),
               makeThinLens(proj[0][0], proj[1][1], 0.25f, 5.0f)});
  c.push_back({"both", test::randomSoup(rng, 120, proj, 1.0f, 15.0f, 0.6f, 2.0f),
               makeThinLens(proj[0][0], proj[1][1], 0.25f, 5.0f)});
  c.push_back({"near-plane crossings", test::randomSoup(rng, 60, proj, -2.0f, 3.0f, 1.0f, 3.0f), ThinLens{}});
  return c;
}

TEST(StochasticRasterizer, BoundingMethodsGiveIdenticalImagesAndTheTighterOnesTestFewer) {
  for (const Case& c : cases())
    for (int spp : {4, 16}) {
      const RunResult all = render(c.soup, c.lens, BoundMethod::Box, spp, 2, true, true, true);
      const RunResult box = render(c.soup, c.lens, BoundMethod::Box, spp);
      const RunResult interval = render(c.soup, c.lens, BoundMethod::Interval, spp);
      const RunResult dual = render(c.soup, c.lens, BoundMethod::DualSpace, spp);
      SCOPED_TRACE(std::string(c.name) + " spp " + std::to_string(spp));
      // Every bound is conservative: the same samples as testing all of them.
      expectSameImage(all, box, "box vs every sample");
      EXPECT_EQ(box.stats.hits, all.stats.hits);
      expectSameImage(box, interval, "interval vs box");
      expectSameImage(box, dual, "dual vs box");
      EXPECT_GT(box.stats.hits, 1000u);
      EXPECT_EQ(interval.stats.hits, box.stats.hits);
      EXPECT_EQ(dual.stats.hits, box.stats.hits);
      // Every covered sample is found by every method (hits equal), with fewer tests.
      EXPECT_LT(interval.stats.tests, box.stats.tests);
      EXPECT_LT(dual.stats.tests, box.stats.tests);
      if (std::string(c.name) != "near-plane crossings") {  // (braces: gtest macros)
        EXPECT_LT(interval.stats.tests * 10, box.stats.tests * 8) << "interval should save at least 20%";
        EXPECT_LT(dual.stats.tests * 10, box.stats.tests * 8) << "dual space should save at least 20%";
      }
    }
}

// A rectangular area light used as the lens (stochastic soft shadow maps): the square lens, one
// sample per pixel in 4 x 4 block strata, or 4 per pixel; every bound still tests a superset.
TEST(StochasticRasterizer, SquareLensBoundsMatchTestingEverySample) {
  const glm::mat4 proj = test::testProjection(kW, kH);
  std::mt19937 rng(11);
  const test::MovingSoup soup = test::randomSoup(rng, 120, proj, 1.0f, 15.0f, 0.6f, 0.0f);
  ThinLens lens = makeThinLens(proj[0][0], proj[1][1], 0.3f, 5.0f);
  lens.ky *= 0.5f;  // a 2:1 rectangle
  for (const auto& [spp, strata] : {std::pair{1, 4}, std::pair{1, 0}, std::pair{4, 0}}) {
    SCOPED_TRACE("spp " + std::to_string(spp) + " strata " + std::to_string(strata));
    const RunResult all =
        render(soup, lens, BoundMethod::Box, spp, 2, false, true, true, LensShape::Square, strata);
    EXPECT_GT(all.stats.hits, 0u);
    for (BoundMethod m : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace}) {
      const RunResult r = render(soup, lens, m, spp, 3, false, true, false, LensShape::Square, strata);
      expectSameImage(all, r, boundMethodName(m));
      EXPECT_LE(r.stats.tests, all.stats.tests);
    }
  }
}

TEST(SamplePattern, SquareLensBlockStrataTakeEveryCellOnce) {
  SamplePattern p;
  p.spp = 1;
  p.motion = false;
  p.shape = LensShape::Square;
  p.blockStrata = 4;
  bool anyOutsideDisk = false;
  for (int by = 0; by < 3; ++by)
    for (int bx = 0; bx < 3; ++bx) {
      int seen[16] = {};
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          Sample s, again;
          pixelSamples(p, 4 * bx + i, 4 * by + j, &s);
          pixelSamples(p, 4 * bx + i, 4 * by + j, &again);
          EXPECT_EQ(std::memcmp(&s, &again, sizeof s), 0);
          ASSERT_GE(s.u, -1.0f);
          ASSERT_LT(s.u, 1.0f);
          ASSERT_GE(s.v, -1.0f);
          ASSERT_LT(s.v, 1.0f);
          anyOutsideDisk = anyOutsideDisk || s.u * s.u + s.v * s.v > 1.0f;
          const int cx = static_cast<int>((s.u + 1.0f) * 2.0f), cy = static_cast<int>((s.v + 1.0f) * 2.0f);
          ++seen[cy * 4 + cx];
        }
      for (int c = 0; c < 16; ++c) EXPECT_EQ(seen[c], 1) << "block " << bx << "," << by << " cell " << c;
    }
  EXPECT_TRUE(anyOutsideDisk);  // the square's corners are used, not only the disk
}

TEST(SamplePattern, SquareLensBlockStrataWithMotionTakeEveryShutterStratumOnce) {
  // With motion the block's 16 pixels also take the shutter's 16 strata once each; the lens points
  // are those without motion; which time goes with which lens cell varies from block to block
  // (a second permutation): over many blocks the two are uncorrelated.
  SamplePattern p;
  p.spp = 1;
  p.shape = LensShape::Square;
  p.blockStrata = 4;
  SamplePattern still = p;
  still.motion = false;
  double sumCT = 0, sumC = 0, sumT = 0, sumCC = 0, sumTT = 0;
  int n = 0, samePairing = 0;
  for (int by = 0; by < 16; ++by)
    for (int bx = 0; bx < 16; ++bx) {
      int seen[16] = {};
      bool diagonal = true;  // cell k with stratum k in every pixel of the block
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          Sample s, lens;
          pixelSamples(p, 4 * bx + i, 4 * by + j, &s);
          pixelSamples(still, 4 * bx + i, 4 * by + j, &lens);
          ASSERT_EQ(s.u, lens.u);
          ASSERT_EQ(s.v, lens.v);
          ASSERT_GE(s.t, 0.0f);
          ASSERT_LT(s.t, 1.0f);
          const int stratum = static_cast<int>(s.t * 16.0f);
          ++seen[stratum];
          const int cx = static_cast<int>((s.u + 1.0f) * 2.0f), cy = static_cast<int>((s.v + 1.0f) * 2.0f);
          const double c = cy * 4 + cx, t = stratum;
          diagonal = diagonal && c == t;
          sumCT += c * t, sumC += c, sumT += t, sumCC += c * c, sumTT += t * t, ++n;
        }
      for (int k = 0; k < 16; ++k) ASSERT_EQ(seen[k], 1) << "block " << bx << "," << by << " stratum " << k;
      samePairing += diagonal ? 1 : 0;
    }
  const double cov = sumCT / n - (sumC / n) * (sumT / n);
  const double corr =
      cov / std::sqrt((sumCC / n - (sumC / n) * (sumC / n)) * (sumTT / n - (sumT / n) * (sumT / n)));
  EXPECT_LT(std::abs(corr), 0.1);
  EXPECT_EQ(samePairing, 0);
}

TEST(StochasticRasterizer, DeterministicAcrossThreadCounts) {
  for (const Case& c : cases()) {
    const RunResult one = render(c.soup, c.lens, BoundMethod::DualSpace, 8, 1);
    for (int threads : {2, 5}) {
      const RunResult many = render(c.soup, c.lens, BoundMethod::DualSpace, 8, threads);
      expectSameImage(one, many, c.name);
      EXPECT_EQ(one.stats.tests, many.stats.tests);
      EXPECT_EQ(one.stats.samplesScanned, many.stats.samplesScanned);
    }
  }
}

TEST(StochasticRasterizer, StaticShortcutGivesTheSameSamplesWithOneTestPerPixel) {
  std::mt19937 rng(8);
  const glm::mat4 proj = test::testProjection(kW, kH);
  const test::MovingSoup still = test::randomSoup(rng, 80, proj, 2.0f, 12.0f, 0.8f, 0.0f);
  const RunResult fast = render(still, ThinLens{}, BoundMethod::Box, 16, 2, true, true);
  const RunResult slow = render(still, ThinLens{}, BoundMethod::Box, 16, 2, true, false);
  expectSameImage(fast, slow, "static shortcut");
  EXPECT_EQ(fast.stats.trianglesStatic + fast.stats.trianglesNoSample, 80u);
  EXPECT_EQ(slow.stats.tests, fast.stats.tests * 16);
  EXPECT_EQ(slow.stats.hits, fast.stats.hits * 16);
  EXPECT_EQ(fast.stats.staticShared, slow.stats.hits);
  // Every sample of a pixel agrees.
  for (size_t p = 0; p < fast.tri.size(); p += 16)
    for (size_t k = 1; k < 16; ++k) {
      ASSERT_EQ(fast.tri[p + k], fast.tri[p]);
    }
}

TEST(StochasticRasterizer, ResolveCountsEverySampleOnce) {
  const Case c = cases()[2];
  raster::Rasterizer r({.threads = 2});
  StochasticRasterizer sr(r);
  StochasticInput in{c.soup.clip0, c.soup.clip1, c.soup.indices, c.soup.surface, raster::CullMode::None, c.lens, true};
  StochasticConfig cfg;
  cfg.pattern.spp = 16;
  raster::Image<ResolvedPixel> out(kW, kH);
  std::vector<uint32_t> tri;
  StochasticDebug dbg;
  dbg.sampleTriangle = &tri;
  const StochasticStats st = sr.render(in, cfg, {}, out, dbg);
  uint64_t layered = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const ResolvedPixel& p = out.at(x, y);
      int total = p.background;
      for (int l = 0; l < p.layers; ++l) {
        total += p.layer[l].count;
        if (l > 0) {
          EXPECT_GE(p.layer[l - 1].count, p.layer[l].count);
        }
        // The representative sample is covered by a triangle of that surface.
        const uint32_t t = tri[(static_cast<size_t>(y) * kW + x) * 16 + p.layer[l].sample];
        ASSERT_NE(t, kNoTriangle);
        EXPECT_EQ(p.layer[l].triangle, t);
        EXPECT_EQ(c.soup.surface[t], p.layer[l].surface);
      }
      EXPECT_EQ(total, 16);
      layered += p.layers > 1 ? 1 : 0;
    }
  EXPECT_GT(layered, 50u) << "motion and defocus should blend surfaces in some pixels";
  EXPECT_LE(st.pixelsMerged, layered);
}

// Motion across the whole screen in one shutter, circles of confusion larger than the screen,
// zero-length motion, degenerate and non-finite triangles: no crash, no NaN depth, and the counts
// stay within the samples' bound.
TEST(StochasticRasterizer, StressCasesStayFiniteAndBounded) {
  const glm::mat4 proj = test::testProjection(kW, kH);
  test::MovingSoup s;
  auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 move) {
    for (const glm::vec3& p : {a, b, c}) {
      s.clip0.push_back(proj * glm::vec4(p, 1.0f));
      s.clip1.push_back(proj * glm::vec4(p + move, 1.0f));
      s.indices.push_back(static_cast<uint32_t>(s.indices.size()));
    }
    s.surface.push_back(static_cast<uint32_t>(s.surface.size()));
  };
  tri({-30, -1, -5}, {-29, -1, -5}, {-29.5f, 1, -5}, {60, 0, 0});         // across the screen and beyond
  tri({-1, -1, -0.2f}, {1, -1, -0.2f}, {0, 1, -0.2f}, {0, 0, 0});         // near the lens: huge CoC
  tri({-1, -1, -6}, {1, -1, -6}, {0, 1, -6}, {0, 0, 0});                   // zero-length motion
  tri({0, 0, -5}, {1, 1, -5}, {2, 2, -5}, {1, 0, 0});                      // degenerate (collinear)
  tri({0, 0, -5}, {0, 0, -5}, {0, 0, -5}, {0, 3, 0});                      // a moving point
  tri({-2, -1, 3}, {2, -1, -3}, {0, 2, -4}, {0, 0, 8});                    // through the camera plane
  s.clip0.push_back(glm::vec4(std::nanf(""), 0, 0, 1));                     // non-finite
  s.clip0.push_back(glm::vec4(0, 0, 0.5f, 1));
  s.clip0.push_back(glm::vec4(1, 0, 0.5f, 1));
  for (int k = 0; k < 3; ++k) {
    s.clip1.push_back(s.clip0[s.clip0.size() - 3 + static_cast<size_t>(k)]);
    s.indices.push_back(static_cast<uint32_t>(s.indices.size()));
  }
  s.surface.push_back(99);
  const ThinLens lens = makeThinLens(proj[0][0], proj[1][1], 2.0f, 50.0f);  // huge aperture, far focus
  for (BoundMethod m : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace}) {
    const RunResult run = render(s, lens, m, 16);
    EXPECT_EQ(run.stats.trianglesDropped, 1u);
    for (float z : run.depth) ASSERT_TRUE(std::isfinite(z) && z >= 0.0f && z <= 1.0f);
    EXPECT_LE(run.stats.tests, run.stats.samples * run.stats.triangles);
    EXPECT_GT(run.stats.hits, 0u);
  }
  const RunResult all = render(s, lens, BoundMethod::Box, 16, 2, true, true, true);
  for (BoundMethod m : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace})
    expectSameImage(all, render(s, lens, m, 16), boundMethodName(m));
}

// A whip pan: trajectories whose ends lie thousands of screens away, so that the float rounding of
// the vertex at the sample's time exceeds a fixed pixel margin; the bounds must still hold.
TEST(StochasticRasterizer, BoundsHoldForTrajectoriesFarOffScreen) {
  const glm::mat4 proj = test::testProjection(kW, kH);
  std::mt19937 rng(17);
  test::MovingSoup s = test::randomSoup(rng, 40, proj, 3.0f, 6.0f, 0.8f, 0.0f);
  for (size_t i = 0; i < s.clip0.size(); ++i) {
    const float sweep = 3000.0f * s.clip0[i].w;  // about 3000 screens to each side
    s.clip1[i] = s.clip0[i] + glm::vec4(sweep, 0.0f, 0.0f, 0.0f);
    s.clip0[i].x -= sweep;
  }
  const RunResult all = render(s, ThinLens{}, BoundMethod::Box, 64, 2, true, true, true);
  EXPECT_GT(all.stats.hits, 0u);
  for (BoundMethod m : {BoundMethod::Box, BoundMethod::Interval, BoundMethod::DualSpace})
    expectSameImage(all, render(s, ThinLens{}, m, 64), boundMethodName(m));
}

TEST(StochasticRasterizer, RejectsAFixedSampleOutsideTheShutterOrTheLens) {
  raster::Rasterizer r({.threads = 1});
  StochasticRasterizer sr(r);
  const test::MovingSoup s;
  StochasticInput in{s.clip0, s.clip1, s.indices, s.surface, raster::CullMode::None, ThinLens{}, true};
  raster::Image<ResolvedPixel> out(8, 8);
  for (const Sample bad : {Sample{1.0f, 0.0f, 0.0f}, Sample{-0.1f, 0.0f, 0.0f}, Sample{0.5f, 0.9f, 0.9f},
                           Sample{std::nanf(""), 0.0f, 0.0f}}) {
    StochasticConfig cfg;
    cfg.pattern.fixed = bad;
    EXPECT_THROW(sr.render(in, cfg, {}, out), std::invalid_argument);
  }
}

TEST(SamplePattern, StratifiedInTimeInsideTheDiskAndDeterministic) {
  SamplePattern p;
  p.spp = 16;
  Sample s[kMaxSpp], again[kMaxSpp], other[kMaxSpp];
  double meanU = 0, meanV = 0, corr = 0;
  int n = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      pixelSamples(p, x, y, s);
      pixelSamples(p, x, y, again);
      ASSERT_EQ(std::memcmp(s, again, sizeof(Sample) * 16), 0);
      for (int k = 0; k < 16; ++k) {
        ASSERT_GE(s[k].t, static_cast<float>(k) / 16.0f);
        ASSERT_LT(s[k].t, static_cast<float>(k + 1) / 16.0f);
        ASSERT_LE(s[k].u * s[k].u + s[k].v * s[k].v, 1.0f + 1e-6f);
        meanU += double{s[k].u}, meanV += double{s[k].v};
        corr += (double{s[k].t} - 0.5) * double{s[k].u};
        ++n;
      }
    }
  EXPECT_NEAR(meanU / n, 0.0, 0.02);
  EXPECT_NEAR(meanV / n, 0.0, 0.02);
  EXPECT_NEAR(corr / n, 0.0, 0.02) << "time and lens must be decorrelated";
  p.frame = 1;
  pixelSamples(p, 3, 4, other);
  p.frame = 0;
  pixelSamples(p, 3, 4, s);
  EXPECT_NE(std::memcmp(s, other, sizeof(Sample) * 16), 0);
  // 1 and 64 samples work; a lone sample spans the whole shutter.
  p.spp = 1;
  pixelSamples(p, 0, 0, s);
  EXPECT_GE(s[0].t, 0.0f);
  EXPECT_LT(s[0].t, 1.0f);
  p.spp = 64;
  pixelSamples(p, 0, 0, s);
  for (int k = 1; k < 64; ++k) EXPECT_GT(s[k].t, s[k - 1].t);
}

}  // namespace
}  // namespace penumbra::stochastic
