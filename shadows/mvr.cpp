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
    samples_ = lightSamples(ctx.in.light, params.integer("views"), params.integer("interleave"), params.choice("samples"));
    taps_ = params.choice("pcf") == "5" ? 5 : 1;
    fitCasters_ = params.choice("fit") == "casters";
    draws_ = casterDraws(ctx.casterGeometry(), casterCull(params));
    ctx.notes.push_back("mvr: " + std::to_string(samples_.points.size()) + " depth maps " + std::to_string(size_) +
                        "^2 from " + params.choice("samples") + " light points, rendered and looked up one at a time, " +
                        std::to_string(taps_) + (taps_ == 1 ? " tap" : " taps") + " per map" +
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
    const std::span<const glm::vec2> taps(kPcfTaps, static_cast<size_t>(taps_));
    for (size_t i = 0; i < samples_.points.size(); ++i) {
      const glm::vec2 lp = samples_.points[i];
      const auto t1 = Clock::now();
      map.view = makeLightView(ctx.in.light, ctx.region, lp, znear, size_, size_, glm::vec2(0.0f),
                               fitCasters_ ? &ctx.casters : nullptr);
      renderDepthMap(ctx, map, draws_);
      ctx.times.msMaps += msSince(t1);
      const auto t2 = Clock::now();
      tests.accumulate(ctx, map, lp, taps, samples_.k > 1 ? samples_.subset[i] : -1);
      ctx.times.msEvaluate += msSince(t2);
    }
    const auto t3 = Clock::now();
    tests.finish(ctx, taps_, samples_, visibility);
    ctx.times.msEvaluate += msSince(t3);
  }

 private:
  BiasParams bias_;
  int size_ = 0, taps_ = 1;
  bool fitCasters_ = true;
  std::vector<CasterDraw> draws_;
  LightSampleSet samples_;
};

}  // namespace

TechniqueInfo mvrTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512, 0.2, 0.2);  // depth at the texel centre: little bias (docs/techniques/mvr.md)
  p.push_back({.name = "views", .kind = ParamKind::Int, .defaultValue = 64, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth maps, from stratified points on the light"});
  p.push_back(interleaveParam());
  p.push_back(samplePatternParam());
  p.push_back(choiceParam("pcf", 0, {"1", "5"},
                          "taps per map: the texel, or the texel and its 4 neighbours (the VWSS paper's MVR)"));
  p.push_back(casterCullParam(2));  // closed meshes' back faces: the same maps, fewer triangles drawn
  p.push_back(mapFitParam(1));      // cut to the casters (docs/techniques/mvr.md)
  return {.name = "mvr",
          .summary =
              "multi-view rasterization: N depth maps from stratified light points, averaged (the accurate "
              "baseline)",
          .params = std::move(p),
          // The last four: fitted to the receivers as vwss's maps are, at the maps counts the VWSS
          // comparison uses, alone and as the VWSS paper's MVR (5-tap PCF, Poisson-disk samples).
          .benchSettings = {"views=8", "views=24", "", "views=128", "views=256", "views=24,fit=receivers",
                            "views=128,fit=receivers", "views=24,pcf=5,samples=poisson,fit=receivers",
                            "views=128,pcf=5,samples=poisson,fit=receivers"},
          .isReference = false,
          .make = [] { return std::make_unique<Mvr>(); }};
}

}  // namespace penumbra::shadows
