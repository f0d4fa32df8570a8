#include "shadows/pcss.h"

#include <chrono>
#include <vector>

#include "shadows/kernel_taps.h"
#include "shadows/sampling.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

std::vector<glm::vec2> squarePattern(int n) {
  std::vector<glm::vec2> pts;
  for (int i = 0; i < n; ++i) pts.push_back(hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n)));
  return pts;
}

class Pcss final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const auto t0 = Clock::now();
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    blocker_ = TapPattern(squarePattern(params.integer("blocker_samples")));
    filter_ = TapPattern(squarePattern(params.integer("filter_samples")));
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    ctx.times.msMaps += msSince(t0);
    const auto t1 = Clock::now();
    minMax_ = params.choice("minmax") == "on";
    if (minMax_) ctx.raster.run([&] { pyramid_ = raster::buildMinMaxPyramid(map_.depth.image()); });
    ctx.times.msFilter += msSince(t1);
    ctx.notes.push_back("pcss: 1 depth map " + std::to_string(size) + "^2, " + std::to_string(blocker_.count) +
                        " blocker + " + std::to_string(filter_.count) + " filter samples");
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    const LightView& view = map_.view;
    const glm::vec2 halfLight(0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height);
    const float znear = view.znear;
    const TapMap taps = map_.tapMap();
    const int64_t simd = ctx.raster.config().simd.taps;
    SkipCounter skipped, filterSkipped;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverPlane plane(view, lookupPoint(view, r, bias_), r.normal, bias_);
      const TapPlane tapPlane = plane.tapPlane();
      const float dr = plane.depth();
      // Taps at the pattern points in [0,1)^2, shifted by this (wrapped), over half-extents around the
      // receiver (kernel_taps.h).
      const glm::vec2 shift(unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10cu)),
                            unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10du)));
      // 1. Blocker search (none possible when the whole search box passes: V = 1 without taps).
      const glm::vec2 search = halfLight * std::max(1.0f / znear - 1.0f / dr, 0.0f);
      if (minMax_ && testBox(map_, pyramid_, plane, plane.tanX() - search.x, plane.tanY() - search.y,
                             plane.tanX() + search.x, plane.tanY() + search.y) == BoxTest::AllLit) {
        skipped.add();
        return 1.0f;
      }
      const BlockerSum blockers = searchBlockers(taps, tapPlane, blocker_.x.data(), blocker_.y.data(), blocker_.count,
                                                 shift.x, shift.y, plane.tanX(), plane.tanY(), search.x, search.y,
                                                 znear, simd);
      if (blockers.count == 0) return 1.0f;
      // 2. Penumbra estimate from the average blocker depth.
      const float db = static_cast<float>(blockers.sum / blockers.count);
      const glm::vec2 filter = halfLight * std::max(1.0f / db - 1.0f / dr, 0.0f);
      // 3. PCF over the penumbra (known without taps when the box is uniformly lit or blocked).
      const BoxTest box = minMax_ ? testBox(map_, pyramid_, plane, plane.tanX() - filter.x, plane.tanY() - filter.y,
                                            plane.tanX() + filter.x, plane.tanY() + filter.y)
                                  : BoxTest::Mixed;
      if (box != BoxTest::Mixed) {
        filterSkipped.add();
        return box == BoxTest::AllLit ? 1.0f : 0.0f;
      }
      const int lit = countLitTaps(taps, tapPlane, filter_.x.data(), filter_.y.data(), filter_.count, shift.x, shift.y,
                                   plane.tanX(), plane.tanY(), filter.x, filter.y, simd);
      return static_cast<float>(lit) / static_cast<float>(filter_.count);
    });
    ctx.times.msEvaluate += msSince(t0);
    if (minMax_)
      ctx.notes.push_back("pcss: min/max test: " + std::to_string(skipped.total()) +
                          " receivers lit without a blocker search, " + std::to_string(filterSkipped.total()) +
                          " resolved without filter taps");
  }

 private:
  ShadowMap map_;
  BiasParams bias_;
  TapPattern blocker_, filter_;
  raster::MinMaxPyramid pyramid_;
  bool minMax_ = true;
};

}  // namespace

TechniqueInfo pcssTechnique() {
  std::vector<ParamSpec> p = depthMapParams(1024);  // its taps are not at texel centres: the slope bias stays (docs/techniques/pcss.md)
  p.push_back({.name = "blocker_samples", .kind = ParamKind::Int, .defaultValue = 64, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth lookups of the blocker search"});
  p.push_back({.name = "filter_samples", .kind = ParamKind::Int, .defaultValue = 128, .minValue = 1,
               .maxValue = 4096, .choices = {}, .help = "depth comparisons of the filtering step"});
  p.push_back(minMaxParam());
  return {.name = "pcss",
          .summary = "percentage-closer soft shadows: blocker search, penumbra estimate, PCF over the penumbra",
          .params = std::move(p),
          .benchSettings = {"blocker_samples=16,filter_samples=32", "", "blocker_samples=256,filter_samples=512"},
          .isReference = false,
          .make = [] { return std::make_unique<Pcss>(); }};
}

}  // namespace penumbra::shadows
