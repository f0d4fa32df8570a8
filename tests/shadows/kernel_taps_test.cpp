// The SIMD tap kernels of PCF and PCSS (shadows/kernel_taps.h) against their scalar references, bit
// for bit on every SIMD target: on random maps, planes and patterns (taps outside the map, clamped
// thresholds, +inf thresholds, NaN coordinates), and on whole images through computeShadows against
// the techniques' original scalar loops.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "raster/kernels.h"
#include "shadows/area_light.h"
#include "shadows/kernel_taps.h"
#include "shadows/pcf.h"
#include "shadows/sampling.h"
#include "shadows/shadow_map.h"
#include "raster/simd.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }
uint32_t bits(float v) { return std::bit_cast<uint32_t>(v); }

// A random map (padded rows) with lookup constants mapping tangent range [-1, 1] x [-1, 1] onto it,
// like ShadowMap::prepareLookup. A quarter of its texels are 0 (nothing drawn), a quarter up to
// 1e9 (not physical: near / z, depths down to 1e-9 near, so that blocker depths span more than the
// 2^23 over which their double sum is exact in any order, and the order is tested).
struct RandomMap {
  std::vector<float> texels;
  TapMap map;

  explicit RandomMap(std::mt19937& rng) {
    std::uniform_int_distribution<int> size(1, 70);
    const int w = size(rng), h = size(rng), stride = (w + 7) / 8 * 8;
    std::uniform_real_distribution<float> z(0.01f, 1.0f), u(0.0f, 1.0f), decades(0.0f, 9.0f);
    texels.resize(static_cast<size_t>(stride) * static_cast<size_t>(h));
    for (float& t : texels) {
      const float r = u(rng);
      t = r < 0.25f ? 0.0f : r < 0.5f ? std::pow(10.0f, decades(rng)) : z(rng);
    }
    map.data = texels.data();
    map.stride = stride;
    map.ax = static_cast<float>(w) / 2.0f;
    map.bx = map.ax;
    map.ay = -static_cast<float>(h) / 2.0f;
    map.by = -map.ay;
    map.maxX = static_cast<float>(w - 1);
    map.maxY = static_cast<float>(h - 1);
  }
};

// A random plane like ReceiverPlane's: thresholds near the map's values, clamps at lo and hi often
// active, scale +inf for one plane in eight (bias beta >= 1).
TapPlane randomPlane(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f), slope(-1.0f, 1.0f);
  TapPlane p;
  p.a = slope(rng);
  p.b = slope(rng);
  p.c = 0.3f + u(rng);
  p.lo = 0.3f + 0.6f * u(rng);
  p.hi = p.lo + 0.8f * u(rng);
  p.scale = u(rng) < 0.125f ? INFINITY : 0.5f + u(rng);
  return p;
}

TEST(KernelTaps, EveryTargetMatchesTheScalarReference) {
  const std::vector<int64_t> targets = raster::supportedSimdTargets();
  ASSERT_FALSE(targets.empty());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), centre(-1.3f, 1.3f), offset(-8.0f, 8.0f);
  std::uniform_int_distribution<int> count(0, 70);
  // How often the interesting cases came up, to know that they were tested.
  int outside = 0, clampedLo = 0, clampedHi = 0, infinite = 0, mixed = 0, nanTaps = 0, withBlockers = 0;
  for (int iter = 0; iter < 400; ++iter) {
    const RandomMap rm(rng);
    const TapMap& map = rm.map;
    const TapPlane plane = randomPlane(rng);
    const int n = count(rng);
    std::vector<glm::vec2> pts(static_cast<size_t>(n)), offs(static_cast<size_t>(n));
    for (glm::vec2& p : pts) p = {u(rng), u(rng)};
    for (glm::vec2& o : offs) o = {offset(rng), offset(rng)};
    const TapPattern pattern(pts), offsets(offs);
    const float shiftX = u(rng), shiftY = u(rng), cx = centre(rng), cy = centre(rng);
    // Half-extents up to 1.5: taps up to 2.8 from the map's centre, far outside it.
    float hx = 1.5f * u(rng), hy = 1.5f * u(rng);
    if (iter % 50 == 7) hx = NAN;  // NaN coordinates read texel 0 and meet the lo clamp, as in the scalar code
    const float angle = 2.0f * std::numbers::pi_v<float> * u(rng);
    const float c = std::cos(angle), s = std::sin(angle), texelX = 2.0f / map.ax, texelY = -2.0f / map.ay;
    const float znear = 0.05f + u(rng);

    // The references, and what their taps did.
    const int lit =
        countLitTapsScalar(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx, hy);
    const BlockerSum blockers = searchBlockersScalar(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY,
                                                     cx, cy, hx, hy, znear);
    const int litRotated = countLitRotatedTapsScalar(map, plane, offsets.x.data(), offsets.y.data(), n, c, s, cx, cy,
                                                     texelX, texelY);
    ASSERT_EQ(lit + blockers.count, n);  // no NaN stored values or thresholds: each tap is lit or blocks
    for (int i = 0; i < n; ++i) {
      float x = pattern.x[static_cast<size_t>(i)] + shiftX, y = pattern.y[static_cast<size_t>(i)] + shiftY;
      x -= std::floor(x);
      y -= std::floor(y);
      const float tx = cx + (2.0f * x - 1.0f) * hx, ty = cy + (2.0f * y - 1.0f) * hy;
      const float fx = map.ax * tx + map.bx;
      outside += fx < 0.0f || fx > map.maxX;
      nanTaps += std::isnan(tx);
      const float v = plane.a * tx + plane.b * ty + plane.c;
      clampedLo += v < plane.lo;
      clampedHi += v > plane.hi;
    }
    infinite += std::isinf(plane.scale) && n > 0;
    mixed += lit > 0 && lit < n;
    withBlockers += blockers.count > 1;

    for (int64_t target : targets) {
      SCOPED_TRACE(raster::simdTargetName(target));
      ASSERT_EQ(countLitTaps(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx, hy, target), lit)
          << "iteration " << iter << ", n " << n;
      const BlockerSum b = searchBlockers(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx,
                                          hy, znear, target);
      ASSERT_EQ(b.count, blockers.count) << "iteration " << iter;
      ASSERT_EQ(bits(b.sum), bits(blockers.sum)) << "iteration " << iter << ": " << b.sum << " vs " << blockers.sum;
      ASSERT_EQ(countLitRotatedTaps(map, plane, offsets.x.data(), offsets.y.data(), n, c, s, cx, cy, texelX, texelY, target),
                litRotated)
          << "iteration " << iter;
    }
  }
  EXPECT_GT(outside, 1000);
  EXPECT_GT(clampedLo, 100);
  EXPECT_GT(clampedHi, 100);
  EXPECT_GT(infinite, 20);
  EXPECT_GT(mixed, 100);
  EXPECT_GT(nanTaps, 100);
  EXPECT_GT(withBlockers, 100);
}

// The smallest float v in [lo, hi] (0 <= lo <= hi) with above(v), for a predicate that is false
// then true over [lo, hi] (the bit patterns of non-negative floats are ordered like their values).
template <class F>
float firstAbove(float lo, float hi, F above) {
  uint32_t a = bits(lo), b = bits(hi);
  while (a < b) {
    const uint32_t m = a + (b - a) / 2;
    if (above(std::bit_cast<float>(m))) b = m;
    else a = m + 1;
  }
  return std::bit_cast<float>(a);
}

// Taps where one ulp matters, which random taps almost never are: pattern points at the pairs of
// adjacent floats across which a tap's column or row changes (found by bisection, as a tap
// coordinate is monotone in its pattern point), on a map whose texels hold exactly the threshold of
// a tap that reads them or the next float above it. A fused multiply-add, another clamp or another
// order of operations anywhere in a tap's computation changes some of these taps' results.
TEST(KernelTaps, TapsOnTexelEdgesAndThresholdsMatch) {
  const std::vector<int64_t> targets = raster::supportedSimdTargets();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int mixed = 0, edges = 0;
  for (int iter = 0; iter < 200; ++iter) {
    RandomMap rm(rng);
    TapMap& map = rm.map;
    TapPlane plane = randomPlane(rng);
    plane.scale = 0.5f + u(rng);
    const float shiftX = 0.5f * u(rng), shiftY = 0.5f * u(rng), cx = 0.4f * u(rng) - 0.2f, cy = 0.4f * u(rng) - 0.2f;
    const float hx = 0.3f + u(rng), hy = 0.3f + u(rng), znear = 0.1f;
    const float angle = 2.0f * u(rng) - 1.0f, c = std::cos(angle), s = std::sin(angle);
    const float texelX = 2.0f / map.ax, texelY = -2.0f / map.ay;
    auto shifted = [](float p, float shift, float centre, float h) {
      p += shift;
      p -= std::floor(p);
      return centre + (2.0f * p - 1.0f) * h;
    };
    auto column = [&](float tx) { return static_cast<int>(std::min(map.maxX, std::max(0.0f, map.ax * tx + map.bx))); };
    auto row = [&](float ty) { return static_cast<int>(std::min(map.maxY, std::max(0.0f, map.ay * ty + map.by))); };
    // Pattern points below 1 - shift (no wrap: tanX and tanY grow with them, columns grow, rows
    // fall); offsets in [0, 8] texels with c > 0 (tanX grows with o.x, tanY falls with o.y: rows
    // grow). Each boundary is the first point at which the column or row of a random point's tap
    // is reached.
    const float endX = (1.0f - shiftX) * 0.99f, endY = (1.0f - shiftY) * 0.99f;
    auto pcssX = [&](float p) { return column(shifted(p, shiftX, cx, hx)); };
    auto pcssY = [&](float p) { return row(shifted(p, shiftY, cy, hy)); };
    std::vector<glm::vec2> pts, offs;
    for (int k = 0; k < 12; ++k) {
      const float px = u(rng) * endX, py = u(rng) * endY, ox = 8.0f * u(rng), oy = 8.0f * u(rng);
      auto pcfX = [&](float o) { return column(cx + (c * o - s * oy) * texelX); };
      auto pcfY = [&](float o) { return row(cy - (s * ox + c * o) * texelY); };
      const float x = firstAbove(0.0f, endX, [&](float p) { return pcssX(p) >= pcssX(px); });
      const float y = firstAbove(0.0f, endY, [&](float p) { return pcssY(p) <= pcssY(py); });
      pts.insert(pts.end(), {{x, py}, {std::nextafter(x, 0.0f), py}, {px, y}, {px, std::nextafter(y, 0.0f)}});
      edges += (pcssX(x) != pcssX(std::nextafter(x, 0.0f))) + (pcssY(y) != pcssY(std::nextafter(y, 0.0f)));
      const float bx = firstAbove(0.0f, 8.0f, [&](float o) { return pcfX(o) >= pcfX(ox); });
      const float by = firstAbove(0.0f, 8.0f, [&](float o) { return pcfY(o) >= pcfY(oy); });
      offs.insert(offs.end(), {{bx, oy}, {std::nextafter(bx, 0.0f), oy}, {ox, by}, {ox, std::nextafter(by, 0.0f)}});
      edges += (pcfX(bx) != pcfX(std::nextafter(bx, 0.0f))) + (pcfY(by) != pcfY(std::nextafter(by, 0.0f)));
    }
    // Texels at the thresholds of the taps that read them (the last such tap's): lit by exactly
    // that threshold (odd taps) or blocked by one ulp (even taps).
    auto pin = [&](float tx, float ty, size_t i) {
      const float t = plane.threshold(tx, ty);
      const size_t at =
          static_cast<size_t>(row(ty)) * static_cast<size_t>(map.stride) + static_cast<size_t>(column(tx));
      rm.texels[at] = i % 2 ? t : std::nextafter(t, INFINITY);
    };
    for (size_t i = 0; i < pts.size(); ++i)
      pin(shifted(pts[i].x, shiftX, cx, hx), shifted(pts[i].y, shiftY, cy, hy), i);
    for (size_t i = 0; i < offs.size(); ++i)
      pin(cx + (c * offs[i].x - s * offs[i].y) * texelX, cy - (s * offs[i].x + c * offs[i].y) * texelY, i);
    const TapPattern pattern(pts), offsets(offs);
    const int n = pattern.count;
    const int lit =
        countLitTapsScalar(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx, hy);
    const BlockerSum blockers = searchBlockersScalar(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY,
                                                     cx, cy, hx, hy, znear);
    const int litRotated = countLitRotatedTapsScalar(map, plane, offsets.x.data(), offsets.y.data(), n, c, s, cx, cy,
                                                     texelX, texelY);
    mixed += lit > n / 4 && lit < 3 * n / 4 && litRotated > n / 4 && litRotated < 3 * n / 4;
    for (int64_t target : targets) {
      SCOPED_TRACE(raster::simdTargetName(target));
      ASSERT_EQ(countLitTaps(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx, hy, target), lit)
          << "iteration " << iter;
      const BlockerSum b = searchBlockers(map, plane, pattern.x.data(), pattern.y.data(), n, shiftX, shiftY, cx, cy, hx,
                                          hy, znear, target);
      ASSERT_EQ(b.count, blockers.count) << "iteration " << iter;
      ASSERT_EQ(bits(b.sum), bits(blockers.sum)) << "iteration " << iter;
      ASSERT_EQ(countLitRotatedTaps(map, plane, offsets.x.data(), offsets.y.data(), n, c, s, cx, cy, texelX, texelY, target),
                litRotated)
          << "iteration " << iter;
    }
  }
  EXPECT_GT(mixed, 100);
  EXPECT_GT(edges, 8000);  // of 200 * 48 pairs straddling a texel edge (fewer at the map's borders)
}

TEST(KernelTaps, TapPatternPadsWithUncountedZeros) {
  const std::vector<glm::vec2> pts = {{0.25f, 0.5f}, {0.75f, 0.125f}, {0.5f, 0.875f}};
  const TapPattern p(pts);
  EXPECT_EQ(p.count, 3);
  ASSERT_EQ(p.x.size(), static_cast<size_t>(kTapLanes));
  ASSERT_EQ(p.y.size(), static_cast<size_t>(kTapLanes));
  EXPECT_EQ(p.x[1], 0.75f);
  EXPECT_EQ(p.y[2], 0.875f);
  for (size_t i = 3; i < p.x.size(); ++i) EXPECT_EQ(p.x[i] + p.y[i], 0.0f);
  // A map of one texel that blocks every tap: the padding lanes are not counted.
  const float texel = 1.0f;
  const TapMap map{.data = &texel, .stride = 8, .ax = 1, .bx = 0, .ay = 1, .by = 0, .maxX = 0, .maxY = 0};
  const TapPlane plane{.a = 0, .b = 0, .c = 0.5f, .lo = 0.1f, .hi = 1.0f, .scale = 1.0f};
  for (int64_t target : raster::supportedSimdTargets()) {
    EXPECT_EQ(countLitTaps(map, plane, p.x.data(), p.y.data(), p.count, 0, 0, 0, 0, 1, 1, target), 0);
    const BlockerSum b = searchBlockers(map, plane, p.x.data(), p.y.data(), p.count, 0, 0, 0, 0, 1, 1, 0.5f, target);
    EXPECT_EQ(b.count, 3);
    EXPECT_EQ(b.sum, 1.5);
  }
}

// ---- Whole images -----------------------------------------------------------------------------

// PCSS and PCF as they were before the tap kernels, one scalar tap at a time through
// ShadowMap::stored and ReceiverPlane::threshold (pcss.cpp and pcf.cpp, timing and notes left out).
class ScalarPcss final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    for (int i = 0, n = params.integer("blocker_samples"); i < n; ++i)
      blocker_.push_back(hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n)));
    for (int i = 0, n = params.integer("filter_samples"); i < n; ++i)
      filter_.push_back(hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n)));
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    minMax_ = params.choice("minmax") == "on";
    if (minMax_) pyramid_ = raster::buildMinMaxPyramid(map_.depth.image());
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const LightView& view = map_.view;
    const glm::vec2 halfLight(0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height);
    const float znear = view.znear;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverPlane plane(view, view.toView(r.position), r.normal, bias_);
      const float dr = plane.depth();
      const glm::vec2 shift(unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10cu)),
                            unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10du)));
      auto tap = [&](glm::vec2 p, glm::vec2 h, float& tx, float& ty) {
        p += shift;
        p -= glm::floor(p);
        tx = plane.tanX() + (2.0f * p.x - 1.0f) * h.x;
        ty = plane.tanY() + (2.0f * p.y - 1.0f) * h.y;
      };
      const glm::vec2 search = halfLight * std::max(1.0f / znear - 1.0f / dr, 0.0f);
      if (minMax_ && testBox(map_, pyramid_, plane, plane.tanX() - search.x, plane.tanY() - search.y,
                             plane.tanX() + search.x, plane.tanY() + search.y) == BoxTest::AllLit)
        return 1.0f;
      double sum = 0.0;
      int blockers = 0;
      for (const glm::vec2& p : blocker_) {
        float tx, ty;
        tap(p, search, tx, ty);
        const float z = map_.stored(tx, ty);
        if (z > plane.threshold(tx, ty)) {
          sum += static_cast<double>(view.depthOf(z));
          ++blockers;
        }
      }
      if (blockers == 0) return 1.0f;
      const float db = static_cast<float>(sum / blockers);
      const glm::vec2 filter = halfLight * std::max(1.0f / db - 1.0f / dr, 0.0f);
      const BoxTest box = minMax_ ? testBox(map_, pyramid_, plane, plane.tanX() - filter.x, plane.tanY() - filter.y,
                                            plane.tanX() + filter.x, plane.tanY() + filter.y)
                                  : BoxTest::Mixed;
      if (box != BoxTest::Mixed) return box == BoxTest::AllLit ? 1.0f : 0.0f;
      int lit = 0;
      for (const glm::vec2& p : filter_) {
        float tx, ty;
        tap(p, filter, tx, ty);
        lit += map_.stored(tx, ty) <= plane.threshold(tx, ty) ? 1 : 0;
      }
      return static_cast<float>(lit) / static_cast<float>(filter_.size());
    });
  }

 private:
  ShadowMap map_;
  BiasParams bias_;
  std::vector<glm::vec2> blocker_, filter_;
  raster::MinMaxPyramid pyramid_;
  bool minMax_ = true;
};

class ScalarPcf final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    radius_ = static_cast<float>(params.number("radius"));
    const int taps = params.integer("taps");
    rotate_ = params.choice("kernel") == "poisson";
    if (rotate_) {
      for (glm::vec2 p : poissonDisk(taps)) offsets_.push_back(p * radius_);
    } else {
      const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(taps)))));
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)
          offsets_.push_back(
              side == 1 ? glm::vec2(0.0f)
                        : glm::vec2(radius_ * (2.0f * static_cast<float>(i) / static_cast<float>(side - 1) - 1.0f),
                                    radius_ * (2.0f * static_cast<float>(j) / static_cast<float>(side - 1) - 1.0f)));
    }
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    minMax_ = params.choice("minmax") == "on";
    if (minMax_) pyramid_ = raster::buildMinMaxPyramid(map_.depth.image());
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const LightView& view = map_.view;
    const glm::vec2 texel((view.tanHi.x - view.tanLo.x) / static_cast<float>(view.width),
                          (view.tanHi.y - view.tanLo.y) / static_cast<float>(view.height));
    const float tapCount = static_cast<float>(offsets_.size());
    const glm::vec2 box = radius_ * texel;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverPlane plane(view, view.toView(r.position), r.normal, bias_);
      if (minMax_) {
        const BoxTest t = testBox(map_, pyramid_, plane, plane.tanX() - box.x, plane.tanY() - box.y,
                                  plane.tanX() + box.x, plane.tanY() + box.y);
        if (t != BoxTest::Mixed) return t == BoxTest::AllLit ? 1.0f : 0.0f;
      }
      float c = 1.0f, s = 0.0f;
      if (rotate_) {
        const float a = 2.0f * std::numbers::pi_v<float> *
                        unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0x9cfu));
        c = std::cos(a), s = std::sin(a);
      }
      int lit = 0;
      for (const glm::vec2& o : offsets_) {
        const glm::vec2 d(c * o.x - s * o.y, s * o.x + c * o.y);
        const float tx = plane.tanX() + d.x * texel.x, ty = plane.tanY() - d.y * texel.y;
        lit += map_.stored(tx, ty) <= plane.threshold(tx, ty) ? 1 : 0;
      }
      return static_cast<float>(lit) / tapCount;
    });
  }

 private:
  ShadowMap map_;
  BiasParams bias_;
  bool rotate_ = true;
  std::vector<glm::vec2> offsets_;
  raster::MinMaxPyramid pyramid_;
  float radius_ = 0;
  bool minMax_ = true;
};

// A 1 x 1 light at height 4 facing down; occluders at heights 1 to 2.5 (a half-plane edge, a tilted
// triangle, a small floating quad); receivers on the plane y = 0 with normals tilted up to grazing,
// so that penumbrae of several widths, clamped receiver planes and large biases all occur.
struct Scene {
  static constexpr int kW = 64, kH = 24;
  std::vector<glm::vec3> positions = {{-20, 2, -20}, {-0.3f, 2, -20}, {-0.3f, 2, 20}, {-20, 2, 20},
                                      {0.3f, 1.0f, -0.6f}, {1.2f, 1.4f, -0.2f}, {0.6f, 1.2f, 0.7f},
                                      {1.4f, 2.5f, 0.2f}, {1.8f, 2.5f, 0.2f}, {1.8f, 2.5f, 0.6f}, {1.4f, 2.5f, 0.6f}};
  std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 7, 8, 9, 7, 9, 10};
  ReceiverImage receivers{kW, kH};
  ShadowInputs in;

  Scene() {
    for (int j = 0; j < kH; ++j)
      for (int i = 0; i < kW; ++i) {
        Receiver& r = receivers.at(i, j);
        const float x = -2.0f + 4.5f * (static_cast<float>(i) + 0.5f) / kW;
        const float z = -1.0f + 2.0f * (static_cast<float>(j) + 0.5f) / kH;
        r.position = {x, 0.02f * static_cast<float>(j % 3), z};
        const float tilt = static_cast<float>(j % 6) * 0.35f;  // up to 1.75 rad from the vertical
        r.normal = glm::normalize(glm::vec3(std::sin(tilt), std::cos(tilt), 0.1f));
        r.valid = (i + j) % 17 != 0;
      }
    makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1.0f, in.light);
    in.casters = {positions, indices};
    in.receivers = &receivers;
  }
};

// The technique's V with its tap kernels on one SIMD target (0: the best), the tile stage on the
// best: the target of one kernel family is the rasterizer's to choose, family by family.
raster::ImageFloat render(const TechniqueInfo& info, const Scene& scene, const std::string& params, int64_t taps = 0) {
  raster::Rasterizer raster({.threads = 2, .simd = {.taps = taps}});
  ParamSet p(info.params);
  EXPECT_FALSE(p.setAll(params)) << params;
  return computeShadows(raster, scene.in, info, p).visibility;
}

TEST(KernelTaps, PcssAndPcfImagesMatchTheScalarLoopsOnEveryTarget) {
  const Scene scene;
  TechniqueInfo scalarPcss = *findTechnique("pcss"), scalarPcf = *findTechnique("pcf");
  scalarPcss.make = [] { return std::make_unique<ScalarPcss>(); };
  scalarPcf.make = [] { return std::make_unique<ScalarPcf>(); };
  struct Case {
    const TechniqueInfo* fast;
    const TechniqueInfo* scalar;
    std::string params;
  };
  const std::vector<Case> cases = {
      {findTechnique("pcss"), &scalarPcss, "map_size=512"},
      {findTechnique("pcss"), &scalarPcss, "map_size=256,minmax=off,blocker_samples=13,filter_samples=37"},
      {findTechnique("pcss"), &scalarPcss, "map_size=64,bias=40,slope_bias=40,blocker_samples=5,filter_samples=70"},
      {findTechnique("pcf"), &scalarPcf, "map_size=512"},
      {findTechnique("pcf"), &scalarPcf, "map_size=256,minmax=off,taps=29,radius=11"},
      {findTechnique("pcf"), &scalarPcf, "map_size=128,kernel=grid,taps=49,radius=3"},
      {findTechnique("pcf"), &scalarPcf, "map_size=64,bias=40,slope_bias=40,minmax=off"},
  };
  const std::vector<int64_t> targets = raster::supportedSimdTargets();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.fast->name + " " + c.params);
    const raster::ImageFloat reference = render(*c.scalar, scene, c.params);
    // The image has penumbrae (so the taps decide something) and full shadow.
    int partial = 0, dark = 0;
    for (int j = 0; j < Scene::kH; ++j)
      for (int i = 0; i < Scene::kW; ++i) {
        const float v = reference.at(i, j);
        partial += v > 0.0f && v < 1.0f;
        dark += v == 0.0f && scene.receivers.at(i, j).valid;
      }
    EXPECT_GT(partial, 50);
    EXPECT_GT(dark, 20);
    for (int64_t target : targets) {
      SCOPED_TRACE(raster::simdTargetName(target));
      const raster::ImageFloat v = render(*c.fast, scene, c.params, target);
      for (int j = 0; j < Scene::kH; ++j)
        for (int i = 0; i < Scene::kW; ++i)
          ASSERT_EQ(bits(v.at(i, j)), bits(reference.at(i, j))) << "at " << i << "," << j << ": " << v.at(i, j)
                                                                 << " vs " << reference.at(i, j);
    }
  }
}

}  // namespace
}  // namespace penumbra::shadows
