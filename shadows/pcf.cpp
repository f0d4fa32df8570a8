#include "shadows/pcf.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "shadows/kernel_taps.h"
#include "shadows/sampling.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

std::vector<glm::vec2> poissonDisk(int n, uint32_t seed) {
  std::vector<glm::vec2> pts;
  pts.reserve(static_cast<size_t>(n));
  uint32_t counter = 0;
  auto candidate = [&] {
    // Uniform in the unit disk by rejection from the square.
    for (;;) {
      const glm::vec2 p(2.0f * unitFloat(hash3(seed, counter, 0)) - 1.0f, 2.0f * unitFloat(hash3(seed, counter, 1)) - 1.0f);
      ++counter;
      if (glm::dot(p, p) <= 1.0f) return p;
    }
  };
  for (int i = 0; i < n; ++i) {
    glm::vec2 best = candidate();
    float bestDist = -1.0f;
    const int tries = i == 0 ? 1 : 8 * (i + 1) > 256 ? 256 : 8 * (i + 1);
    for (int c = 0; c < tries; ++c) {
      const glm::vec2 p = c == 0 ? best : candidate();
      float d = INFINITY;
      for (const glm::vec2& q : pts) d = std::min(d, glm::dot(p - q, p - q));
      if (d > bestDist) bestDist = d, best = p;
    }
    pts.push_back(best);
  }
  return pts;
}

namespace {

class Pcf final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const auto t0 = Clock::now();
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    const float radius = static_cast<float>(params.number("radius"));
    const int taps = params.integer("taps");
    rotate_ = params.choice("kernel") == "poisson";
    std::vector<glm::vec2> offsets;
    if (rotate_) {
      for (glm::vec2 p : poissonDisk(taps)) offsets.push_back(p * radius);
    } else {
      const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(taps)))));
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)
          offsets.push_back(side == 1 ? glm::vec2(0.0f)
                                      : glm::vec2(radius * (2.0f * static_cast<float>(i) / static_cast<float>(side - 1) - 1.0f),
                                                  radius * (2.0f * static_cast<float>(j) / static_cast<float>(side - 1) - 1.0f)));
    }
    offsets_ = TapPattern(offsets);
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    ctx.times.msMaps += msSince(t0);
    const auto t1 = Clock::now();
    minMax_ = params.choice("minmax") == "on";
    if (minMax_) ctx.raster.run([&] { pyramid_ = raster::buildMinMaxPyramid(map_.depth.image()); });
    ctx.times.msFilter += msSince(t1);
    radius_ = radius;
    ctx.notes.push_back("pcf: 1 depth map " + std::to_string(size) + "^2, " + std::to_string(offsets_.count) + " taps (" +
                        params.choice("kernel") + ")");
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    const LightView& view = map_.view;
    // Tangent-space size of one texel.
    const glm::vec2 texel((view.tanHi.x - view.tanLo.x) / static_cast<float>(view.width),
                          (view.tanHi.y - view.tanLo.y) / static_cast<float>(view.height));
    const float tapCount = static_cast<float>(offsets_.count);
    const TapMap taps = map_.tapMap();
    const glm::vec2 box = radius_ * texel;
    const int64_t simd = ctx.raster.config().simd.taps;
    SkipCounter skipped;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverPlane plane(view, lookupPoint(view, r, bias_), r.normal, bias_);
      if (minMax_) {
        const BoxTest t = testBox(map_, pyramid_, plane, plane.tanX() - box.x, plane.tanY() - box.y,
                                  plane.tanX() + box.x, plane.tanY() + box.y);
        if (t != BoxTest::Mixed) {
          skipped.add();
          return t == BoxTest::AllLit ? 1.0f : 0.0f;
        }
      }
      float c = 1.0f, s = 0.0f;
      if (rotate_) {
        const float a = 2.0f * std::numbers::pi_v<float> *
                        unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0x9cfu));
        c = std::cos(a), s = std::sin(a);
      }
      // Offsets o rotated by (c, s), in texels: tap at centre + (c o.x - s o.y, -(s o.x + c o.y)) * texel.
      const int lit = countLitRotatedTaps(taps, plane.tapPlane(), offsets_.x.data(), offsets_.y.data(), offsets_.count,
                                          c, s, plane.tanX(), plane.tanY(), texel.x, texel.y, simd);
      return static_cast<float>(lit) / tapCount;  // exactly 1 when every tap passes (n * (1/n) may not be)
    });
    ctx.times.msEvaluate += msSince(t0);
    if (minMax_)
      ctx.notes.push_back("pcf: min/max test: " + std::to_string(skipped.total()) + " receivers resolved without taps");
  }

 private:
  ShadowMap map_;
  BiasParams bias_;
  bool rotate_ = true;
  TapPattern offsets_;  // texels
  raster::MinMaxPyramid pyramid_;
  float radius_ = 0;
  bool minMax_ = true;
};

}  // namespace

TechniqueInfo pcfTechnique() {
  std::vector<ParamSpec> p = depthMapParams(1024);
  p.push_back({.name = "kernel", .kind = ParamKind::Choice, .defaultValue = 1, .minValue = 0, .maxValue = 1,
               .choices = {"grid", "poisson"}, .help = "regular grid or per-pixel rotated Poisson disk"});
  p.push_back({.name = "taps", .kind = ParamKind::Int, .defaultValue = 32, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth comparisons per receiver (grid: rounded to a square)"});
  p.push_back({.name = "radius", .kind = ParamKind::Float, .defaultValue = 4, .minValue = 0, .maxValue = 256,
               .choices = {}, .help = "kernel radius, texels"});
  p.push_back(minMaxParam());
  return {.name = "pcf",
          .summary = "percentage-closer filtering over a fixed kernel (grid or rotated Poisson disk)",
          .params = std::move(p),
          .benchSettings = {"kernel=grid,taps=25", "", "taps=64,radius=8"},
          .isReference = false,
          .make = [] { return std::make_unique<Pcf>(); }};
}

}  // namespace penumbra::shadows
