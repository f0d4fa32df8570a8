#include "shadows/light_samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>

#include "shadows/sampling.h"

namespace penumbra::shadows {

std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n) {
  std::vector<glm::vec2> pts;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 h = hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n));
    pts.emplace_back((h.x - 0.5f) * light.width, (h.y - 0.5f) * light.height);
  }
  return pts;
}

LightSampleSet interleavedLightSamples(const RectLight& light, int n, int k) {
  LightSampleSet set;
  set.k = std::max(k, 1);
  while (set.k > 1 && set.k * set.k > n) --set.k;  // every subset holds at least one point
  const int subsets = set.k * set.k;
  set.count.assign(static_cast<size_t>(subsets), 0);
  if (set.k == 1) {
    set.points = lightSamplePoints(light, n);
    set.subset.assign(set.points.size(), 0);
    set.count[0] = n;
    return set;
  }
  for (int s = 0; s < subsets; ++s) {
    const int m = n / subsets + (s < n % subsets ? 1 : 0);
    const glm::vec2 shift((static_cast<float>(s) + 0.5f) / static_cast<float>(subsets),
                          radicalInverse2(static_cast<uint32_t>(s)));
    for (int i = 0; i < m; ++i) {
      glm::vec2 h = hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(m)) + shift;
      h -= glm::floor(h);
      set.points.emplace_back((h.x - 0.5f) * light.width, (h.y - 0.5f) * light.height);
      set.subset.push_back(s);
    }
    set.count[static_cast<size_t>(s)] = m;
  }
  return set;
}

ParamSpec interleaveParam() {
  return {.name = "interleave", .kind = ParamKind::Int, .defaultValue = 1, .minValue = 1, .maxValue = 4, .choices = {},
          .help = "k: pixels in each k x k block use disjoint subsets of the views (noise instead of stacked edge "
                  "copies in wide penumbrae); 1 = off"};
}

void LightSampleTests::prepare(ShadowContext& ctx, BiasParams bias, int interleave) {
  interleave_ = std::max(interleave, 1);
  const ReceiverImage& rec = *ctx.in.receivers;
  const RectLight& light = ctx.in.light;
  width_ = rec.width();
  height_ = rec.height();
  normalOffset_ = bias.normal;
  prep_.assign(static_cast<size_t>(width_) * static_cast<size_t>(height_), Prepared{});
  counts_.resize(width_, height_, 0);
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height_, 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < width_; ++x) {
          const Receiver& r = rec.at(x, y);
          Prepared& p = prep_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)];
          const glm::vec3 v = toLightSpace(light, r.position);
          p = {v.x, v.y, v.z, 0.0f, 0.0f,
               {glm::dot(r.normal, light.right), glm::dot(r.normal, light.up), glm::dot(r.normal, light.normal())}};
          if (!r.valid || !(v.z > 0.0f)) {
            p.d = -1.0f;  // nothing to test
            continue;
          }
          p.invD = 1.0f / v.z;
          const float c = std::abs(glm::dot(p.n, v)) / glm::length(v);
          const float tanTheta = std::min(std::sqrt(std::max(1.0f - c * c, 0.0f)) / std::max(c, 1e-6f), 10.0f);
          p.bias = bias.constant + bias.slope * tanTheta;
        }
    });
  });
}

void LightSampleTests::accumulate(ShadowContext& ctx, const ShadowMap& map, glm::vec2 lp,
                                  std::span<const glm::vec2> taps, int subset) {
  // With interleaving, the pixels of `subset`: columns x0, x0 + k, ... of the rows y = y0 (mod k).
  const int k = subset < 0 ? 1 : interleave_;
  const int x0 = subset < 0 ? 0 : subset % k, y0 = subset < 0 ? 0 : subset / k;
  // Receiver at light-space (x, y, d), view origin (lx, ly, 0): view-space (x - lx, y - ly, d).
  const float texel = map.view.texelWorld(1.0f), znear = map.view.znear, offset = normalOffset_ * texel;
  const glm::vec2 texelTan((map.view.tanHi.x - map.view.tanLo.x) / static_cast<float>(map.view.width),
                           (map.view.tanHi.y - map.view.tanLo.y) / static_cast<float>(map.view.height));
  const TexelCentres centres(map.tapMap());
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height_, 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y) {
        if (y % k != y0) continue;
        const Prepared* row = &prep_[static_cast<size_t>(y) * static_cast<size_t>(width_)];
        uint16_t* out = &counts_.at(0, y);
        for (int x = x0; x < width_; x += k) {
          const Prepared& p = row[x];
          if (!(p.d > 0.0f)) continue;
          float vx = p.x - lp.x, vy = p.y - lp.y, vz = p.d;
          if (!(-(p.n.x * vx + p.n.y * vy + p.n.z * vz) > 0.0f)) continue;  // below the horizon
          // The lookup point, moved along the normal by normalOffset_ texel footprints (shadow_map.h).
          if (offset != 0.0f) {
            const float o = offset * p.d;
            vx += p.n.x * o, vy += p.n.y * o, vz += p.n.z * o;
          }
          const float invD = offset != 0.0f ? 1.0f / vz : p.invD;
          // Receiver-plane depth at the texel's centre (shadow_map.h, receiverPlaneThreshold): what the
          // receiver's own surface stored there, whatever its slope; the bias then only covers
          // curvature and rounding.
          const float invK = 1.0f / (p.n.x * vx + p.n.y * vy + p.n.z * vz);
          const float beta = texel * p.bias;
          const float scale = beta < 1.0f ? znear / (1.0f - beta) : INFINITY;
          const float tx = vx * invD, ty = vy * invD;
          int lit = 0;
          for (const glm::vec2& o : taps) {
            const float qx = tx + o.x * texelTan.x, qy = ty + o.y * texelTan.y;
            lit += centres.m.stored(qx, qy) <= scale * centres.plane(qx, qy, p.n, invK, invD) ? 1 : 0;
          }
          out[x] = static_cast<uint16_t>(out[x] + lit);
        }
      }
    });
  });
}

void LightSampleTests::finish(ShadowContext& ctx, int taps, const LightSampleSet& samples,
                              raster::ImageFloat& visibility) const {
  const int k = samples.k;
  forEachReceiver(
      ctx, visibility,
      [&](int x, int y, const Receiver&) {
        const int n = samples.count[static_cast<size_t>(x % k + k * (y % k))] * taps;
        return n > 0 ? static_cast<float>(counts_.at(x, y)) / static_cast<float>(n) : 1.0f;
      },
      SelfShadow::Handled);
}

}  // namespace penumbra::shadows
