#include "shadows/mvr.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>

#include "shadows/sampling.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n) {
  std::vector<glm::vec2> pts;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 h = hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n));
    pts.emplace_back((h.x - 0.5f) * light.width, (h.y - 0.5f) * light.height);
  }
  return pts;
}

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

class Mvr final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    size_ = params.integer("map_size");
    points_ = lightSamplePoints(ctx.in.light, params.integer("views"));
    ctx.notes.push_back("mvr: " + std::to_string(points_.size()) + " depth maps " + std::to_string(size_) +
                        "^2 from stratified light points, rendered and looked up one at a time");
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const ReceiverImage& rec = *ctx.in.receivers;
    const RectLight& light = ctx.in.light;
    const auto t0 = Clock::now();
    // Per receiver, once: light-space position (x, y, d), 1/d, the normal in light space and the
    // bias factor constant + slope * tan(theta) for the ray from the light's centre (the views'
    // origins are within the light, so theta hardly changes between them).
    struct Prepared {
      float x, y, d, invD, bias;
      glm::vec3 n;
    };
    const int w = rec.width(), h = rec.height();
    std::vector<Prepared> prep(static_cast<size_t>(w) * static_cast<size_t>(h));
    raster::Image<uint16_t> lit(w, h, 0);
    ctx.raster.run([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const Receiver& r = rec.at(x, y);
            Prepared& p = prep[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)];
            const glm::vec3 v = toLightSpace(light, r.position);
            p = {v.x, v.y, v.z, 0.0f, 0.0f, {glm::dot(r.normal, light.right), glm::dot(r.normal, light.up),
                                            glm::dot(r.normal, light.normal())}};
            if (!r.valid || !(v.z > 0.0f)) {
              p.d = -1.0f;  // nothing to test
              continue;
            }
            p.invD = 1.0f / v.z;
            const float c = std::abs(glm::dot(p.n, v)) / glm::length(v);
            const float tanTheta = std::min(std::sqrt(std::max(1.0f - c * c, 0.0f)) / std::max(c, 1e-6f), 10.0f);
            p.bias = bias_.constant + bias_.slope * tanTheta;
          }
      });
    });
    ctx.times.msEvaluate += msSince(t0);
    ShadowMap map;
    const float znear = ctx.nearPlane();
    for (const glm::vec2& lp : points_) {
      const auto t1 = Clock::now();
      map.view = makeLightView(light, ctx.region, lp, znear, size_, size_);
      renderDepthMap(ctx, map);
      ctx.times.msMaps += msSince(t1);
      const auto t2 = Clock::now();
      // Receiver at light-space (x, y, d), view origin (lx, ly, 0): view-space (x - lx, y - ly, d).
      // Lit when the origin is above its tangent plane, and the stored value passes
      // near / (d (1 - beta)), beta = texel footprint per unit depth * bias factor (shadow_map.h).
      const float texel = map.view.texelWorld(1.0f);
      ctx.raster.run([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
          for (int y = rows.begin(); y != rows.end(); ++y) {
            const Prepared* row = &prep[static_cast<size_t>(y) * static_cast<size_t>(w)];
            uint16_t* out = &lit.at(0, y);
            for (int x = 0; x < w; ++x) {
              const Prepared& p = row[x];
              if (!(p.d > 0.0f)) continue;
              const float vx = p.x - lp.x, vy = p.y - lp.y;
              if (!(-(p.n.x * vx + p.n.y * vy + p.n.z * p.d) > 0.0f)) continue;  // below the horizon
              const float beta = texel * p.bias;
              const float threshold = beta < 1.0f ? znear * p.invD / (1.0f - beta) : INFINITY;
              out[x] = static_cast<uint16_t>(out[x] + (map.stored(vx * p.invD, vy * p.invD) <= threshold ? 1 : 0));
            }
          }
        });
      });
      ctx.times.msEvaluate += msSince(t2);
    }
    const auto t3 = Clock::now();
    const float n = static_cast<float>(points_.size());  // lit / n: exactly 1 when every view is lit
    forEachReceiver(
        ctx, visibility, [&](int x, int y, const Receiver&) { return static_cast<float>(lit.at(x, y)) / n; },
        SelfShadow::Handled);
    ctx.times.msEvaluate += msSince(t3);
  }

 private:
  BiasParams bias_;
  int size_ = 0;
  std::vector<glm::vec2> points_;
};

}  // namespace

TechniqueInfo mvrTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512);
  p.push_back({.name = "views", .kind = ParamKind::Int, .defaultValue = 64, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth maps, from stratified points on the light"});
  return {.name = "mvr",
          .summary = "multi-view rasterization: N depth maps from stratified light points, averaged (the accurate baseline)",
          .params = std::move(p),
          .benchSettings = {"views=8", "views=32", "", "views=128", "views=256"},
          .isReference = false,
          .make = [] { return std::make_unique<Mvr>(); }};
}

}  // namespace penumbra::shadows
