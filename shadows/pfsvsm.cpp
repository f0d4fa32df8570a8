#include "shadows/pfsvsm.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "shadows/prefiltered.h"
#include "shadows/sampling.h"

namespace penumbra::shadows {

namespace {

// A Poisson-disk set of n points in the unit disk by best candidate (Mitchell 1991): each new
// point is the one of 8 n candidates farthest from those already placed. Deterministic (hash3);
// minDistance is the set's smallest pairwise distance.
std::vector<glm::dvec2> poissonDisk(int n, double& minDistance) {
  std::vector<glm::dvec2> pts;
  for (int i = 0; i < n; ++i) {
    glm::dvec2 best(0.0);
    double bestD = -1.0;
    for (int c = 0; c < 8 * n; ++c) {
      const double r = std::sqrt(
          static_cast<double>(unitFloat(hash3(static_cast<uint32_t>(i), static_cast<uint32_t>(c), 0x9015u))));
      const double a =
          6.283185307179586 *
          static_cast<double>(unitFloat(hash3(static_cast<uint32_t>(i), static_cast<uint32_t>(c), 0x9016u)));
      const glm::dvec2 p(r * std::cos(a), r * std::sin(a));
      double d = 1e30;
      for (const glm::dvec2& q : pts) d = std::min(d, glm::length(p - q));
      if (d > bestD) bestD = d, best = p;
    }
    pts.push_back(best);
  }
  minDistance = 2.0;
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t j = i + 1; j < pts.size(); ++j)
      minDistance = std::min(minDistance, glm::length(pts[i] - pts[j]));
  return pts;
}

class Pfsvsm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    usePlane_ = params.choice("receiver_plane") == "on";
    minVariance_ = params.number("min_variance");
    bleed_ = params.number("bleed_reduction");
    pcf_ = params.choice("test") == "pcf";
    disk_ = poissonDisk(params.integer("taps"), minDistance_);
    preparePrefilterMap(ctx, params, m_, {.moments = true, .pyramid = false});
    const auto t0 = Clock::now();
    ctx.raster.run([&] { mips_ = raster::mipChain4(m_.map.texels); });
    ctx.times.msFilter += msSince(t0);
    char buf[200];
    std::snprintf(
        buf, sizeof buf,
        "pfsvsm: map %d^2, %zu mip levels of (z, z^2), %zu Poisson taps (min distance %.3f), %s test",
        m_.z.width(), mips_.size(), disk_.size(), minDistance_, pcf_ ? "PCF" : "Chebyshev");
    ctx.notes.push_back(buf);
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverKernel k = receiverKernel(m_, ctx, r, bias_, usePlane_);
      // 1. Blocker search: one fetch over the search box.
      const double searchLevel = std::log2(std::max(2.0 * std::max(k.sx, k.sy), 1.0));
      const std::array<double, 4> s = raster::sampleTrilinear(mips_, k.cx, k.cy, searchLevel);
      const double p = chebyshevUpperBound(s[0], s[1], k.zr, minVariance_);
      if (p > 0.99) return 1.0f;
      const double zOcc = std::clamp((s[0] - p * k.zr) / (1.0 - p), 0.0, k.zr);
      // 2. Penumbra; 3. the rotated Poisson taps over it.
      const glm::dvec2 h = penumbraHalf(m_, ctx, k, zOcc);
      const double level = std::log2(std::max(minDistance_ * std::max(h.x, h.y), 1.0));
      const double a =
          6.283185307179586 *
          static_cast<double>(unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0x9017u)));
      const double ca = std::cos(a), sa = std::sin(a);
      double m1 = 0, m2 = 0;
      int lit = 0;
      for (const glm::dvec2& d : disk_) {
        const double tx = k.cx + (ca * d.x - sa * d.y) * h.x, ty = k.cy + (sa * d.x + ca * d.y) * h.y;
        if (pcf_) {
          if (static_cast<double>(m_.zAt(tx, ty)) >= k.zrAt(tx, ty)) ++lit;
          continue;
        }
        const std::array<double, 4> t = raster::sampleTrilinear(mips_, tx, ty, level);
        m1 += t[0], m2 += t[1];
      }
      const double n = static_cast<double>(disk_.size());
      const double v =
          pcf_ ? lit / n
               : reduceLightBleeding(chebyshevUpperBound(m1 / n, m2 / n, k.zr, minVariance_), bleed_);
      return v < 0x1p-24 ? 0.0f : static_cast<float>(std::min(v, 1.0));
    });
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  PrefilterMap m_;
  BiasParams bias_;
  bool usePlane_ = true, pcf_ = false;
  double minVariance_ = 1e-6, bleed_ = 0, minDistance_ = 1;
  std::vector<glm::dvec2> disk_;
  std::vector<raster::ImageFloat4> mips_;
};

}  // namespace

TechniqueInfo pfsvsmTechnique() {
  std::vector<ParamSpec> p = prefilterParams(1);
  std::erase_if(p, [](const ParamSpec& s) { return s.name == "subdivision"; });
  for (ParamSpec& c : chebyshevParams(1e-6)) p.push_back(std::move(c));
  p.push_back({.name = "taps",
               .kind = ParamKind::Int,
               .defaultValue = 16,
               .minValue = 1,
               .maxValue = 256,
               .choices = {},
               .help = "Poisson-disk taps of the post-filter"});
  p.push_back(
      {.name = "test",
       .kind = ParamKind::Choice,
       .defaultValue = 0,
       .minValue = 0,
       .maxValue = 1,
       .choices = {"chebyshev", "pcf"},
       .help =
           "the post-filter's test: mip moments and one Chebyshev bound, or PCF taps (the blog's hybrid)"});
  return {
      .name = "pfsvsm",
      .summary =
          "post-filtered soft VSM: mip-chain blocker search, Poisson taps at their footprint's mip level, "
          "one Chebyshev bound",
      .params = std::move(p),
      .benchSettings = {"", "taps=32", "test=pcf", "test=pcf,taps=64"},
      .isReference = false,
      .make = [] { return std::make_unique<Pfsvsm>(); },
      .peakBytes =
          [](const ParamSet& ps, uint64_t) {
            const uint64_t n = static_cast<uint64_t>(ps.integer("map_size"));
            return n * n * 43;  // moments 16 + their mips ~5.3, z 4
          }};
}

}  // namespace penumbra::shadows
