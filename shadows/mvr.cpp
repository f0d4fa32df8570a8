#include "shadows/mvr.h"

#include <chrono>

#include "shadows/light_samples.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

class Mvr final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    size_ = params.integer("map_size");
    samples_ = interleavedLightSamples(ctx.in.light, params.integer("views"), params.integer("interleave"));
    ctx.notes.push_back("mvr: " + std::to_string(samples_.points.size()) + " depth maps " + std::to_string(size_) +
                        "^2 from stratified light points, rendered and looked up one at a time" +
                        (samples_.k > 1 ? ", interleaved over " + std::to_string(samples_.k) + "x" +
                                              std::to_string(samples_.k) + " pixel blocks"
                                        : std::string()));
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    LightSampleTests tests;
    tests.prepare(ctx, bias_, samples_.k);
    ctx.times.msEvaluate += msSince(t0);
    ShadowMap map;
    const float znear = ctx.nearPlane();
    const glm::vec2 oneTap[1] = {glm::vec2(0.0f)};
    for (size_t i = 0; i < samples_.points.size(); ++i) {
      const glm::vec2 lp = samples_.points[i];
      const auto t1 = Clock::now();
      map.view = makeLightView(ctx.in.light, ctx.region, lp, znear, size_, size_);
      renderDepthMap(ctx, map);
      ctx.times.msMaps += msSince(t1);
      const auto t2 = Clock::now();
      tests.accumulate(ctx, map, lp, oneTap, samples_.k > 1 ? samples_.subset[i] : -1);
      ctx.times.msEvaluate += msSince(t2);
    }
    const auto t3 = Clock::now();
    tests.finish(ctx, 1, samples_, visibility);
    ctx.times.msEvaluate += msSince(t3);
  }

 private:
  BiasParams bias_;
  int size_ = 0;
  LightSampleSet samples_;
};

}  // namespace

TechniqueInfo mvrTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512, 0.2, 0.2);  // depth at the texel centre: little bias (docs/techniques/mvr.md)
  p.push_back({.name = "views", .kind = ParamKind::Int, .defaultValue = 64, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth maps, from stratified points on the light"});
  p.push_back(interleaveParam());
  return {.name = "mvr",
          .summary = "multi-view rasterization: N depth maps from stratified light points, averaged (the accurate baseline)",
          .params = std::move(p),
          .benchSettings = {"views=8", "views=24", "", "views=128", "views=256"},
          .isReference = false,
          .make = [] { return std::make_unique<Mvr>(); }};
}

}  // namespace penumbra::shadows
