// Every technique of the registry on analytic cases: a square light, a straight occluder edge
// parallel to it and a parallel receiver plane give a known penumbra (a linear ramp of width
// w (d_r - d_o) / d_o); fully lit and fully blocked receivers give exactly 1 and 0; outputs are in
// [0, 1], finite, and identical at every thread count.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "shadows/area_light.h"
#include "shadows/light_samples.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

// The light: 1 x 1 at height 4 facing down, centred over x = 0. The occluder: the half-plane
// x < 0 at height 2 (a large quad). Receivers: the plane y = 0, x in [-2.5, 2.5], z in [-1, 1].
// A receiver at x sees light points with x_l >= -x, so V(x) = clamp(x + 0.5, 0, 1): a ramp of width
// w (d_r - d_o) / d_o = 1 (2 / 2) = 1.
struct EdgeCase {
  static constexpr int kW = 80, kH = 12;
  std::vector<glm::vec3> positions = {{-20, 2, -20}, {0, 2, -20}, {0, 2, 20}, {-20, 2, 20}};
  std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  ReceiverImage receivers{kW, kH};
  ShadowInputs in;

  EdgeCase() {
    for (int j = 0; j < kH; ++j)
      for (int i = 0; i < kW; ++i) {
        Receiver& r = receivers.at(i, j);
        r.position = {x(i), 0.0f, -1.0f + 2.0f * (static_cast<float>(j) + 0.5f) / kH};
        r.normal = {0, 1, 0};
        r.valid = 1;
      }
    receivers.at(0, 0).valid = 0;  // a background texel
    makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light);
    in.casters = {positions, indices};
    in.receivers = &receivers;
  }
  // Receivers off the light samples' grid (an offset of 0.0123), so that no sample count is exact
  // by accident.
  static float x(int i) { return -2.5f + 5.0f * (static_cast<float>(i) + 0.5f) / kW + 0.0123f; }
  static float exact(int i) { return std::clamp(x(i) + 0.5f, 0.0f, 1.0f); }
};

raster::ImageFloat run(const TechniqueInfo& t, const ShadowInputs& in, int threads,
                       const std::string& params = "") {
  raster::Rasterizer raster({.threads = threads});
  ParamSet p(t.params);
  EXPECT_FALSE(p.setAll(params));
  return computeShadows(raster, in, t, p).visibility;
}

// Mean absolute error against the ramp over the receivers, and the worst.
void rampError(const raster::ImageFloat& v, double& mean, double& worst) {
  double sum = 0;
  int n = 0;
  worst = 0;
  for (int j = 0; j < EdgeCase::kH; ++j)
    for (int i = 0; i < EdgeCase::kW; ++i) {
      if (i == 0 && j == 0) continue;
      const double e = std::abs(static_cast<double>(v.at(i, j)) - static_cast<double>(EdgeCase::exact(i)));
      sum += e, ++n, worst = std::max(worst, e);
    }
  mean = sum / n;
}

// The receivers' plane as a caster (as the ground is in a frame) and a small caster nearer the
// light (y = 3) that shadows only receivers already in the umbra but pulls the map's near plane
// to it: a search box then three times the penumbra box.
void addGroundAndNearCaster(EdgeCase& c) {
  c.positions.insert(c.positions.end(), {{-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}});
  c.positions.insert(c.positions.end(),
                     {{-0.9f, 3, -0.2f}, {-0.8f, 3, -0.2f}, {-0.8f, 3, 0.2f}, {-0.9f, 3, 0.2f}});
  c.indices.insert(c.indices.end(), {4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11});
  c.in.casters = {c.positions, c.indices};
}

// Each setting of a technique against the ramp: mean and worst error below the run's bounds.
struct RampRun {
  const char* params;
  double mean, worst;  // about 1.5x what each measures
};
void expectRamps(const char* technique, const ShadowInputs& in, std::initializer_list<RampRun> runs) {
  for (const RampRun& t : runs) {
    double mean = 0, worst = 0;
    rampError(run(*findTechnique(technique), in, 2, t.params), mean, worst);
    std::printf("%s %s vs analytic ramp: mean |err| %.4f, max %.4f\n", technique, t.params, mean, worst);
    EXPECT_LT(mean, t.mean) << technique << " " << t.params;
    EXPECT_LT(worst, t.worst) << technique << " " << t.params;
  }
}

TEST(Techniques, RangeExactnessAndDeterminism) {
  EdgeCase c;
  for (const TechniqueInfo& t : registry()) {
    SCOPED_TRACE(t.name);
    const raster::ImageFloat v1 = run(t, c.in, 1), v3 = run(t, c.in, 3);
    EXPECT_EQ(v1.at(0, 0), 1.0f) << "background";
    for (int j = 0; j < EdgeCase::kH; ++j)
      for (int i = 0; i < EdgeCase::kW; ++i) {
        const float v = v1.at(i, j);
        ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << i << "," << j << ": " << v;
        ASSERT_EQ(std::bit_cast<uint32_t>(v), std::bit_cast<uint32_t>(v3.at(i, j)))
            << "threads differ at " << i << "," << j;
        if (i == 0 && j == 0) continue;  // background
        // Far from the penumbra [-0.5, 0.5]: exactly 0 in the umbra, exactly 1 in full light. CSSM's
        // truncated Fourier series ripples there (docs/techniques/cssm.md): within 0.01 (0.0042
        // measured).
        const float ripple = t.name == "cssm" ? 0.01f : 0.0f;
        if (EdgeCase::x(i) < -1.5f) {
          ASSERT_LE(v, ripple) << "umbra at x = " << EdgeCase::x(i);
        }
        if (EdgeCase::x(i) > 1.5f) {
          ASSERT_GE(v, 1.0f - ripple) << "lit at x = " << EdgeCase::x(i);
        }
      }
  }
}

TEST(Techniques, MinMaxSkippingChangesNothing) {
  // The min/max pyramid resolves uniformly lit or blocked kernels without taps: same bits. On a
  // scene with several occluders at different heights and a tilted receiver row as well.
  EdgeCase c;
  c.positions.insert(c.positions.end(), {{0.3f, 1.0f, -0.4f}, {0.9f, 1.0f, -0.4f}, {0.6f, 1.2f, 0.5f}});
  c.indices.insert(c.indices.end(), {4, 5, 6});
  c.in.casters = {c.positions, c.indices};
  for (int i = 0; i < EdgeCase::kW; ++i)
    c.receivers.at(i, 11).normal = glm::normalize(glm::vec3(0.4f, 1.0f, 0.1f));
  for (const char* name : {"pcf", "pcss"}) {
    for (const char* extra : {"", "kernel=grid", "map_size=256", "taps=41", "kernel=grid,taps=121"}) {
      if (std::string(name) == "pcss" && std::string(extra).find("taps") != std::string::npos) continue;
      if (std::string(name) == "pcss" && std::string(extra) == "kernel=grid") continue;
      const std::string base = extra;
      const raster::ImageFloat on = run(*findTechnique(name), c.in, 2, base);
      const raster::ImageFloat off =
          run(*findTechnique(name), c.in, 2, base + (base.empty() ? "" : ",") + "minmax=off");
      for (int j = 0; j < EdgeCase::kH; ++j)
        for (int i = 0; i < EdgeCase::kW; ++i)
          ASSERT_EQ(std::bit_cast<uint32_t>(on.at(i, j)), std::bit_cast<uint32_t>(off.at(i, j)))
              << name << " " << extra << " at " << i << "," << j;
    }
  }
}

TEST(Techniques, BehindTheLightIsUnlitAndNoReachableCasterMeansNoPass) {
  EdgeCase c;
  c.receivers.at(5, 5).position.y = 5.0f;  // above the light: behind its emitting side
  raster::Rasterizer raster({.threads = 2});
  const TechniqueInfo& hard = *findTechnique("hard");
  ShadowResult r = computeShadows(raster, c.in, hard, ParamSet(hard.params));
  EXPECT_EQ(r.visibility.at(5, 5), 0.0f);
  EXPECT_FALSE(r.skipped);
  // Move the occluder out of every light path: no pass at all, V = 1.
  for (glm::vec3& p : c.positions) p.y = -3.0f;
  r = computeShadows(raster, c.in, hard, ParamSet(hard.params));
  EXPECT_TRUE(r.skipped);
  EXPECT_EQ(r.trianglesCulled, 2u);
  EXPECT_EQ(r.mapPasses.trianglesIn, 0u);
  EXPECT_EQ(r.visibility.at(40, 6), 1.0f);
}

TEST(Techniques, CastersCrossingTheLightPlaneAreNotClippedByTheNearPlane) {
  // A wall x = 0.6 from below the receivers to above the light (beside it): it hides the light
  // from receivers at x > 0.6 + margin, over depths from ~0 to the receivers. Its vertices in front
  // of the light are all at depth 5; the near plane must still come from the part near the light.
  ReceiverImage rec(32, 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 32; ++i)
      rec.at(i, j) = {
          {1.0f + 2.0f * static_cast<float>(i) / 32.0f, -1.0f, -0.2f + 0.1f * static_cast<float>(j)},
          {0, 1, 0},
          1u};
  const std::vector<glm::vec3> pos = {
      {0.6f, -1.0f, -10.0f}, {0.6f, 10.0f, -10.0f}, {0.6f, -1.0f, 10.0f}, {0.6f, 10.0f, 10.0f}};
  const std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3};
  ShadowInputs in;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light);
  in.casters = {pos, idx};
  in.receivers = &rec;
  for (const TechniqueInfo& t : registry()) {
    // vwss samples the wall from one view behind the light, at a grazing angle: too few points
    // for the light samples' maps (its documented limit), so it is not a near-plane check.
    if (t.name == "vwss") continue;
    // occtex with 64 layers summed: a layer flattens its part of the wall onto one plane, which a
    // wall this steep is not, and multiplied, the bands leak (its documented failures, tested on
    // their own); thin slabs, each rendered from its own near plane, summed, hide the light but
    // for the flattened bands' seams (measured up to 0.11), not where a near plane clipped the
    // wall's top off.
    const raster::ImageFloat v = run(t, in, 2,
                                     t.isReference        ? "samples=64"
                                     : t.name == "occtex" ? "layers=64,fusion=sum"
                                                          : "");
    for (int i = 0; i < 32; ++i) {
      if (t.name == "occtex")
        EXPECT_LT(v.at(i, 1), 0.15f) << t.name << " at " << i;
      else
        EXPECT_EQ(v.at(i, 1), 0.0f) << t.name << " at " << i;
    }
  }
}

TEST(Techniques, PcssMatchesTheAnalyticPenumbra) {
  // Its assumptions (one planar blocker parallel to the light and the receiver) hold here.
  EdgeCase c;
  double mean = 0, worst = 0;
  rampError(run(*findTechnique("pcss"), c.in, 2), mean, worst);
  std::printf("pcss vs analytic ramp: mean |err| %.4f, max %.4f\n", mean, worst);
  EXPECT_LT(mean, 0.01);
  EXPECT_LT(worst, 0.05);
  // A hard shadow is a step: it misses by half the ramp on average over the penumbra.
  rampError(run(*findTechnique("hard"), c.in, 2), mean, worst);
  EXPECT_GT(worst, 0.4);
}

TEST(Techniques, PrefilteredSoftShadowsMatchTheAnalyticPenumbra) {
  // The constant-time family shares PCSS's assumptions, which hold here: each setting must find
  // the ramp (its blocker depth and its width) to within a few hundredths. The receivers' plane is
  // a caster too, as the ground is in a frame: the variance techniques' bound is tight only when a
  // receiver's own surface is in the map around it (moments.h).
  // A small caster nearer the light (y = 3) shadows only receivers already in the umbra, but it
  // pulls the map's near plane to it: the blocker search box is then three times the penumbra box,
  // so a wrong penumbra width cannot hide behind the search box's clamp.
  EdgeCase c;
  addGroundAndNearCaster(c);
  struct Run {
    const char *name, *params;
    double mean, worst;  // bounds: about 1.5x what each measures, so a lost factor shows
  };
  const Run runs[] = {{"essm", "", 0.001, 0.005},
                      {"essm", "sat=integer", 0.001, 0.005},
                      {"essm", "sat=double", 0.001, 0.005},
                      {"essm", "kernel=ellipse", 0.011, 0.09},  // the pixel footprint widens the ramp
                      {"essm", "subdivision=1", 0.001, 0.005},
                      {"essm", "split=adaptive", 0.001, 0.005},
                      {"cssm", "", 0.012, 0.05},  // the smooth step of four Fourier terms
                      {"cssm", "order=8", 0.008, 0.11},
                      {"vssm", "bleed_reduction=0", 0.002, 0.02},
                      {"vssm", "bleed_reduction=0,subdivision=1", 0.002, 0.02},
                      {"savsm", "bleed_reduction=0", 0.002, 0.03},
                      {"pfsvsm", "bleed_reduction=0", 0.01, 0.1},  // box mips and 16 taps
                      {"pfsvsm", "test=pcf", 0.011, 0.16}};
  for (const Run& t : runs) {
    double mean = 0, worst = 0;
    rampError(run(*findTechnique(t.name), c.in, 2, t.params), mean, worst);
    std::printf("%s %s vs analytic ramp: mean |err| %.4f, max %.4f\n", t.name, t.params, mean, worst);
    EXPECT_LT(mean, t.mean) << t.name << " " << t.params;
    EXPECT_LT(worst, t.worst) << t.name << " " << t.params;
  }
}

TEST(Techniques, BackprojectionMatchesTheAnalyticPenumbra) {
  // The straight edge over a plane, with the receivers' plane a caster and the small caster nearer
  // the light that pulls the near plane (and the first search area) up, as for the pre-filtered
  // family: micropatches of the edge's texels, projected onto the light, give the ramp.
  EdgeCase c;
  addGroundAndNearCaster(c);
  expectRamps("backproj", c.in,
              {{"", 0.0025, 0.036},
               {"samples=64", 0.006, 0.12},  // 64 jittered samples: steps of 1/64
               {"samples=1024", 0.0012, 0.017},
               {"occlusion=area", 0.001, 0.004},  // one occluder: no overlap to over-count
               {"search_cap=8", 0.0035, 0.09},    // level 4 and down, mixed texels refined
               {"search_cap=4096", 0.0025, 0.036},
               {"minmax=off", 0.0025, 0.036},
               {"micro=quads", 0.0025, 0.036},
               {"micro=quads_outline", 0.0025, 0.036},
               {"micro=quads,occlusion=area", 0.001, 0.004},
               {"micro=quads,search_cap=8", 0.0035, 0.09},
               {"search=mssm", 0.0025, 0.036},
               {"search=hsm", 0.0025, 0.036}});
}

TEST(Techniques, BackprojectionSearchStructuresOnlyTightenTheSearchAreas) {
  // The min/max stack (MSSM) bounds a search area's depths exactly, the pyramid (HSM) by up to 2 x 2
  // aligned texels around it, YSM by the pyramid up to 8 texels and the stack on 4 x 4 texels
  // beyond: tighter bounds give smaller areas (fewer texels visited) but the same micro-occluders
  // inside the light's projection, so the same V at level 0.
  EdgeCase c;
  addGroundAndNearCaster(c);
  const TechniqueInfo& t = *findTechnique("backproj");
  auto texels = [&](const char* params, raster::ImageFloat& v) {
    raster::Rasterizer raster({.threads = 2});
    ParamSet p(t.params);
    EXPECT_FALSE(p.setAll(params));
    const ShadowResult res = computeShadows(raster, c.in, t, p);
    v = res.visibility;
    for (const std::string& n : res.notes) {
      const size_t at = n.find(" receivers searched, ");
      if (at != std::string::npos) return std::stod(n.substr(at + 21));
    }
    ADD_FAILURE() << "no search note";
    return 0.0;
  };
  raster::ImageFloat hsm, mssm, ysm;
  const double nh = texels("search_cap=4096,search=hsm", hsm), nm = texels("search_cap=4096,search=mssm", mssm);
  const double ny = texels("search_cap=4096,search=ysm", ysm);
  std::printf("texels visited per receiver: HSM %.1f, MSSM %.1f, YSM %.1f\n", nh, nm, ny);
  EXPECT_LT(nm, nh);
  EXPECT_LE(nm, ny);
  EXPECT_LE(ny, nh);
  for (int j = 0; j < EdgeCase::kH; ++j)
    for (int i = 0; i < EdgeCase::kW; ++i) {
      ASSERT_EQ(hsm.at(i, j), mssm.at(i, j)) << i << "," << j;
      ASSERT_EQ(hsm.at(i, j), ysm.at(i, j)) << i << "," << j;
    }
}

TEST(Techniques, SssmMatchesTheAnalyticPenumbra) {
  // The straight edge over a plane, the receivers' plane a caster (their own surface is in the
  // stochastic map, as the ground is in a frame) and the small caster nearer the light that widens
  // the map. One light sample per texel, filtered with its circle of confusion, gives the ramp.
  EdgeCase c;
  addGroundAndNearCaster(c);
  // The default map (512, widened to about 540 texels) gives the ramp's circles a radius of 42
  // texels; two coarse levels (the paper's) hold 32 (R_G 8 at a quarter of the resolution), so the
  // widest circles are cut by the gather: the ramp ends early and is darker inside (docs/techniques/
  // sssm.md). More levels keep every circle but blur it by the coarse levels' texels. The receivers
  // are at one depth: every plane count puts all planes there.
  expectRamps("sssm", c.in,
              {{"", 0.026, 0.22},
               {"planes=1", 0.026, 0.22},
               {"spacing=depth,planes=3", 0.026, 0.22},
               {"estimator=coverage", 0.031, 0.35},
               {"centres=texel", 0.022, 0.16},
               {"widen=off", 0.025, 0.4},
               {"levels=0", 0.052, 0.43},
               {"levels=3", 0.032, 0.33},
               {"interleave=on", 0.027, 0.21},
               {"box=off", 0.026, 0.22},
               {"strata=0", 0.027, 0.22},
               {"bleed_reduction=0", 0.017, 0.23},
               {"map_size=1024", 0.041, 0.62}});
  // The ramp's width, which the mean error alone does not pin down (circles of half the size give
  // a mean error of 0.021): the mean V over x in [0.1, 0.4] less the mean over [-0.4, -0.1] is
  // exactly 0.5 (0.75 - 0.25) and grows as the penumbra narrows: 0.607 measured (the cut circles
  // steepen it), 0.727 with circles of half the size.
  const raster::ImageFloat v = run(*findTechnique("sssm"), c.in, 2);
  double lo = 0, hi = 0;
  int nLo = 0, nHi = 0;
  for (int j = 0; j < EdgeCase::kH; ++j)
    for (int i = 0; i < EdgeCase::kW; ++i) {
      const float x = EdgeCase::x(i);
      if (x > -0.4f && x < -0.1f) lo += static_cast<double>(v.at(i, j)), ++nLo;
      if (x > 0.1f && x < 0.4f) hi += static_cast<double>(v.at(i, j)), ++nHi;
    }
  const double rise = hi / nHi - lo / nLo;
  std::printf("sssm ramp rise over [-0.4, -0.1] -> [0.1, 0.4]: %.3f (exact 0.5)\n", rise);
  EXPECT_NEAR(rise, 0.5, 0.16);
}

TEST(Techniques, SssmActiveTilesBoundingMethodsAndThreadsChangeNothing) {
  // Active tiles skip only what no receiver reads; the three bounding methods of the light-lens
  // pass find the same samples (stochastic/: exact per sample); the reprojection merges samples in
  // a fixed order. So each of these gives the same bits, with several filter planes as well.
  EdgeCase c;
  addGroundAndNearCaster(c);
  for (int j = 0; j < EdgeCase::kH; ++j)  // receivers at several depths: every plane is read
    for (int i = 0; i < EdgeCase::kW; ++i) c.receivers.at(i, j).position.y = 0.1f * static_cast<float>(j % 4);
  const TechniqueInfo& t = *findTechnique("sssm");
  for (const char* base : {"", "planes=4", "planes=3,interleave=on,levels=0"}) {
    const std::string b = base;
    const std::string sep = b.empty() ? "" : ",";
    const raster::ImageFloat ref = run(t, c.in, 2, b);
    const std::pair<std::string, int> variants[] = {{b + sep + "active_tiles=off", 2},
                                                    {b + sep + "bound=box", 2},
                                                    {b + sep + "bound=interval", 2},
                                                    {b, 1},
                                                    {b, 3}};
    for (const auto& [params, threads] : variants) {
      const raster::ImageFloat v = run(t, c.in, threads, params);
      for (int j = 0; j < EdgeCase::kH; ++j)
        for (int i = 0; i < EdgeCase::kW; ++i)
          ASSERT_EQ(std::bit_cast<uint32_t>(ref.at(i, j)), std::bit_cast<uint32_t>(v.at(i, j)))
              << params << " at " << threads << " threads, " << i << "," << j;
    }
  }
}

// The edge case with the occluder moving across the shutter: its edge at x = s(t) = t - 0.5
// (open -0.5, close +0.5), halfway between light and receivers, so the ramp moves by 2 s. V at a
// static receiver averages it over the shutter:
//     V(x) = integral over t of clamp(x - 2 s(t) + 0.5, 0, 1) dt,
// a ramp three times as wide with rounded ends (computed here by the midpoint rule, 4096 steps).
// Vertical: the edge stays at x = 0 and rises from height 1.5 to 2.5 instead (its depth changes
// with time); at height h the ramp is clamp(0.5 + x (4 - h) / h, 0, 1).
struct MovingEdge {
  EdgeCase c;
  std::vector<glm::vec3> open, close;
  bool vertical = false;
  explicit MovingEdge(bool up = false) : vertical(up) {
    addGroundAndNearCaster(c);
    open = close = c.positions;
    for (size_t k = 0; k < 4; ++k) {  // the occluder's quad
      if (vertical)
        open[k].y = 1.5f, close[k].y = 2.5f;
      else
        open[k].x -= 0.5f, close[k].x += 0.5f;
    }
    c.in.castersOpen = open;
    c.in.castersClose = close;
  }
  double exact(int i) const {
    double sum = 0;
    constexpr int kSteps = 4096;
    const auto x = static_cast<double>(EdgeCase::x(i));
    for (int k = 0; k < kSteps; ++k) {
      const double t = (k + 0.5) / kSteps, h = 1.5 + t;
      sum += std::clamp(vertical ? 0.5 + x * (4.0 - h) / h : x - 2.0 * (t - 0.5) + 0.5, 0.0, 1.0);
    }
    return sum / kSteps;
  }
  double meanError(const raster::ImageFloat& v) const {
    double sum = 0;
    int n = 0;
    for (int j = 0; j < EdgeCase::kH; ++j)
      for (int i = 0; i < EdgeCase::kW; ++i) {
        if (i == 0 && j == 0) continue;
        sum += std::abs(static_cast<double>(v.at(i, j)) - exact(i)), ++n;
      }
    return sum / n;
  }
};

TEST(Techniques, SssmMotionBlurredShadows) {
  const TechniqueInfo& t = *findTechnique("sssm");
  // A static scene through the time path (every vertex's open and close positions the same):
  // the samples' times change nothing, so the same V bits as without time.
  {
    EdgeCase c;
    addGroundAndNearCaster(c);
    const raster::ImageFloat ref = run(t, c.in, 2);
    c.in.castersOpen = c.positions;
    c.in.castersClose = c.positions;
    for (const auto& [params, threads] :
         {std::pair<const char*, int>{"", 2}, {"", 1}, {"bound=interval", 2}}) {
      const raster::ImageFloat v = run(t, c.in, threads, params);
      for (int j = 0; j < EdgeCase::kH; ++j)
        for (int i = 0; i < EdgeCase::kW; ++i)
          ASSERT_EQ(std::bit_cast<uint32_t>(ref.at(i, j)), std::bit_cast<uint32_t>(v.at(i, j)))
              << params << " at " << threads << " threads, " << i << "," << j;
    }
  }
  // The moving edge: sampled over the shutter SSSM finds the time-averaged ramp; frozen at
  // mid-shutter (no motion handed over) it finds the static ramp, far from it. The reference with
  // its time samples within its noise. Measured: sssm 0.025, frozen 0.072, reference 0.0023.
  MovingEdge m;
  const double moving = m.meanError(run(t, m.c.in, 2));
  ShadowInputs frozenIn = m.c.in;
  frozenIn.castersOpen = {};
  frozenIn.castersClose = {};
  std::vector<glm::vec3> mid = m.c.positions;  // the occluder at t = 0.5: where it is static
  frozenIn.casters = {mid, m.c.indices};
  const double frozen = m.meanError(run(t, frozenIn, 2));
  const raster::ImageFloat refV = run(*findTechnique("reference"), m.c.in, 2, "samples=256");
  const double reference = m.meanError(refV);
  std::printf("moving edge, mean |V - time-averaged ramp|: sssm %.4f, sssm frozen %.4f, reference %.4f\n",
              moving, frozen, reference);
  EXPECT_LT(moving, 0.035);
  EXPECT_GT(frozen, 2.0 * moving);
  EXPECT_LT(reference, 0.005);
  // The edge rising through the shutter: the samples' depths change with their time (the exact
  // depth per texel is the triangle's at the sample's time). The output is deterministic, so the
  // bound is tight: measured 0.0129; with every sample's depth taken at t = 0 instead, 0.0155.
  const MovingEdge up(true);
  const double rising = up.meanError(run(t, up.c.in, 2));
  std::printf("rising edge, mean |V - time-averaged ramp|: sssm %.4f\n", rising);
  EXPECT_LT(rising, 0.0142);
  // Bits across threads with motion too.
  const raster::ImageFloat a = run(t, m.c.in, 1), b = run(t, m.c.in, 3);
  for (int j = 0; j < EdgeCase::kH; ++j)
    for (int i = 0; i < EdgeCase::kW; ++i)
      ASSERT_EQ(std::bit_cast<uint32_t>(a.at(i, j)), std::bit_cast<uint32_t>(b.at(i, j)));
}

// Two occluders under the light (1 x 1 at height 4): the half-plane x < 0 at height 2 and the
// half-plane z < 0 at height 1; receivers on y = 0 at x in [0.02, 0.42], z in [-0.12, 0.12]. Each
// hides a band of the light: a = x + 0.5 is left by the upper one, b = 3 z + 0.5 by the lower one.
struct TwoOccluders {
  static constexpr int kN = 16;
  std::vector<glm::vec3> positions = {{-20, 2, -20}, {0, 2, -20},  {0, 2, 20}, {-20, 2, 20},
                                      {-20, 1, -20}, {20, 1, -20}, {20, 1, 0}, {-20, 1, 0}};
  std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  ReceiverImage receivers{kN, kN};
  ShadowInputs in;

  TwoOccluders() {
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i)
        receivers.at(i, j) = {{static_cast<float>(at(i)), 0.0f, static_cast<float>(atZ(j))}, {0, 1, 0}, 1};
    makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light);
    in.casters = {positions, indices};
    in.receivers = &receivers;
  }
  static double at(int i) { return 0.02 + 0.4 * (i + 0.5) / kN; }
  static double atZ(int j) { return -0.12 + 0.24 * (j + 0.5) / kN; }
};

TEST(Techniques, BackprojectionBitmaskCountsAnOverlapOnce) {
  // Two occluders each hiding a band of the light, overlapping as the receivers see them: the
  // half-plane x < 0 at height 2 (it leaves the light's x_l >= -x, a fraction a = x + 0.5) and
  // the half-plane z < 0 at height 1 (it leaves z_l >= -3 z, b = 3 z + 0.5). The exact V is the
  // product ab. Receivers at x >= 0, where the light centre's map sees all of the lower occluder
  // that matters: the part of it at x >= 0 (the upper one hides the rest), which hides the light's
  // band z_l < -3 z only at x_l >= -3 x. Summing the two areas counts their overlap
  // (-3 x <= x_l < -x) twice: V = 1 - (1 - a) - (1 - b) min(1, 3 x + 0.5), clamped at 0.
  TwoOccluders t;
  const raster::ImageFloat bits = run(*findTechnique("backproj"), t.in, 2, "samples=1024,map_size=1024");
  // Without gap filling (it extends the patches where the two occluders meet in the map, which
  // area accumulation counts twice as well) and without coarse texels (one patch at a mean depth).
  const raster::ImageFloat area =
      run(*findTechnique("backproj"), t.in, 2, "occlusion=area,gap_fill=off,search_cap=4096,map_size=1024");
  // Microquads: the two occluders' texels meet in the map along the upper one's edge, where the
  // quads between them are steep walls from one height to the other, inside the upper one's shadow
  // (its edge x = 0 is where the lower one's texels begin).
  const raster::ImageFloat quads =
      run(*findTechnique("backproj"), t.in, 2, "samples=1024,map_size=1024,micro=quads");
  double bitErr = 0, quadErr = 0, areaErr = 0, areaDark = 0, overlap = 0;
  for (int j = 0; j < TwoOccluders::kN; ++j)
    for (int i = 0; i < TwoOccluders::kN; ++i) {
      const double a = std::clamp(t.at(i) + 0.5, 0.0, 1.0), b = std::clamp(3.0 * t.atZ(j) + 0.5, 0.0, 1.0);
      const double exact = a * b, summed = std::max(0.0, a - (1.0 - b) * std::min(1.0, 3.0 * t.at(i) + 0.5));
      bitErr += std::abs(static_cast<double>(bits.at(i, j)) - exact);
      quadErr += std::abs(static_cast<double>(quads.at(i, j)) - exact);
      areaErr += std::abs(static_cast<double>(area.at(i, j)) - summed);
      areaDark += exact - static_cast<double>(area.at(i, j));
      overlap += exact - summed;
    }
  const double n = TwoOccluders::kN * TwoOccluders::kN;
  std::printf(
      "overlap: bitmask mean |V - ab| %.4f (microquads %.4f); area mean |V - summed| %.4f, darker by %.4f "
      "(overlap %.4f)\n",
      bitErr / n, quadErr / n, areaErr / n, areaDark / n, overlap / n);
  EXPECT_LT(bitErr / n, 0.005);                   // measured 0.0029
  EXPECT_LT(quadErr / n, 0.005);
  EXPECT_LT(areaErr / n, 0.004);                  // measured 0.0012
  EXPECT_NEAR(areaDark / n, overlap / n, 0.004);  // 0.0939 against 0.0927
  EXPECT_GT(overlap / n, 0.05);                   // the case does overlap
  // Microquads' exact triangle tests give the same bits at any thread count.
  const raster::ImageFloat one = run(*findTechnique("backproj"), t.in, 1, "micro=quads,samples=256");
  const raster::ImageFloat three = run(*findTechnique("backproj"), t.in, 3, "micro=quads,samples=256");
  for (int j = 0; j < TwoOccluders::kN; ++j)
    for (int i = 0; i < TwoOccluders::kN; ++i)
      ASSERT_EQ(std::bit_cast<uint32_t>(one.at(i, j)), std::bit_cast<uint32_t>(three.at(i, j)));
}

TEST(Techniques, BackprojectionGapFillingClosesTheCracksOfASteepOccluder) {
  // A wall x = 0.6 from y = -1 to 3.5 under the light (y = 4): receivers at x in [1, 1.2] on
  // y = -1 see every light point (x_l in [-0.5, 0.5]) through it, V = 0 exactly. From the light
  // centre the wall is seen at a grazing angle, a staircase of micropatches whose projections
  // leave cracks between them unless each reaches its neighbour's (gap filling).
  ReceiverImage rec(16, 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 16; ++i)
      rec.at(i, j) = {
          {1.0f + 0.2f * static_cast<float>(i) / 15.0f, -1.0f, -0.2f + 0.1f * static_cast<float>(j)},
          {0, 1, 0},
          1u};
  const std::vector<glm::vec3> pos = {
      {0.6f, -1.0f, -10.0f}, {0.6f, 3.5f, -10.0f}, {0.6f, -1.0f, 10.0f}, {0.6f, 3.5f, 10.0f}};
  const std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3};
  ShadowInputs in;
  ASSERT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light));
  in.casters = {pos, idx};
  in.receivers = &rec;
  auto meanV = [&](const std::string& params) {
    const raster::ImageFloat v = run(*findTechnique("backproj"), in, 2, params);
    double sum = 0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 16; ++i) sum += static_cast<double>(v.at(i, j));
    return sum / 64.0;
  };
  // Level 0 only (measured 0.137 without, 0 with), and the default cap, whose coarse texels'
  // bounding rectangles close most cracks by themselves (0.0038 without, 0 with).
  const struct {
    const char* level;
    double leak;
  } cases[] = {{"search_cap=4096", 0.05}, {"", 0.002}};
  for (const auto& c : cases) {
    const double off = meanV(std::string("gap_fill=off,minmax=off,") + c.level);
    const double on = meanV(std::string("minmax=off,") + c.level);
    std::printf("steep wall, %s: mean V %.4f without gap filling, %.4f with\n", c.level, off, on);
    EXPECT_GT(off, c.leak) << c.level;
    EXPECT_LT(on, 0.001) << c.level;
  }
  // Microquads join the texel centres whatever their depths: no crack to fill at level 0 (coarse
  // texels taken whole are rectangles, which gap filling joins as above).
  for (const char* micro : {"micro=quads", "micro=quads_outline"}) {
    const double quads = meanV(std::string(micro) + ",gap_fill=off,minmax=off,search_cap=4096");
    std::printf("steep wall, %s without gap filling: mean V %.4f\n", micro, quads);
    EXPECT_LT(quads, 0.001) << micro;
  }
}

TEST(Techniques, BackprojectionMicroquadsKeepWiresAndOutlines) {
  // A wire about a texel wide (0.006 at height 2 under the light at 4; texels of about 0.005 there)
  // over the edge case's receivers: where the map holds it one texel wide, no quad has three
  // blocker corners, and without the lone texels' patches its shadow would vanish (V 1 against
  // 0.955 measured). Microquads keep it within 0.01 of micropatches' mean V.
  EdgeCase c;
  c.positions = {{-0.005f, 0.5f, -20}, {0.005f, 0.5f, -20}, {0.005f, 0.5f, 20}, {-0.005f, 0.5f, 20}};
  c.in.casters = {c.positions, c.indices};
  auto meanV = [&](const char* params) {
    const raster::ImageFloat v = run(*findTechnique("backproj"), c.in, 2, params);
    double sum = 0;
    int n = 0;
    for (int j = 0; j < EdgeCase::kH; ++j)
      for (int i = 0; i < EdgeCase::kW; ++i)
        if (std::abs(EdgeCase::x(i)) < 0.1f) sum += static_cast<double>(v.at(i, j)), ++n;
    return sum / n;
  };
  const double patches = meanV("samples=1024"), quads = meanV("samples=1024,micro=quads");
  const double outline = meanV("samples=1024,micro=quads_outline");
  std::printf("a wire: mean V under it %.4f micropatches, %.4f microquads, %.4f with outline patches\n", patches,
              quads, outline);
  EXPECT_LT(patches, 0.99);  // the wire does shadow them
  EXPECT_NEAR(quads, patches, 0.01);
  EXPECT_NEAR(outline, patches, 0.01);
  // The straight edge: pure microquads stop half a texel inside it, so its penumbra is brighter
  // than micropatches'; the outline patches put it back.
  EdgeCase e;
  auto meanEdge = [&](const char* params) {
    const raster::ImageFloat v = run(*findTechnique("backproj"), e.in, 2, params);
    double sum = 0;
    for (int j = 0; j < EdgeCase::kH; ++j)
      for (int i = 1; i < EdgeCase::kW; ++i) sum += static_cast<double>(v.at(i, j));
    return sum / (EdgeCase::kH * (EdgeCase::kW - 1));
  };
  const double ePatches = meanEdge("samples=1024"), eQuads = meanEdge("samples=1024,micro=quads");
  const double eOutline = meanEdge("samples=1024,micro=quads_outline");
  std::printf("the edge: mean V %.5f micropatches, %.5f microquads, %.5f with outline patches\n", ePatches, eQuads,
              eOutline);
  EXPECT_GT(eQuads - ePatches, 0.0005);  // 0.00094 measured: half a texel of the edge's penumbra
  EXPECT_LT(std::abs(eOutline - ePatches), 0.0002);  // 0 measured
}

TEST(Techniques, OcclusionTexturesMatchTheAnalyticPenumbra) {
  // The straight edge over a plane, the receivers' plane a caster and the small caster nearer the
  // light: the edge's layer, filtered over the light's footprint at its depth, gives the ramp; the
  // ground's own layer (it holds the receivers) must not darken it.
  EdgeCase c;
  addGroundAndNearCaster(c);
  expectRamps("occtex", c.in,
              {{"", 0.0008, 0.004},
               {"layers=1", 0.0008, 0.004},  // one slab from the near caster to the ground
               {"layers=8", 0.0011, 0.028},
               {"layers=16", 0.0008, 0.004},
               {"layer_depth=slab", 0.0105, 0.09},  // the edge's slab (1 of 4) taken at its middle
               {"layers=8,layer_depth=slab", 0.004, 0.04},
               {"slices=map,fusion=sum", 0.0011, 0.028},
               {"plane_test=off", 0.0011, 0.028}});
}

TEST(Techniques, OcclusionTexturesReceiverPlaneTestKeepsContactShadows) {
  // The edge case with the occluder lowered to height 0.1, the receivers' plane a caster: the
  // occluder shares the receivers' slab at every layer count here (1, 8, 32), which the paper's filter (only
  // layers wholly in front of the receiver) skips -- no shadow under it at all. With the receiver-
  // plane test the slab's part in front of the receiver counts: V = clamp(39 x + 0.5, 0, 1).
  EdgeCase c;
  for (glm::vec3& p : c.positions) p.y = 0.1f;
  addGroundAndNearCaster(c);
  // A farther receiver (not compared) deepens the last slab past the compared ones, as a frame's
  // receivers at many depths do.
  c.receivers.at(0, 0) = {{-2.4f, -2.5f, 0.0f}, {0, 1, 0}, 1u};
  for (const char* layers : {"layers=1", "layers=8", "layers=32"}) {
    double err[2] = {0, 0};
    for (int off = 0; off < 2; ++off) {
      const raster::ImageFloat v =
          run(*findTechnique("occtex"), c.in, 2, std::string(layers) + (off ? ",plane_test=off" : ""));
      for (int j = 0; j < EdgeCase::kH; ++j)
        for (int i = 1; i < EdgeCase::kW; ++i)
          err[off] += std::abs(static_cast<double>(v.at(i, j)) -
                               std::clamp(39.0 * static_cast<double>(EdgeCase::x(i)) + 0.5, 0.0, 1.0));
      err[off] /= EdgeCase::kH * (EdgeCase::kW - 1);
    }
    std::printf(
        "occtex %s, an occluder at 0.1 over the receivers: mean |err| %.4f with the plane test, %.4f "
        "without\n",
        layers, err[0], err[1]);
    EXPECT_LT(err[0], 0.005) << layers;
    EXPECT_GT(err[1], 0.4) << layers;  // half the receivers lit under the occluder
  }
}

TEST(Techniques, OcclusionTexturesMultiplyTheLayersAndLeakThroughASplitWall) {
  // Two occluders in different layers (heights 2 and 1 under the light at 4, as in the bitmask
  // test): each layer's transmission is exactly its own band's, a = x + 0.5 and b = 3 z + 0.5, and
  // the product ab is the exact V. A wall split across layers (x = 0.6 from y = -1 to 3.5, as in
  // the gap-filling test, where V = 0 exactly): its parts hide disjoint bands of the light, the
  // product of their transmissions leaks -- the failure the note counts, more with more layers.
  {
    TwoOccluders t;
    constexpr int kN = TwoOccluders::kN;
    for (const char* params : {"layers=4,map_size=1024", "layers=16,map_size=1024"}) {
      const raster::ImageFloat v = run(*findTechnique("occtex"), t.in, 2, params);
      double err = 0;
      for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i) {
          const double a = std::clamp(t.at(i) + 0.5, 0.0, 1.0), b = std::clamp(3.0 * t.atZ(j) + 0.5, 0.0, 1.0);
          err += std::abs(static_cast<double>(v.at(i, j)) - a * b);
        }
      std::printf("occtex %s, two occluders in two layers: mean |V - ab| %.4f\n", params, err / (kN * kN));
      EXPECT_LT(err / (kN * kN), 0.001) << params;
    }
  }
  ReceiverImage rec(16, 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 16; ++i)
      rec.at(i, j) = {
          {1.0f + 0.2f * static_cast<float>(i) / 15.0f, -1.0f, -0.2f + 0.1f * static_cast<float>(j)},
          {0, 1, 0},
          1u};
  const std::vector<glm::vec3> pos = {
      {0.6f, -1.0f, -10.0f}, {0.6f, 3.5f, -10.0f}, {0.6f, -1.0f, 10.0f}, {0.6f, 3.5f, 10.0f}};
  const std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3};
  ShadowInputs in;
  ASSERT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light));
  in.casters = {pos, idx};
  in.receivers = &rec;
  // One layer flattens the whole wall onto one plane, which (wrongly flat, rightly here) covers
  // the footprint; 16 layers split it into bands whose transmissions multiply.
  // Dealt from one map and summed (Penumbra's variant), the wall's bands add up to the light.
  for (const auto& [layers, lo, hi] : {std::tuple("layers=1", 0.0, 0.01), std::tuple("layers=16", 0.2, 0.5),
                                       std::tuple("layers=16,slices=map,fusion=sum", 0.0, 0.11)}) {
    raster::Rasterizer raster({.threads = 2});
    ParamSet p(findTechnique("occtex")->params);
    ASSERT_FALSE(p.setAll(layers));
    const ShadowResult res = computeShadows(raster, in, *findTechnique("occtex"), p);
    double sum = 0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 16; ++i) sum += static_cast<double>(res.visibility.at(i, j));
    std::printf("occtex %s, a wall split across layers (V = 0): mean V %.4f\n", layers, sum / 64.0);
    EXPECT_GE(sum / 64.0, lo) << layers;
    EXPECT_LE(sum / 64.0, hi) << layers;
    // The note counts the split triangles: both of the wall's at 16 layers.
    bool reported = false;
    for (const std::string& n : res.notes)
      reported |= n.find(std::string(std::string(layers) == "layers=1" ? "; 0" : "; 2") +
                         " split across layers") != std::string::npos;
    EXPECT_TRUE(reported) << layers;
  }
}

TEST(Techniques, OcclusionTexturesRefinedBlocksSumAsTheWholeBox) {
  // Receivers on y = 0 under a light at height 4; stripes 0.1 wide along z at height 0.5 (scene A),
  // and (scene B) as many 0.3 below the ground between them: behind every receiver's tangent plane,
  // they hide nothing, so B's V is A's. In A a footprint's pyramid blocks hold near stripes and
  // empty texels (settled whole, one box query); in B they mix texels nearer and behind the plane
  // and are refined down to single texels, many only partly inside the footprint: those parts must
  // add up to the same covered area and depth sum. One layer holds both kinds (a farther receiver,
  // not compared, deepens it past the lower stripes).
  ReceiverImage rec(24, 8);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 24; ++i)
      rec.at(i, j) = {
          {-1.0f + 2.0f * static_cast<float>(i) / 23.0f, 0.0f, -0.5f + static_cast<float>(j) / 7.0f},
          {0, 1, 0},
          1u};
  rec.at(0, 0) = {{0.0f, -2.5f, 0.0f}, {0, 1, 0}, 1u};
  struct Stripes {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
  };
  const auto stripes = [](bool below) {
    Stripes m;
    for (int k = 0; k < 15; ++k) {
      const float x0 = -1.5f + 0.2f * static_cast<float>(k), x1 = x0 + 0.1f;
      for (int b = 0; b < (below ? 2 : 1); ++b) {
        const float y = b == 0 ? 0.5f : -0.3f, u0 = b == 0 ? x0 : x1, u1 = u0 + 0.1f;
        const auto v = static_cast<uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {{u0, y, -1.0f}, {u1, y, -1.0f}, {u0, y, 1.0f}, {u1, y, 1.0f}});
        m.indices.insert(m.indices.end(), {v, v + 2, v + 1, v + 1, v + 2, v + 3});
      }
    }
    return m;
  };
  ShadowInputs in;
  ASSERT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light));
  in.receivers = &rec;
  const Stripes a = stripes(false), b = stripes(true);
  in.casters = {a.positions, a.indices};
  const raster::ImageFloat va = run(*findTechnique("occtex"), in, 2, "layers=1");
  in.casters = {b.positions, b.indices};
  const raster::ImageFloat vb = run(*findTechnique("occtex"), in, 2, "layers=1");
  double worst = 0, mean = 0;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 24; ++i) {
      if (i == 0 && j == 0) continue;
      worst = std::max(worst, std::abs(static_cast<double>(va.at(i, j)) - static_cast<double>(vb.at(i, j))));
      mean += static_cast<double>(va.at(i, j)) / (24 * 8 - 1);
    }
  std::printf("occtex, stripes with and without stripes behind the receivers: max |dV| %.2g (mean V %.3f)\n",
              worst, mean);
  EXPECT_GT(mean, 0.2);  // the stripes shadow the receivers: the comparison means something
  EXPECT_LT(mean, 0.8);
  EXPECT_LT(worst, 1e-5);
}

TEST(Techniques, MvrConvergesWithViews) {
  // Error falls with the number of views until the maps' resolution limits it (1024^2 here).
  EdgeCase c;
  double previous = 1.0;
  for (int views : {4, 16, 64, 256}) {
    double mean = 0, worst = 0;
    rampError(run(*findTechnique("mvr"), c.in, 2, "map_size=1024,views=" + std::to_string(views)), mean,
              worst);
    std::printf("mvr views=%d vs analytic ramp: mean |err| %.4f, max %.4f\n", views, mean, worst);
    if (views <= 64) {
      EXPECT_LT(mean, previous * 0.75) << views;
    }
    previous = mean;
  }
  EXPECT_LT(previous, 0.001);
}

TEST(Techniques, MapsCutToTheCastersAreFinerAndLeaveTheRestLit) {
  // One small square caster (0.5 wide, height 2) over a wide ground (x, z in [-4, 4]) under a 1 x 1
  // light at height 4: fitted to the receivers, a 64^2 map gives the caster 8 texels a side; cut
  // to it, about 52. Every receiver the reference sees fully lit stays exactly lit, and the
  // penumbra follows the reference more closely. Measured (RMSE against the reference): mvr 0.0090
  // fitted to the receivers, 0.0035 cut; vwss 0.0116, 0.0076.
  constexpr int kN = 96;
  ReceiverImage rec(kN, kN);
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i)
      rec.at(i, j) = {{-4.0f + 8.0f * (static_cast<float>(i) + 0.5f) / kN, 0.0f,
                       -4.0f + 8.0f * (static_cast<float>(j) + 0.5f) / kN},
                      {0, 1, 0},
                      1u};
  const std::vector<glm::vec3> pos = {
      {-0.25f, 2, -0.25f}, {0.25f, 2, -0.25f}, {0.25f, 2, 0.25f}, {-0.25f, 2, 0.25f}};
  const std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  ShadowInputs in;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light);
  in.casters = {pos, idx};
  in.receivers = &rec;
  const raster::ImageFloat ref = run(*findTechnique("reference"), in, 2, "samples=1024");
  const auto rmse = [&](const raster::ImageFloat& v) {
    double sum = 0;
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) sum += std::pow(static_cast<double>(v.at(i, j) - ref.at(i, j)), 2.0);
    return std::sqrt(sum / (kN * kN));
  };
  for (const char* name : {"mvr", "vwss"}) {
    const std::string common = "map_size=64,views=64,";
    const raster::ImageFloat wide = run(*findTechnique(name), in, 2, common + "fit=receivers");
    const raster::ImageFloat cut = run(*findTechnique(name), in, 2, common + "fit=casters");
    int lit = 0;
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i)
        if (ref.at(i, j) == 1.0f) {
          ++lit;
          EXPECT_EQ(cut.at(i, j), 1.0f) << name << " at " << i << "," << j;
        }
    EXPECT_GT(lit, kN * kN / 2);
    std::printf(
        "%s: RMSE against the reference, maps fitted to the receivers %.4f, cut to the casters %.4f\n", name,
        rmse(wide), rmse(cut));
    EXPECT_LT(rmse(cut), 0.8 * rmse(wide)) << name;
  }
}

TEST(Techniques, InterleavedSubsetsAreStratifiedAndCoverTheLight) {
  RectLight light;
  ASSERT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 2.0f, 1.0f, glm::vec3(1), 1, light));
  const LightSampleSet one = interleavedLightSamples(light, 64, 1);
  EXPECT_EQ(one.points, lightSamplePoints(light, 64));   // k = 1: the plain set, the same images
  EXPECT_EQ(interleavedLightSamples(light, 3, 4).k, 1);  // no empty subset: k^2 <= views
  EXPECT_EQ(interleavedLightSamples(light, 10, 4).k, 3);
  for (int n : {64, 66}) {
    const LightSampleSet set = interleavedLightSamples(light, n, 2);
    ASSERT_EQ(set.points.size(), static_cast<size_t>(n));
    ASSERT_EQ(set.count.size(), 4u);
    int total = 0;
    for (int s = 0; s < 4; ++s) {
      total += set.count[static_cast<size_t>(s)];
      // Each subset covers the light: its points' mean lies near the centre, its points inside.
      glm::vec2 mean(0.0f);
      for (size_t i = 0; i < set.points.size(); ++i)
        if (set.subset[i] == s) {
          mean += set.points[i];
          EXPECT_LE(std::abs(set.points[i].x), 1.0f);
          EXPECT_LE(std::abs(set.points[i].y), 0.5f);
        }
      mean /= static_cast<float>(set.count[static_cast<size_t>(s)]);
      EXPECT_LT(std::abs(mean.x), 0.1f) << s;
      EXPECT_LT(std::abs(mean.y), 0.08f) << s;
    }
    EXPECT_EQ(total, n);
  }
  // MVR and VWSS with interleaving: every pixel's V a fraction of its own subset's views, near the
  // analytic ramp on average, in [0, 1].
  EdgeCase c;
  for (const char* name : {"mvr", "vwss"}) {
    double mean = 0, worst = 0;
    const raster::ImageFloat v = run(*findTechnique(name), c.in, 2, "views=64,interleave=2");
    rampError(v, mean, worst);
    EXPECT_LT(mean, 0.03) << name;
    for (int j = 0; j < EdgeCase::kH; ++j)
      for (int i = 0; i < EdgeCase::kW; ++i) ASSERT_TRUE(v.at(i, j) >= 0.0f && v.at(i, j) <= 1.0f);
  }
}

}  // namespace
}  // namespace penumbra::shadows
