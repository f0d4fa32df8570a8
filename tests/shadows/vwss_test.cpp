// View-warped multi-view soft shadows: point generation counts, the buffered and unbuffered
// variants and every traversal mode give the same maps, and the light-leak cases of naive warping
// (disocclusion, the light's field-of-view border; Marrs et al. 2018, Fig. 4) do not leak.
#include "shadows/vwss.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <span>

#include "shadows/area_light.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

raster::ImageFloat run(const std::string& name, const ShadowInputs& in, int threads,
                       const std::string& params) {
  raster::Rasterizer raster({.threads = threads});
  const TechniqueInfo& t = *findTechnique(name);
  ParamSet p(t.params);
  EXPECT_FALSE(p.setAll(params)) << params;
  return computeShadows(raster, in, t, p).visibility;
}

ReceiverImage groundReceivers(int w, int h, float half) {
  ReceiverImage r(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      r.at(i, j) = {{(2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(w) - 1.0f) * half, 0.0f,
                     (2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(h) - 1.0f) * half},
                    {0, 1, 0},
                    1u};
  return r;
}

// A horizontal rectangle at height y, wound counter-clockwise seen from above (facing up).
void addPlate(std::vector<glm::vec3>& pos, std::vector<uint32_t>& idx, float x0, float x1, float z0, float z1,
              float y) {
  const auto b = static_cast<uint32_t>(pos.size());
  pos.insert(pos.end(), {{x0, y, z1}, {x1, y, z1}, {x1, y, z0}, {x0, y, z0}});
  idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
}

TEST(Vwss, PointGenerationEmitsEveryFragmentOfEveryLayer) {
  // Two plates filling the whole source view (a view fitted to a small region, plates larger):
  // all layers give 2 points per texel, the nearest layer 1, and culling the faces turned away
  // from the light drops a plate wound the other way.
  RectLight light;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1, 1, glm::vec3(1), 1, light);
  LightRegion region;
  region.empty = false;
  region.lo = {-0.5f, -0.5f, 3.9f};
  region.hi = {0.5f, 0.5f, 4.0f};
  const LightView source = makeLightView(light, region, {0, 0}, 0.5f, 37, 29);
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  addPlate(pos, idx, -1.5f, 1.5f, -1.5f, 1.5f, 2.0f);  // seen from the light at 35 degrees and more
  addPlate(pos, idx, -1.5f, 1.5f, -1.5f, 1.5f, 1.0f);
  raster::Rasterizer raster({.threads = 2});
  const Geometry g{pos, idx};
  const LightPoints all = generateLightPoints(raster, g, source, light, true, CasterCull::None);
  EXPECT_EQ(all.points.size(), 2u * 37u * 29u);
  const LightPoints nearest = generateLightPoints(raster, g, source, light, false, CasterCull::None);
  ASSERT_EQ(nearest.points.size(), 37u * 29u);
  for (const glm::vec3& p : nearest.points) EXPECT_NEAR(p.y, 2.0f, 1e-4f);  // the upper plate only
  // Both plates face up, towards the light: culling keeps them. Reversed, they are culled.
  EXPECT_EQ(generateLightPoints(raster, g, source, light, true, CasterCull::Back).points.size(),
            2u * 37u * 29u);
  std::vector<uint32_t> flipped = idx;
  for (size_t t = 0; t < flipped.size(); t += 3) std::swap(flipped[t + 1], flipped[t + 2]);
  EXPECT_EQ(generateLightPoints(raster, {pos, flipped}, source, light, true, CasterCull::Back).points.size(),
            0u);
  // A payload is the point's source texel; every texel appears once per layer.
  std::vector<int> seen(37 * 29, 0);
  for (uint32_t p : all.payloads) ++seen[p];
  for (int s : seen) EXPECT_EQ(s, 2);
  // Same points in the same order at another thread count.
  raster::Rasterizer one({.threads = 1});
  const LightPoints again = generateLightPoints(one, g, source, light, true, CasterCull::None);
  ASSERT_EQ(again.points.size(), all.points.size());
  for (size_t i = 0; i < all.points.size(); ++i) {
    EXPECT_EQ(again.points[i], all.points[i]);
    EXPECT_EQ(again.payloads[i], all.payloads[i]);
  }
}

// A scene for the leak cases: receivers on the ground, a low plate under a high one (the high
// plate hides part of the low one from the light's centre: disocclusion), and a small occluder
// near the light off to the side (outside the centre view's frustum, inside a corner sample's).
struct LeakScene {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  ReceiverImage rec = groundReceivers(64, 64, 3.0f);
  ShadowInputs in;
  LeakScene() {
    addPlate(pos, idx, -1.0f, 1.0f, -1.0f, 1.0f, 2.5f);  // high
    addPlate(pos, idx, -1.6f, 0.4f, -0.5f, 0.5f, 1.0f);  // low, partly under the high one
    addPlate(pos, idx, 0.6f, 1.6f, -1.5f, 1.5f, 3.7f);   // near the light, beside its centre view
    makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 3.0f, 3.0f, glm::vec3(1), 1, in.light);
    in.casters = {pos, idx};
    in.receivers = &rec;
  }
};

double maxDiff(const raster::ImageFloat& a, const raster::ImageFloat& b, double* mean = nullptr) {
  double m = 0, s = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const double d = std::abs(static_cast<double>(a.at(x, y)) - static_cast<double>(b.at(x, y)));
      m = std::max(m, d);
      s += d;
    }
  if (mean) *mean = s / (a.width() * a.height());
  return m;
}

// The containing view's Eq. 3 grows with (near + D) / near: a caster just below the light asks
// for a huge source view. The cap shrinks both sides by one factor, so the texels keep their shape
// (a wide region stays wide), and leaves a view under the cap as Eq. 3 gives it.
TEST(Vwss, ContainingViewCapKeepsTheTexelShape) {
  RectLight light;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1, 1, glm::vec3(1), 1, light);
  LightRegion region;
  region.empty = false;
  region.lo = {-3.0f, 0.0f, -1.5f};
  region.hi = {3.0f, 3.9f, 1.5f};
  const LightView sample = makeLightView(light, region, {0, 0}, 0.5f, 256, 256);
  const LightView free = makeContainingView(light, region, sample, 0.5f, 16384);
  ASSERT_LT(free.width, 4096);
  EXPECT_EQ(free.width, makeContainingView(light, region, sample, 0.5f, free.width).width);
  const auto texelShape = [](const LightView& v) {
    return (static_cast<double>(v.tanHi.x - v.tanLo.x) / v.width) /
           (static_cast<double>(v.tanHi.y - v.tanLo.y) / v.height);
  };
  EXPECT_GT(static_cast<double>(free.width) / free.height, 1.2);  // the region is wide
  const LightView nearLight = makeContainingView(light, region, sample, 1e-3f, 16384);
  EXPECT_EQ(std::max(nearLight.width, nearLight.height), 16384);
  for (const int cap : {free.width / 2, free.width / 5}) {
    const LightView capped = makeContainingView(light, region, sample, 0.5f, cap);
    EXPECT_EQ(std::max(capped.width, capped.height), cap);
    EXPECT_NEAR(texelShape(capped), texelShape(free), 0.02) << cap;
    // The same frustum (up to its one-texel margin): only the resolution changes.
    EXPECT_EQ(capped.znear, free.znear);
    EXPECT_EQ(capped.origin, free.origin);
    EXPECT_LE(capped.tanLo.x, free.tanLo.x);
    EXPECT_GE(capped.tanHi.y, free.tanHi.y);
    EXPECT_NEAR(capped.tanHi.x - capped.tanLo.x, free.tanHi.x - free.tanLo.x,
                0.02f * (free.tanHi.x - free.tanLo.x));
  }
}

TEST(Vwss, NoLeaksWhereNaiveWarpingLeaks) {
  LeakScene s;
  const std::string common = "views=64,map_size=256";
  const raster::ImageFloat mvr = run("mvr", s.in, 2, common);
  const raster::ImageFloat vwss = run("vwss", s.in, 2, common);
  const raster::ImageFloat nearest = run("vwss", s.in, 2, common + ",layers=nearest");
  const raster::ImageFloat onLight = run("vwss", s.in, 2, common + ",containing=off");
  double meanVwss = 0, meanNearest = 0, meanOnLight = 0;
  const double dVwss = maxDiff(vwss, mvr, &meanVwss);
  const double dNearest = maxDiff(nearest, mvr, &meanNearest);
  const double dOnLight = maxDiff(onLight, mvr, &meanOnLight);
  std::printf(
      "vs mvr, max / mean |dV|: vwss %.3f / %.4f, nearest layer %.3f / %.4f, source on the light %.3f / "
      "%.4f\n",
      dVwss, meanVwss, dNearest, meanNearest, dOnLight, meanOnLight);
  EXPECT_LT(meanVwss, 0.01);
  EXPECT_LT(dVwss, 0.2);
  EXPECT_GT(dNearest, 0.2);  // the disocclusion leak of a warped plain depth map
  EXPECT_GT(meanNearest, 2.0 * meanVwss);
  EXPECT_GT(dOnLight, 0.2);  // the occluder beside the centre view is missing
  EXPECT_GT(meanOnLight, 2.0 * meanVwss);
}

// A closed box, wound counter-clockwise seen from outside (12 triangles).
void addBox(std::vector<glm::vec3>& pos, std::vector<uint32_t>& idx, glm::vec3 lo, glm::vec3 hi) {
  const auto b = static_cast<uint32_t>(pos.size());
  for (int c = 0; c < 8; ++c)
    pos.push_back({(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z});
  // Faces as corner quads (a, b, c, d) counter-clockwise from outside.
  const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces)
    idx.insert(idx.end(), {b + f[0], b + f[1], b + f[2], b + f[0], b + f[2], b + f[3]});
}

// cull=auto drops the faces of closed meshes that the whole light sees from behind by more than 30
// degrees, and nothing else: a closed box under the light keeps its top and its sides (every light
// corner sees the -x side from behind, but at a grazing angle), loses its bottom; a plate turned
// away from the light stays (open), which cull=back drops. V moves little on average: along every
// ray from the light a kept face of the box comes first, but the source view sees the tall sides
// almost edge-on, their surfels' footprints exceed the cap (8 source pixels) and leave gaps that
// the bottom filled (the worst case: curved meshes lose far less, docs/techniques/vwss.md).
TEST(Vwss, CullAutoDropsTheFacesClosedMeshesTurnAwayFromTheWholeLight) {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  addBox(pos, idx, {-0.8f, 0.5f, -0.6f}, {0.2f, 1.6f, 0.4f});
  const size_t boxTriangles = idx.size() / 3;
  addPlate(pos, idx, 0.4f, 1.4f, -0.5f, 0.5f, 2.0f);
  for (size_t t = 3 * boxTriangles; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);  // facing down
  std::vector<uint8_t> closed(idx.size() / 3, 0);
  std::fill(closed.begin(), closed.begin() + static_cast<std::ptrdiff_t>(boxTriangles), 1);
  RectLight light;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.5f, 1.5f, glm::vec3(1), 1, light);
  const Geometry g{pos, idx, closed};
  // Which triangles each choice keeps (casterDraws with the light, as the source view draws them).
  const auto kept = [&](CasterCull c) {
    const std::vector<CasterDraw> d = casterDraws(g, c, &light);
    return d.empty() ? size_t{0} : d[0].indices.size() / 3;
  };
  const size_t plateTriangles = idx.size() / 3 - boxTriangles;
  EXPECT_EQ(kept(CasterCull::None), idx.size() / 3);
  EXPECT_EQ(kept(CasterCull::Auto), 10u + plateTriangles);  // all but the box's bottom
  EXPECT_EQ(kept(CasterCull::Back), 10u);                   // and not the plate
  // The points: the box loses its bottom, the plate its only side with cull=back.
  LightRegion region;
  region.empty = false;
  region.lo = {-2.0f, -2.0f, 2.0f};
  region.hi = {2.0f, 2.0f, 4.0f};
  const LightView source = makeLightView(light, region, {0, 0}, 0.5f, 200, 200);
  raster::Rasterizer raster({.threads = 2});
  const size_t none = generateLightPoints(raster, g, source, light, true, CasterCull::None).points.size();
  const size_t autoCull = generateLightPoints(raster, g, source, light, true, CasterCull::Auto).points.size();
  const size_t back = generateLightPoints(raster, g, source, light, true, CasterCull::Back).points.size();
  std::printf("points: none %zu, auto %zu, back %zu\n", none, autoCull, back);
  EXPECT_LT(autoCull, none * 9 / 10);  // the bottom's points
  EXPECT_EQ(back, autoCull - generateLightPoints(raster, {pos, std::span(idx).subspan(3 * boxTriangles)},
                                                 source, light, true, CasterCull::None)
                                 .points.size());  // the plate's
  // V with and without culling, on ground receivers.
  ShadowInputs in;
  in.casters = g;
  ReceiverImage rec = groundReceivers(64, 64, 2.5f);
  in.receivers = &rec;
  in.light = light;
  const raster::ImageFloat vNone = run("vwss", in, 2, "views=32,map_size=256,cull=none");
  const raster::ImageFloat vAuto = run("vwss", in, 2, "views=32,map_size=256,cull=auto");
  double mean = 0;
  const double worst = maxDiff(vAuto, vNone, &mean);
  std::printf("V, cull=auto against none: max %.4f, mean %.5f\n", worst, mean);
  EXPECT_LT(worst, 0.3);
  EXPECT_LT(mean, 0.003);
}

TEST(Vwss, VariantsAndTraversalsGiveTheSameBits) {
  LeakScene s;
  const std::string base = "views=24,map_size=128";
  const raster::ImageFloat ref = run("vwss", s.in, 2, base);
  for (const char* extra : {",views_per_pass=1", ",views_per_pass=5", ",views_per_pass=0", ",mode=unbuffered",
                            ",mode=unbuffered,views_per_pass=7"}) {
    for (int threads : {1, 3}) {
      const raster::ImageFloat v = run("vwss", s.in, threads, base + extra);
      for (int y = 0; y < v.height(); ++y)
        for (int x = 0; x < v.width(); ++x)
          ASSERT_EQ(std::bit_cast<uint32_t>(v.at(x, y)), std::bit_cast<uint32_t>(ref.at(x, y)))
              << extra << " at " << threads << " threads, " << x << "," << y;
    }
  }
}

}  // namespace
}  // namespace penumbra::shadows
