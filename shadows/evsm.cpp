#include "shadows/evsm.h"

#include <chrono>
#include <cmath>

#include "shadows/moments.h"

namespace penumbra::shadows {

namespace {

// 2 c <= 84 < ln(FLT_MAX) = 88.72 (evsm.h).
constexpr double kMaxExponent = 42.0;

class Evsm final : public Technique {
 public:
  explicit Evsm(bool four) : four_(four) {}

  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    minVariance_ = params.number("min_variance");
    bleedReduction_ = params.number("bleed_reduction");
    MomentWarp warp{.kind = four_ ? MomentKind::Evsm4 : MomentKind::Evsm2,
                    .cPos = static_cast<float>(params.number("exponent_pos")),
                    .cNeg = four_ ? static_cast<float>(params.number("exponent_neg")) : 0.0f};
    prepareMomentMap(ctx, params, warp, map_);
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
      const glm::vec3 v = lookupPoint(map_.view, r, bias_);
      const MomentSample s = map_.sample(map_.view.toMap(v));
      const double p =
          evsmBound(s, map_.warp, static_cast<double>(receiverDepth(map_, v, r.normal, bias_)), minVariance_);
      return static_cast<float>(reduceLightBleeding(p, bleedReduction_));
    });
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  bool four_;
  MomentMap map_;
  BiasParams bias_;
  double minVariance_ = 0, bleedReduction_ = 0;
};

std::vector<ParamSpec> evsmParams(bool four) {
  std::vector<ParamSpec> params = momentMapParams();
  params.push_back(
      {.name = "exponent_pos",
       .kind = ParamKind::Float,
       .defaultValue = 40,
       .minValue = 0,
       .maxValue = kMaxExponent,
       .choices = {},
       .help = "c+ of the positive warp exp(c+ z), z = normalized depth; <= 42 keeps exp(2 c+) below "
               "FLT_MAX"});
  if (four)
    params.push_back({.name = "exponent_neg",
                      .kind = ParamKind::Float,
                      .defaultValue = 5,
                      .minValue = 0,
                      .maxValue = kMaxExponent,
                      .choices = {},
                      .help = "c- of the negative warp -exp(-c- z), z = normalized depth"});
  for (ParamSpec& p : chebyshevParams(1e-7)) params.push_back(std::move(p));
  return params;
}

}  // namespace

TechniqueInfo evsm2Technique() {
  return {
      .name = "evsm2",
      .summary = "exponential variance shadow map, 2 moments (exp(c z), its square); fixed penumbra width",
      .params = evsmParams(false),
      .benchSettings = {"", "filter_sigma=4"},
      .isReference = false,
      .make = [] { return std::make_unique<Evsm>(false); }};
}

TechniqueInfo evsm4Technique() {
  return {
      .name = "evsm4",
      .summary =
          "exponential variance shadow map, 4 moments (positive and negative warps); fixed penumbra width",
      .params = evsmParams(true),
      .benchSettings = {"", "filter_sigma=4", "exponent_pos=20,exponent_neg=10"},
      .isReference = false,
      .make = [] { return std::make_unique<Evsm>(true); }};
}

}  // namespace penumbra::shadows
