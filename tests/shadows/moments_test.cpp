// The pre-filtered moment shadow maps (shadows/moments.h): vsm, evsm2, evsm4, esm. Scenes are
// built by hand: a receiver plane y = 0 seen straight down by a 1 x 1 light facing -y, horizontal
// quads as casters. Checks: lit and blocked receivers, the closed form for one planar occluder,
// range and finiteness under a huge depth range and near-contact, thread-count independence,
// light bleeding, and parameter validation; the depth-only pass and the HSM search boxes of the
// summed-area-table techniques (shadows/prefiltered.h), which share this pass.
#include "shadows/moments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "raster/kernels.h"
#include "shadows/area_light.h"
#include "shadows/light_view.h"
#include "shadows/prefiltered.h"
#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

const char* const kMoments[] = {"vsm", "evsm2", "evsm4", "esm"};

struct Scene {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  ReceiverImage receivers;
  RectLight light;

  // A horizontal quad at height y over [x0, x1] x [z0, z1].
  void quad(float x0, float x1, float z0, float z1, float y) {
    const auto base = static_cast<uint32_t>(positions.size());
    positions.insert(positions.end(), {{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  ShadowInputs inputs() const {
    return {.casters = {positions, indices}, .receivers = &receivers, .light = light, .cache = nullptr};
  }
};

// Receivers on y = 0 over [-half, half]^2 (n x n texel centres) facing up, a 1 x 1 light at height
// lightY facing down, and the receiver plane itself as a caster (slightly larger).
Scene planeScene(int n, float half, float lightY) {
  Scene s;
  EXPECT_TRUE(makeRectLight({0, lightY, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, s.light));
  s.receivers.resize(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Receiver& r = s.receivers.at(i, j);
      r.position = {(2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(n) - 1.0f) * half, 0.0f,
                    (2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(n) - 1.0f) * half};
      r.normal = {0, 1, 0};
      r.valid = 1;
    }
  s.quad(-1.1f * half, 1.1f * half, -1.1f * half, 1.1f * half, 0.0f);
  return s;
}

ShadowResult shade(const Scene& s, const char* name, const std::string& settings, int threads = 2) {
  raster::Rasterizer raster(raster::RasterConfig{.threads = threads});
  const TechniqueInfo* info = findTechnique(name);
  EXPECT_NE(info, nullptr) << name;
  ParamSet params(info->params);
  const auto err = params.setAll(settings);
  EXPECT_FALSE(err) << name << ": " << err.value_or("");
  const ShadowInputs in = s.inputs();
  ShadowResult r = computeShadows(raster, in, *info, params);
  EXPECT_FALSE(r.skipped) << r.skipReason;
  return r;
}

// What the driver sets up for a technique on one light: the region fitted to the receivers, the
// casters culled to it (for tests that call the shared passes directly).
struct LightSetup {
  ShadowInputs in;
  raster::Rasterizer raster{raster::RasterConfig{.threads = 2}};
  ShadowContext ctx{
      .raster = raster, .in = in, .region = {}, .casters = {}, .times = {}, .notes = {}, .mapPasses = {}};

  explicit LightSetup(const Scene& s) : in(s.inputs()) {
    raster.run([&] { ctx.region = fitRegion(in.light, *in.receivers); });
    ctx.casters = cullCasters(in.light, ctx.region, in.casters);
  }
};

// Smallest and largest V over the receivers whose position satisfies `in` (count: how many), after
// checking that every value of the image is finite and in [0, 1].
struct Span {
  float lo = INFINITY, hi = -INFINITY;
  int count = 0;
};
template <class Pred>
Span span(const Scene& s, const raster::ImageFloat& v, Pred in) {
  Span out;
  int bad = 0;
  for (int y = 0; y < v.height(); ++y)
    for (int x = 0; x < v.width(); ++x) {
      const float f = v.at(x, y);
      if (!(std::isfinite(f) && f >= 0.0f && f <= 1.0f) && bad++ == 0)
        ADD_FAILURE() << "V = " << f << " at " << x << "," << y;
      if (!in(s.receivers.at(x, y).position)) continue;
      out.lo = std::min(out.lo, f);
      out.hi = std::max(out.hi, f);
      ++out.count;
    }
  return out;
}

float maxAbs(glm::vec3 p) {
  return std::max(std::abs(p.x), std::abs(p.z));
}

// (a) One 1 x 1 occluder at height 2 under a light at height 4, default parameters: receivers
// outside the area light's penumbra (max(|x|, |z|) > 1.5) are lit, those in its umbra (< 0.5)
// blocked. Without the bleeding reduction the Chebyshev techniques keep their bound's floor there,
// about minVariance / D^2 (D = the occluder-receiver gap in normalized depth, here 0.94; EVSM:
// minVariance c^2, the gap being ~1 in warped units relative to the receiver).
TEST(Moments, LitAndBlocked) {
  Scene s = planeScene(96, 2.0f, 4.0f);
  s.quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f);
  for (const char* name : kMoments) {
    for (const char* settings : {"", "bleed_reduction=0"}) {
      const bool raw = settings[0] != '\0';
      if (raw && std::string(name) == "esm") continue;
      const ShadowResult r = shade(s, name, settings);
      const Span lit = span(s, r.visibility, [](glm::vec3 p) { return maxAbs(p) > 1.5f; });
      ASSERT_GT(lit.count, 1000);
      EXPECT_EQ(lit.lo, 1.0f) << name;  // exactly: the receiver is in front of its own mean depth
      const Span blocked = span(s, r.visibility, [](glm::vec3 p) { return maxAbs(p) < 0.5f; });
      ASSERT_GT(blocked.count, 100);
      EXPECT_LT(blocked.hi, raw ? 2e-4f : 1e-6f) << name << " " << settings;
      std::printf("[ moments ] %-5s %-17s lit min %.9g, blocked max %.3g\n", name, settings,
                  static_cast<double>(lit.lo), static_cast<double>(blocked.hi));
      EXPECT_GT(r.mapPasses.trianglesIn, 0u) << name;
      EXPECT_GT(r.times.msMaps, 0.0) << name;
    }
  }
}

// For one planar occluder over a receiver plane parallel to the light that is itself in the map,
// with no bias and no bleeding reduction, every technique of the family equals Gaussian-weighted
// PCF: the filter region holds two depths, z_o with weight f and the receiver's z_g with 1 - f,
// and t = z_g (or its warp), so Chebyshev's bound is f(1-f)D^2 / (f(1-f)D^2 + f^2 D^2) = 1 - f and
// ESM's f exp(-c D) + (1 - f) is 1 - f up to exp(-c D) (D = z_g - z_o). The reference: the same
// view's hard depth map, its occluder mask blurred with the same Gaussian, sampled bilinearly.
// The driver's caster culling drops the receiver plane (it cannot block anything); the moment map
// draws it anyway (moments.h, momentCasters), without which this fails by up to 0.78 (ESM).
TEST(Moments, OnePlanarOccluderIsGaussianPcf) {
  Scene s = planeScene(80, 2.0f, 4.0f);
  s.quad(-0.53f, 0.47f, -0.45f, 0.55f, 2.0f);
  const int size = 128;
  const float sigma = 3.0f;
  LightSetup setup(s);
  const ShadowInputs& in = setup.in;
  ShadowContext& ctx = setup.ctx;
  ShadowMap hard;
  hard.view = makeLightView(in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
  renderDepthMap(ctx, hard);
  raster::ImageFloat mask(size, size);
  int covered = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float d = hard.view.depthOf(hard.depth.at(x, y));  // 2 on the occluder, 4 on the ground
      mask.at(x, y) = d < 3.0f ? 1.0f : 0.0f;
      covered += d < 3.0f ? 1 : 0;
    }
  ASSERT_GT(covered, 500);
  setup.raster.run([&] { raster::gaussianBlur(mask, mask, sigma); });
  auto coverage = [&](glm::vec2 m) {  // bilinear, clamped to the edge texels
    const float u = std::clamp(m.x - 0.5f, 0.0f, static_cast<float>(size - 1));
    const float v = std::clamp(m.y - 0.5f, 0.0f, static_cast<float>(size - 1));
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    const int x1 = std::min(x0 + 1, size - 1), y1 = std::min(y0 + 1, size - 1);
    const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
    return (1 - fy) * ((1 - fx) * mask.at(x0, y0) + fx * mask.at(x1, y0)) +
           fy * ((1 - fx) * mask.at(x0, y1) + fx * mask.at(x1, y1));
  };

  const std::string common = "map_size=" + std::to_string(size) + ",filter_sigma=3,bias=0,slope_bias=0";
  for (const char* name : kMoments) {
    const std::string settings = common + (std::string(name) == "esm" ? "" : ",bleed_reduction=0");
    const ShadowResult r = shade(s, name, settings);
    float worst = 0.0f;
    int penumbra = 0;
    for (int y = 0; y < s.receivers.height(); ++y)
      for (int x = 0; x < s.receivers.width(); ++x) {
        const glm::vec3 p = s.receivers.at(x, y).position;
        const float f = coverage(hard.view.toMap(hard.view.toView(p)));
        penumbra += (f > 0.01f && f < 0.99f) ? 1 : 0;
        worst = std::max(worst, std::abs(r.visibility.at(x, y) - (1.0f - f)));
      }
    ASSERT_GT(penumbra, 200) << name;
    EXPECT_LT(worst, 2e-3f) << name;
    std::printf("[ moments ] %-5s one planar occluder: max |V - (1 - f)| = %.3g over %d penumbra receivers\n",
                name, static_cast<double>(worst), penumbra);
  }
}

// The depth-only pass (for techniques that read z alone) writes the moment map's first channel,
// texel for texel, with the same depth range, and leaves the moments empty.
TEST(Moments, DepthOnlyPassIsTheMomentMapsFirstChannel) {
  Scene s = planeScene(60, 2.0f, 4.0f);
  s.quad(-0.53f, 0.47f, -0.45f, 0.55f, 2.0f);
  s.quad(-2.5f, 0.1f, -0.3f, 1.7f, 3.5f);
  LightSetup setup(s);
  const ShadowInputs& in = setup.in;
  ShadowContext& ctx = setup.ctx;
  MomentMap full, depthOnly;
  full.view = depthOnly.view = makeLightView(in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), 97, 83);
  full.warp = depthOnly.warp = MomentWarp{.kind = MomentKind::Vsm, .cPos = 0.0f, .cNeg = 0.0f};
  renderMomentMap(ctx, full);
  raster::ImageFloat z;
  renderNormalizedDepth(ctx, depthOnly, z);
  EXPECT_EQ(full.zNear, depthOnly.zNear);
  EXPECT_EQ(full.zFar, depthOnly.zFar);
  EXPECT_TRUE(depthOnly.texels.empty());
  ASSERT_EQ(z.width(), 97);
  ASSERT_EQ(z.height(), 83);
  int occluders = 0, mismatches = 0;
  for (int y = 0; y < 83; ++y)
    for (int x = 0; x < 97; ++x) {
      mismatches += z.at(x, y) == full.texels.at(x, y).r ? 0 : 1;
      occluders += z.at(x, y) < 0.6f ? 1 : 0;
    }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(occluders, 100);  // both quads are drawn
}

// HSM: a search box shrunk by the min/max pyramid still holds every texel that can block the
// receiver (one in front of it, inside the light's frustum from the receiver cut at the texel's own
// depth), and it does shrink where the near plane's box is loose. Occluders near the light over
// half the scene, one at mid height, one near the receivers.
TEST(Moments, HsmSearchBoxesHoldEveryTexelThatCanBlock) {
  Scene s = planeScene(40, 2.0f, 4.0f);
  s.quad(-2.5f, -0.2f, -0.3f, 1.7f, 3.5f);
  s.quad(-0.53f, 0.47f, -0.45f, 0.55f, 2.0f);
  s.quad(0.6f, 1.4f, -1.2f, -0.4f, 0.4f);
  LightSetup setup(s);
  ShadowContext& ctx = setup.ctx;
  const std::vector<ParamSpec> specs = prefilterParams(3);  // ParamSet keeps a reference
  ParamSet params(specs);
  ASSERT_FALSE(params.setAll("map_size=96"));
  PrefilterMap m;
  preparePrefilterMap(ctx, params, m);
  const BiasParams bias = biasParams(params);
  int shrunk = 0, checked = 0, outside = 0;
  for (int y = 0; y < s.receivers.height(); ++y)
    for (int x = 0; x < s.receivers.width(); ++x) {
      const ReceiverKernel near = receiverKernel(m, ctx, s.receivers.at(x, y), bias, false);
      ReceiverKernel k = near;
      shrunk += shrinkSearchBox(m, ctx, k) ? 1 : 0;
      ASSERT_LE(k.sx, near.sx);
      ASSERT_LE(k.sy, near.sy);
      const int i0 = std::max(0, static_cast<int>(std::floor(near.cx - near.sx)));
      const int i1 = std::min(m.z.width() - 1, static_cast<int>(std::ceil(near.cx + near.sx)));
      const int j0 = std::max(0, static_cast<int>(std::floor(near.cy - near.sy)));
      const int j1 = std::min(m.z.height() - 1, static_cast<int>(std::ceil(near.cy + near.sy)));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const float z = m.z.at(i, j);
          if (!(static_cast<double>(z) < near.zr)) continue;  // not in front of the receiver
          const glm::dvec2 reach = penumbraHalf(m, ctx, near, static_cast<double>(z), 0.0);
          const double dx = std::abs(i + 0.5 - near.cx), dy = std::abs(j + 0.5 - near.cy);
          if (dx > reach.x || dy > reach.y) continue;  // cannot block: outside the frustum at its depth
          ++checked;
          // Its texel square meets the shrunk box.
          outside += (dx > k.sx + 0.5 || dy > k.sy + 0.5) ? 1 : 0;
        }
    }
  EXPECT_EQ(outside, 0);
  EXPECT_GT(checked, 10000);
  EXPECT_GT(shrunk, s.receivers.width() * s.receivers.height() / 4);
}

// (b) Stress. A light 1e5 above the receivers with a caster 2 units from the light over x > 1
// (far / near = 5e4) and a caster 2 units above the receivers; and, under a light at height 4, a
// receiver 1e-4 below its occluder. (Under the light at 1e5 an occluder within 1 unit of the
// receivers is culled by the driver, cullCasters: 1e-5 of the scene's size.) Every output finite
// and in [0, 1]; the shadow of the caster near the light is resolved exactly. The caster 2 units
// above the receivers is 2e-5 of the depth range away from them and the 1e-4 gap is 1.3e-3 of it,
// below what the family resolves (sqrt(min_variance), ln(100) / c, the bias): those receivers
// come out lit, measured and printed.
TEST(Moments, HugeDepthRangeAndNearContact) {
  const float h = 1e5f;
  Scene far = planeScene(64, 2.0f, h);
  far.quad(2e-5f, 1.0f, -1.0f, 1.0f, h - 2.0f);  // tan x > 1e-5: the receivers at x > 1
  far.quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f);
  Scene contact = planeScene(64, 2.0f, 4.0f);
  contact.quad(-0.5f, 0.5f, -0.5f, 0.5f, 1e-4f);
  for (const char* name : kMoments) {
    // One texel is 4/128 world units on the receivers: sigma 8 blurs over 3 sigma = 0.75 units.
    for (const char* settings :
         {"map_size=128", "map_size=128,filter_sigma=0", "map_size=128,filter_sigma=8"}) {
      const ShadowResult rf = shade(far, name, settings);
      EXPECT_LT(span(far, rf.visibility, [](glm::vec3 p) { return p.x > 1.8f; }).hi, 1e-6f)
          << name << " " << settings;
      EXPECT_EQ(span(far, rf.visibility, [](glm::vec3 p) { return p.x < -1.8f; }).lo, 1.0f)
          << name << " " << settings;
      const Span under = span(far, rf.visibility, [](glm::vec3 p) { return maxAbs(p) < 0.3f; });
      const ShadowResult rc = shade(contact, name, settings);
      const Span touching = span(contact, rc.visibility, [](glm::vec3 p) { return maxAbs(p) < 0.3f; });
      std::printf(
          "[ moments ] %-5s %-28s V under a caster 2 above at distance 1e5: >= %.3g; 1e-4 above: >= %.3g "
          "(truth 0)\n",
          name, settings, static_cast<double>(under.lo), static_cast<double>(touching.lo));
    }
  }
}

// (c) The same bytes at 1 and 3 threads.
TEST(Moments, SameBytesAtAnyThreadCount) {
  Scene s = planeScene(72, 2.0f, 4.0f);
  s.quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f);
  s.quad(-2.5f, 0.1f, -0.3f, 1.7f, 3.5f);
  for (const char* name : kMoments) {
    const std::vector<float> a = shade(s, name, "map_size=200,filter_sigma=2.5", 1).visibility.packed();
    const std::vector<float> b = shade(s, name, "map_size=200,filter_sigma=2.5", 3).visibility.packed();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << name;
  }
}

// (d) Light bleeding, the classic case: occluder A near the light (height 3.5, x < 0) and occluder
// B near the receivers (height 0.5, |x| < 1). Every receiver with |x| <= 0.8 is in B's umbra
// (|x| <= 1.07 for this 1 x 1 light), so V should be 0 there; where the filter straddles A's edge
// in the map, it holds depths z_A and z_B far apart, a large variance, and the Chebyshev bound
// lets light through (Donnelly & Lauritzen 2006, section 4; Lauritzen & McCool 2008, section 3).
TEST(Moments, LightBleeding) {
  Scene s = planeScene(128, 2.0f, 4.0f);
  s.quad(-2.5f, 0.0f, -2.5f, 2.5f, 3.5f);
  s.quad(-1.0f, 1.0f, -2.5f, 2.5f, 0.5f);
  auto bleed = [&](const char* name, const std::string& settings) {
    const ShadowResult r = shade(s, name, "map_size=256,filter_sigma=4" + settings);
    const Span umbra = span(s, r.visibility, [](glm::vec3 p) { return std::abs(p.x) <= 0.8f; });
    EXPECT_GT(umbra.count, 1000);
    std::printf("[ moments ] %-5s %-22s light bleeding: max V = %.4g in the umbra\n", name, settings.c_str(),
                static_cast<double>(umbra.hi));
    return umbra.hi;
  };
  const float vsm0 = bleed("vsm", ",bleed_reduction=0");
  const float vsm = bleed("vsm", "");
  const float vsm5 = bleed("vsm", ",bleed_reduction=0.5");
  const float evsm2 = bleed("evsm2", ",bleed_reduction=0");
  const float evsm40 = bleed("evsm4", ",bleed_reduction=0");
  const float evsm4 = bleed("evsm4", "");
  const float esm = bleed("esm", "");
  EXPECT_GT(vsm0, 0.2f);  // the case does bleed
  EXPECT_LT(vsm, vsm0 - 0.05f);
  EXPECT_LT(vsm5, vsm);
  EXPECT_LT(evsm40, 0.1f * vsm0);
  EXPECT_LE(evsm40, evsm2);  // the min of two bounds (here the negative warp adds nothing)
  EXPECT_LE(evsm4, vsm);
  EXPECT_LT(esm, 0.1f * vsm0);
}

// (e) Out-of-range values are rejected with a message naming the range.
TEST(Moments, ParameterRanges) {
  auto rejects = [](const char* name, const char* assignment, const char* range) {
    const TechniqueInfo* info = findTechnique(name);
    ASSERT_NE(info, nullptr);
    ParamSet p(info->params);
    const auto err = p.set(assignment);
    ASSERT_TRUE(err) << name << " accepted " << assignment;
    EXPECT_NE(err->find(range), std::string::npos) << *err;
  };
  rejects("vsm", "bleed_reduction=1", "[0, 0.99]");
  rejects("vsm", "min_variance=-1e-6", "[0, 0.01]");
  rejects("vsm", "filter_sigma=65", "[0, 64]");
  rejects("vsm", "map_size=8", "[16, 8192]");
  rejects("evsm2", "exponent_pos=43", "[0, 42]");  // exp(2 * 43) is within e^3 of FLT_MAX
  rejects("evsm2", "exponent_neg=5", "unknown parameter");
  rejects("evsm4", "exponent_neg=42.5", "[0, 42]");
  rejects("esm", "exponent=89", "[1, 88]");  // exp(89) > FLT_MAX
  rejects("esm", "exponent=0.5", "[1, 88]");
  rejects("esm", "min_variance=0", "unknown parameter");
  // The bounds themselves are accepted, and give finite output (the overflow bound of the headers).
  for (const char* name : {"evsm2", "evsm4", "esm"}) {
    const TechniqueInfo* info = findTechnique(name);
    ParamSet p(info->params);
    for (const ParamSpec& spec : info->params)
      if (spec.name.starts_with("exponent")) {
        EXPECT_FALSE(p.set(spec.name + "=" + std::to_string(spec.maxValue)));
      }
  }
}

// The exponents at their upper bounds: the largest moment is exp(84) (EVSM) or exp(88) (ESM),
// still finite, and the output stays in [0, 1] with receivers at z = 1 (the far plane).
TEST(Moments, ExponentsAtTheirBounds) {
  Scene s = planeScene(48, 2.0f, 4.0f);
  s.quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f);
  const std::pair<const char*, const char*> cases[] = {{"evsm2", "exponent_pos=42"},
                                                       {"evsm4", "exponent_pos=42,exponent_neg=42"},
                                                       {"evsm4", "exponent_pos=0,exponent_neg=0"},
                                                       {"esm", "exponent=88"},
                                                       {"vsm", "min_variance=0,bleed_reduction=0"}};
  for (const auto& [name, settings] : cases) {
    const ShadowResult r = shade(s, name, std::string("map_size=64,") + settings);
    EXPECT_EQ(span(s, r.visibility, [](glm::vec3 p) { return maxAbs(p) > 1.5f; }).lo, 1.0f)
        << name << " " << settings;
    const Span blocked = span(s, r.visibility, [](glm::vec3 p) { return maxAbs(p) < 0.5f; });
    if (std::string(settings) != "exponent_pos=0,exponent_neg=0") {
      EXPECT_LT(blocked.hi, 0.01f) << name << " " << settings;
    } else {
      EXPECT_EQ(blocked.lo, 1.0f) << "c = 0: constant warps, no information";
    }
  }
}

}  // namespace
}  // namespace penumbra::shadows
