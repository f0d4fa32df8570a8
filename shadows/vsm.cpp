#include "shadows/vsm.h"

#include <chrono>

#include "shadows/moments.h"

namespace penumbra::shadows {

namespace {

class Vsm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    minVariance_ = params.number("min_variance");
    bleedReduction_ = params.number("bleed_reduction");
    prepareMomentMap(ctx, params, MomentWarp{.kind = MomentKind::Vsm, .cPos = 0.0f, .cNeg = 0.0f}, map_);
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
      const glm::vec3 v = lookupPoint(map_.view, r, bias_);
      const MomentSample s = map_.sample(map_.view.toMap(v));
      const double t = receiverDepth(map_, v, r.normal, bias_);
      const double p = chebyshevUpperBound(s.m[0], s.m[1], t, minVariance_);
      return static_cast<float>(reduceLightBleeding(p, bleedReduction_));
    });
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  MomentMap map_;
  BiasParams bias_;
  double minVariance_ = 0, bleedReduction_ = 0;
};

}  // namespace

TechniqueInfo vsmTechnique() {
  std::vector<ParamSpec> params = momentMapParams();
  for (ParamSpec& p : chebyshevParams(1e-5)) params.push_back(std::move(p));
  return {.name = "vsm",
          .summary = "variance shadow map: Gaussian-filtered (z, z^2), Chebyshev bound; fixed penumbra width",
          .params = std::move(params),
          .benchSettings = {"", "filter_sigma=4"},
          .isReference = false,
          .make = [] { return std::make_unique<Vsm>(); }};
}

}  // namespace penumbra::shadows
