#include "shadows/pcss.h"

#include <chrono>
#include <vector>

#include "shadows/sampling.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

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
    blocker_ = squarePattern(params.integer("blocker_samples"));
    filter_ = squarePattern(params.integer("filter_samples"));
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    ctx.times.msMaps += msSince(t0);
    const auto t1 = Clock::now();
    minMax_ = params.choice("minmax") == "on";
    if (minMax_) ctx.raster.run([&] { pyramid_ = raster::buildMinMaxPyramid(map_.depth.image()); });
    ctx.times.msFilter += msSince(t1);
    ctx.notes.push_back("pcss: 1 depth map " + std::to_string(size) + "^2, " + std::to_string(blocker_.size()) +
                        " blocker + " + std::to_string(filter_.size()) + " filter samples");
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    const LightView& view = map_.view;
    const glm::vec2 halfLight(0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height);
    const float znear = view.znear;
    SkipCounter skipped, filterSkipped;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverPlane plane(view, view.toView(r.position), r.normal, bias_);
      const float dr = plane.depth();
      const glm::vec2 shift(unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10cu)),
                            unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xb10du)));
      // A tap at pattern point p in [0,1)^2 (shifted, wrapped) over half-extents h around the receiver.
      auto tap = [&](glm::vec2 p, glm::vec2 h, float& tx, float& ty) {
        p += shift;
        p -= glm::floor(p);
        tx = plane.tanX() + (2.0f * p.x - 1.0f) * h.x;
        ty = plane.tanY() + (2.0f * p.y - 1.0f) * h.y;
      };
      // 1. Blocker search (none possible when the whole search box passes: V = 1 without taps).
      const glm::vec2 search = halfLight * std::max(1.0f / znear - 1.0f / dr, 0.0f);
      if (minMax_ && testBox(map_, pyramid_, plane, plane.tanX() - search.x, plane.tanY() - search.y,
                             plane.tanX() + search.x, plane.tanY() + search.y) == BoxTest::AllLit) {
        skipped.add();
        return 1.0f;
      }
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
      // 2. Penumbra estimate from the average blocker depth.
      const float db = static_cast<float>(sum / blockers);
      const glm::vec2 filter = halfLight * std::max(1.0f / db - 1.0f / dr, 0.0f);
      // 3. PCF over the penumbra (known without taps when the box is uniformly lit or blocked).
      const BoxTest box = minMax_ ? testBox(map_, pyramid_, plane, plane.tanX() - filter.x, plane.tanY() - filter.y,
                                            plane.tanX() + filter.x, plane.tanY() + filter.y)
                                  : BoxTest::Mixed;
      if (box != BoxTest::Mixed) {
        filterSkipped.add();
        return box == BoxTest::AllLit ? 1.0f : 0.0f;
      }
      int lit = 0;
      for (const glm::vec2& p : filter_) {
        float tx, ty;
        tap(p, filter, tx, ty);
        lit += map_.stored(tx, ty) <= plane.threshold(tx, ty) ? 1 : 0;
      }
      return static_cast<float>(lit) / static_cast<float>(filter_.size());
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
  std::vector<glm::vec2> blocker_, filter_;
  raster::MinMaxPyramid pyramid_;
  bool minMax_ = true;
};

}  // namespace

TechniqueInfo pcssTechnique() {
  std::vector<ParamSpec> p = depthMapParams(1024);
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
