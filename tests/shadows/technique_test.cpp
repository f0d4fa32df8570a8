// The technique framework: parameters, registry, the light's irradiance, region fitting, caster
// culling and the light views' projection.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <type_traits>

#include "shadows/area_light.h"
#include "shadows/light_view.h"
#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

TEST(Params, DefaultsRangesAndErrors) {
  const TechniqueInfo* pcss = findTechnique("pcss");
  ASSERT_NE(pcss, nullptr);
  ParamSet p(pcss->params);
  EXPECT_EQ(p.integer("blocker_samples"), 64);
  EXPECT_EQ(p.integer("filter_samples"), 128);
  EXPECT_EQ(p.changed(), "");
  EXPECT_FALSE(p.set("blocker_samples=16"));
  EXPECT_EQ(p.integer("blocker_samples"), 16);
  EXPECT_EQ(p.changed(), "blocker_samples=16");
  auto err = p.set("blocker_samples=0");
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("[1, 1024]"), std::string::npos) << *err;
  err = p.set("blocker_samples=1.5");
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("integer"), std::string::npos) << *err;
  err = p.set("nonsense=3");
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("known: map_size"), std::string::npos) << *err;
  EXPECT_TRUE(p.set("bias"));
  EXPECT_TRUE(p.set("bias=nan"));
  EXPECT_TRUE(p.set("bias=inf"));
  EXPECT_EQ(p.integer("blocker_samples"), 16);  // failed sets change nothing

  const TechniqueInfo* pcf = findTechnique("pcf");
  ASSERT_NE(pcf, nullptr);
  ParamSet q(pcf->params);
  EXPECT_FALSE(q.setAll("kernel=grid,taps=25"));
  EXPECT_EQ(q.choice("kernel"), "grid");
  err = q.set("kernel=box");
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("grid, poisson"), std::string::npos) << *err;
}

TEST(Registry, NamesUniqueAndSettingsValid) {
  ASSERT_FALSE(registry().empty());
  for (size_t i = 0; i < registry().size(); ++i) {
    const TechniqueInfo& t = registry()[i];
    EXPECT_EQ(findTechnique(t.name), &t);
    EXPECT_FALSE(t.summary.empty());
    ASSERT_TRUE(t.make);
    for (const std::string& s : t.benchSettings) {
      ParamSet p(t.params);
      EXPECT_FALSE(p.setAll(s)) << t.name << ": " << s;
    }
    for (const ParamSpec& spec : t.params) {
      EXPECT_LE(spec.minValue, spec.defaultValue) << t.name << "." << spec.name;
      EXPECT_LE(spec.defaultValue, spec.maxValue) << t.name << "." << spec.name;
    }
  }
  EXPECT_EQ(findTechnique("nope"), nullptr);
}

// Cosine-weighted solid angle of an a x b rectangle seen from a point at distance c below one
// corner, facing it: pi times the form factor (Howell's catalogue, configuration B-3).
double cornerFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return 0.5 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy));
}

TEST(AreaLight, IrradianceMatchesClosedForm) {
  RectLight l;
  ASSERT_TRUE(makeRectLight({0, 3, 0}, {0, -1, 0}, {1, 0, 0}, 2.0f, 1.0f, glm::vec3(1), 1.0f, l));
  EXPECT_NEAR(glm::length(l.normal() - glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
  // Centred below: four corner rectangles of 1 x 0.5.
  EXPECT_NEAR(irradianceFactor(l, {0, 0, 0}, {0, 1, 0}), 4 * cornerFactor(1.0, 0.5, 3.0), 1e-5);
  // Below a corner.
  EXPECT_NEAR(irradianceFactor(l, {1, 0, 0.5f}, {0, 1, 0}), cornerFactor(2.0, 1.0, 3.0), 1e-5);
  // Behind the light, or facing away: nothing.
  EXPECT_EQ(irradianceFactor(l, {0, 4, 0}, {0, -1, 0}), 0.0f);
  EXPECT_EQ(irradianceFactor(l, {0, 0, 0}, {0, -1, 0}), 0.0f);
  // A vertical receiver below the centre sees half the light, the same from either side, less than
  // a horizontal one sees, and more than nothing.
  const float side = irradianceFactor(l, {0, 0, 0}, {1, 0, 0});
  EXPECT_NEAR(side, irradianceFactor(l, {0, 0, 0}, {-1, 0, 0}), 1e-6);
  EXPECT_GT(side, 0.0f);
  EXPECT_LT(side, irradianceFactor(l, {0, 0, 0}, {0, 1, 0}));
  // Far away it tends to A cos cos / r^2.
  const float far = irradianceFactor(l, {0, -997, 0}, {0, 1, 0});
  EXPECT_NEAR(far, 2.0 / (1000.0 * 1000.0), 1e-9);
  RectLight bad;
  std::string why;
  EXPECT_FALSE(makeRectLight({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, 1, 1, glm::vec3(1), 1, bad, &why));
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(makeRectLight({0, 0, 0}, {0, -1, 0}, {1, 0, 0}, -1, 1, glm::vec3(1), 1, bad));
}

TEST(AreaLight, HorizonFraction) {
  RectLight l;
  ASSERT_TRUE(makeRectLight({0, 3, 0}, {0, -1, 0}, {1, 0, 0}, 2.0f, 1.0f, glm::vec3(1), 1.0f, l));
  EXPECT_EQ(horizonFraction(l, {0, 0, 0}, {0, 1, 0}), 1.0f);     // all above
  EXPECT_EQ(horizonFraction(l, {0, 0, 0}, {0, -1, 0}), 0.0f);    // all below
  EXPECT_EQ(horizonFraction(l, {0, 4, 0}, {0, 1, 0}), 0.0f);     // behind the light
  EXPECT_NEAR(horizonFraction(l, {0, 0, 0}, {1, 0, 0}), 0.5f, 1e-6f);  // a vertical plane through the centre
  // A plane through the receiver cutting the light at s = 0.5 (x = 0.5 of a width of 2): 1/4 above.
  const glm::vec3 n = glm::normalize(glm::cross(glm::vec3(0, 0, 1), glm::vec3(0.5f, 3.0f, 0.0f)));
  const float f = horizonFraction(l, {0, 0, 0}, -n);
  EXPECT_NEAR(std::min(f, 1.0f - f), 0.25f, 1e-5f);
}

ReceiverImage planeReceivers(int w, int h, float half, float y = 0.0f) {
  ReceiverImage r(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      Receiver& t = r.at(i, j);
      t.position = {(2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(w) - 1.0f) * half, y,
                    (2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(h) - 1.0f) * half};
      t.normal = {0, 1, 0};
      t.valid = 1;
    }
  return r;
}

// A 1 x 1 light at height 4 facing down over planeReceivers(n, n, half) on y = 0, and the region
// fitted to them.
struct LitPlane {
  RectLight light;
  ReceiverImage receivers;
  LightRegion region;
};
LitPlane litPlane(raster::Rasterizer& raster, int n, float half) {
  LitPlane p;
  EXPECT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, p.light));
  p.receivers = planeReceivers(n, n, half);
  raster.run([&] { p.region = fitRegion(p.light, p.receivers); });
  return p;
}

TEST(LightView, RegionCullingAndProjection) {
  raster::Rasterizer raster({.threads = 2});
  const LitPlane lit = litPlane(raster, 16, 2.0f);
  const RectLight& l = lit.light;
  const ReceiverImage& rec = lit.receivers;
  const LightRegion& region = lit.region;
  ASSERT_FALSE(region.empty);
  EXPECT_EQ(region.receivers, 256u);
  EXPECT_NEAR(region.hi.z, 4.0f, 1e-5f);
  // Casters: one between light and receivers (kept), one beside the light's reach (culled), one
  // behind the light (culled), one below the receivers (culled).
  const std::vector<glm::vec3> pos = {{-0.1f, 2, -0.1f}, {0.1f, 2, -0.1f}, {0, 2, 0.1f},
                                      {20, 2, 0},        {21, 2, 0},       {20, 2, 1},
                                      {0, 5, 0},         {1, 5, 0},        {0, 5, 1},
                                      {0, -1, 0},        {1, -1, 0},       {0, -1, 1}};
  const std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  const CasterSet cs = cullCasters(l, region, {pos, idx});
  EXPECT_EQ(cs.trianglesIn, 4u);
  EXPECT_EQ(cs.trianglesCulled, 3u);
  ASSERT_EQ(cs.indices.size(), 3u);
  EXPECT_EQ(cs.indices[0], 0u);
  EXPECT_NEAR(cs.minDepth, 2.0f, 1e-5f);

  // Projection: the clip matrix and toMap agree; stored depth near/d.
  const LightView v = makeLightView(l, region, {0.25f, -0.25f}, 1.0f, 64, 32);
  for (const glm::vec3 p : {glm::vec3(0.3f, 0.0f, -1.2f), glm::vec3(-1.9f, 0.0f, 1.9f), glm::vec3(0.1f, 2.0f, 0.2f)}) {
    const glm::vec4 c = v.viewProj * glm::vec4(p, 1.0f);
    const glm::vec3 vs = v.toView(p);
    const glm::vec2 m = v.toMap(vs);
    EXPECT_NEAR((c.x / c.w * 0.5f + 0.5f) * 64.0f, m.x, 1e-3f);
    EXPECT_NEAR((0.5f - c.y / c.w * 0.5f) * 32.0f, m.y, 1e-3f);
    EXPECT_NEAR(c.z / c.w, 1.0f / vs.z, 1e-6f);
    EXPECT_NEAR(v.depthOf(c.z / c.w), vs.z, 1e-4f);
    EXPECT_GE(m.x, 0.0f);
    EXPECT_LE(m.x, 64.0f);
  }
  // Every receiver maps inside the map.
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      const glm::vec2 m = v.toMap(v.toView(rec.at(i, j).position));
      EXPECT_TRUE(m.x > 0.0f && m.x < 64.0f && m.y > 0.0f && m.y < 32.0f) << i << "," << j;
    }
}

TEST(LightView, CutToTheCastersCoversThemAndLeavesTheBorderEmpty) {
  // A wide ground (8 x 8) under a 1 x 1 light at height 4, one small caster (0.4 wide, height 2).
  raster::Rasterizer raster({.threads = 2});
  const LitPlane lit = litPlane(raster, 32, 4.0f);
  const RectLight& l = lit.light;
  const LightRegion& region = lit.region;
  const std::vector<glm::vec3> pos = {{-0.2f, 2, -0.2f}, {0.2f, 2, -0.2f}, {0, 2, 0.2f}};
  const std::vector<uint32_t> idx = {0, 1, 2};
  const CasterSet cs = cullCasters(l, region, {pos, idx});
  ASSERT_TRUE(cs.boxed());
  EXPECT_NEAR(cs.lo.z, 2.0f, 1e-5f);
  EXPECT_NEAR(cs.hi.z, 2.0f, 1e-5f);
  for (const glm::vec2 lp : {glm::vec2(0.0f), glm::vec2(0.4f, -0.3f)}) {
    const LightView wide = makeLightView(l, region, lp, 1.0f, 64, 64);
    const LightView cut = makeLightView(l, region, lp, 1.0f, 64, 64, glm::vec2(0.0f), &cs);
    EXPECT_EQ(wide.casterCut, 0u);
    EXPECT_EQ(cut.casterCut, 15u);
    // The caster's texels: about 6 times finer than the receivers' fit (0.4 of a 2 x 2 tangent box).
    EXPECT_LT((cut.tanHi.x - cut.tanLo.x) * 4.0f, wide.tanHi.x - wide.tanLo.x);
    // Every point of the caster maps at least kCasterFitMargin texels inside the cut map.
    for (float a : {0.0f, 0.25f, 0.5f, 1.0f})
      for (float b : {0.0f, 0.5f, 1.0f}) {
        if (a + b > 1.0f) continue;
        const glm::vec3 p = pos[0] + a * (pos[1] - pos[0]) + b * (pos[2] - pos[0]);
        const glm::vec2 m = cut.toMap(cut.toView(p));
        for (float c : {m.x, m.y}) {
          EXPECT_GE(c, static_cast<float>(kCasterFitMargin)) << lp.x;
          EXPECT_LE(c, 64.0f - static_cast<float>(kCasterFitMargin)) << lp.x;
        }
      }
    // A margin (a widened map) keeps the receivers' fit.
    EXPECT_EQ(makeLightView(l, region, lp, 1.0f, 64, 64, glm::vec2(0.1f), &cs).casterCut, 0u);
  }
  // A caster wider than the receivers cuts nothing.
  const std::vector<glm::vec3> big = {{-30, 2, -30}, {30, 2, -30}, {0, 2, 30}};
  const CasterSet all = cullCasters(l, region, {big, idx});
  ASSERT_TRUE(all.boxed());
  const LightView same = makeLightView(l, region, glm::vec2(0.0f), 1.0f, 64, 64, glm::vec2(0.0f), &all);
  const LightView wide = makeLightView(l, region, glm::vec2(0.0f), 1.0f, 64, 64);
  EXPECT_EQ(same.casterCut, 0u);
  EXPECT_EQ(same.tanLo, wide.tanLo);
  EXPECT_EQ(same.tanHi, wide.tanHi);

  // The border of the cut sides is emptied, the coarse record still bounding it.
  raster::DepthTarget t(20, 12, 0.5f);
  t.fillBorder(0.0f, 2u | 4u);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x) EXPECT_EQ(t.at(x, y), (x == 19 || y == 0) ? 0.0f : 0.5f) << x << "," << y;
  EXPECT_EQ(t.blockMin()[0], 0.0f);
  EXPECT_EQ(t.blockMax()[0], 0.5f);
  EXPECT_EQ(t.blockMin()[static_cast<size_t>(t.blocksX())], 0.5f);  // the second row of blocks: untouched
  raster::Image<uint32_t> bits(5, 4, 7u);
  LightView v;
  v.casterCut = 1u | 8u;
  clearCasterCutBorder(v, bits, 0u);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_EQ(bits.at(x, y), (x == 0 || y == 3) ? 0u : 7u) << x << "," << y;
}

TEST(LightView, ReceiverPlaneDepth) {
  RectLight l;
  ASSERT_TRUE(makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, l));
  LightRegion region;
  region.empty = false;
  region.lo = {-2, -2, 1};
  region.hi = {2, 2, 4};
  const LightView v = makeLightView(l, region, {0, 0}, 0.5f, 256, 256);
  // A tilted plane through p: the threshold at another tangent point is near / depth of the point
  // of the plane on that ray.
  const glm::vec3 p(0.5f, 0.0f, 0.3f), n = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  const ReceiverPlane plane(v, v.toView(p), n, {0.0f, 0.0f});
  EXPECT_NEAR(plane.threshold(plane.tanX(), plane.tanY()), v.znear / v.toView(p).z, 1e-6f);
  const float tx = plane.tanX() + 0.01f, ty = plane.tanY() - 0.02f;
  const float d = v.znear / plane.threshold(tx, ty);
  const glm::vec3 q = v.origin + d * (tx * v.right + ty * v.up + v.axis);
  EXPECT_NEAR(glm::dot(q - p, n), 0.0f, 1e-4f);
  // Bias moves the compared depth towards the light (a larger stored threshold).
  const ReceiverPlane biased(v, v.toView(p), n, {1.0f, 1.0f});
  EXPECT_GT(biased.threshold(tx, ty), plane.threshold(tx, ty));
  // Seen edge-on, the plane's depth is clamped to [d/2, 2d].
  const ReceiverPlane edge(v, v.toView(p), glm::normalize(glm::vec3(1.0f, 0.0f, 0.0f)), {0.0f, 0.0f});
  const float z = edge.threshold(edge.tanX() + 5.0f, edge.tanY());
  EXPECT_GE(z, v.znear / (2.0f * v.toView(p).z) * 0.999f);
  EXPECT_LE(z, 2.0f * v.znear / v.toView(p).z * 1.001f);
}

}  // namespace
}  // namespace penumbra::shadows

namespace penumbra::shadows {
namespace {

// A ShadowMap caches a pointer into its own image: it cannot be copied, and a moved map reads
// its own texels (the image it now holds), not the moved-from one's.
TEST(ShadowMapOwnership, NotCopyableAndAMovedMapReadsItsOwnTexels) {
  static_assert(!std::is_copy_constructible_v<ShadowMap> && !std::is_copy_assignable_v<ShadowMap>);
  static_assert(std::is_nothrow_move_constructible_v<ShadowMap>);
  ShadowMap a;
  a.view.width = a.view.height = 4;  // tangents [-1, 1]^2 over 4 x 4 texels
  a.depth.resize(4, 4, 0.5f);
  a.prepareLookup();
  ShadowMap b(std::move(a));
  b.depth.image().at(3, 0) = 0.25f;  // top right: tan x > 0.5, tan y > 0.5
  EXPECT_EQ(b.stored(0.9f, 0.9f), 0.25f);
  EXPECT_EQ(b.stored(-0.9f, -0.9f), 0.5f);
  ShadowMap c;
  c = std::move(b);
  c.depth.image().at(0, 3) = 0.125f;
  EXPECT_EQ(c.stored(-0.9f, -0.9f), 0.125f);
  EXPECT_EQ(c.tapMap().data, &c.depth.image().at(0, 0));
}

}  // namespace
}  // namespace penumbra::shadows
