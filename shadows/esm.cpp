#include "shadows/esm.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "shadows/moments.h"

namespace penumbra::shadows {

namespace {

// exp(c) for z = 1 must stay below FLT_MAX = e^88.72 (esm.h).
constexpr double kMaxExponent = 88.0;

class Esm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    bleedReduction_ = params.number("bleed_reduction");
    prepareMomentMap(
        ctx, params,
        MomentWarp{
            .kind = MomentKind::Esm, .cPos = static_cast<float>(params.number("exponent")), .cNeg = 0.0f},
        map_);
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    const double c = static_cast<double>(map_.warp.cPos);
    forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
      const glm::vec3 v = lookupPoint(map_.view, r, bias_);
      const MomentSample s = map_.sample(map_.view.toMap(v));
      const double z = receiverDepth(map_, v, r.normal, bias_);
      // The filtered exp(c z_occ) is a mean of values >= 1 (z_occ >= 0); the max only guards log.
      const double logMean = std::log(std::max(s.m[0], std::numeric_limits<double>::min()));
      // exp never reaches 0: values below 2^-24 (under float's resolution at 1, and under any
      // display's) are flushed to 0 so that a full umbra is exactly 0, as for every technique.
      // Light bleeding control (moments.h, reduceLightBleeding): the faint light ESM leaks behind
      // occluders close in depth is cut to 0, the rest rescaled.
      const double vis = reduceLightBleeding(std::clamp(std::exp(logMean - c * z), 0.0, 1.0), bleedReduction_);
      return vis < 0x1p-24 ? 0.0f : static_cast<float>(vis);
    });
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  MomentMap map_;
  BiasParams bias_;
  double bleedReduction_ = 0;
};

}  // namespace

TechniqueInfo esmTechnique() {
  std::vector<ParamSpec> params = momentMapParams();
  params.push_back({.name = "exponent",
                    .kind = ParamKind::Float,
                    .defaultValue = 80,
                    .minValue = 1,
                    .maxValue = kMaxExponent,
                    .choices = {},
                    .help = "c of exp(c z), z = normalized depth; <= 88 keeps exp(c) below FLT_MAX"});
  params.push_back({.name = "bleed_reduction",
                    .kind = ParamKind::Float,
                    .defaultValue = 0.0,
                    .minValue = 0,
                    .maxValue = 0.99,
                    .choices = {},
                    .help = "V below this is cut to 0 and the rest rescaled: less light leaking behind occluders "
                            "close in depth (at contact), darker penumbrae"});
  return {.name = "esm",
          .summary =
              "exponential shadow map: Gaussian-filtered exp(c z), V = E[exp(c z_occ)] exp(-c z_r); fixed "
              "penumbra width",
          .params = std::move(params),
          .benchSettings = {"", "exponent=40", "filter_sigma=4"},
          .isReference = false,
          .make = [] { return std::make_unique<Esm>(); }};
}

}  // namespace penumbra::shadows
