#include "shadows/hard.h"

#include <chrono>

#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

class Hard final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const auto t0 = Clock::now();
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    map_.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
    renderDepthMap(ctx, map_);
    ctx.times.msMaps += msSince(t0);
    ctx.notes.push_back("hard: 1 depth map " + std::to_string(size) + "^2 from the light centre");
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
      // The point-light limit: lit when the light's centre is above the receiver's tangent plane
      // and no caster is in front of it.
      if (!(glm::dot(r.normal, map_.view.origin - r.position) > 0.0f)) return 0.0f;
      const glm::vec3 v = lookupPoint(map_.view, r, bias_);
      const ReceiverPlane plane(map_.view, v, r.normal, bias_);
      const float tx = plane.tanX(), ty = plane.tanY();
      return map_.stored(tx, ty) <= plane.texelCentreThreshold(map_.tapMap(), tx, ty) ? 1.0f : 0.0f;
    }, SelfShadow::Handled);
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  ShadowMap map_;
  BiasParams bias_;
};

}  // namespace

TechniqueInfo hardTechnique() {
  return {.name = "hard",
          .summary = "one shadow map from the light centre, slope-scaled bias: hard shadows (V is 0 or 1)",
          .params = depthMapParams(1024),
          .benchSettings = {"", "map_size=2048"},
          .isReference = false,
          .make = [] { return std::make_unique<Hard>(); }};
}

}  // namespace penumbra::shadows
