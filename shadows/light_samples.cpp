#include "shadows/light_samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

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

void LightSampleTests::prepare(ShadowContext& ctx, BiasParams bias) {
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
                                  std::span<const glm::vec2> taps) {
  // Receiver at light-space (x, y, d), view origin (lx, ly, 0): view-space (x - lx, y - ly, d).
  const float texel = map.view.texelWorld(1.0f), znear = map.view.znear, offset = normalOffset_ * texel;
  const glm::vec2 texelTan((map.view.tanHi.x - map.view.tanLo.x) / static_cast<float>(map.view.width),
                           (map.view.tanHi.y - map.view.tanLo.y) / static_cast<float>(map.view.height));
  const TapMap m = map.tapMap();
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height_, 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y) {
        const Prepared* row = &prep_[static_cast<size_t>(y) * static_cast<size_t>(width_)];
        uint16_t* out = &counts_.at(0, y);
        for (int x = 0; x < width_; ++x) {
          const Prepared& p = row[x];
          if (!(p.d > 0.0f)) continue;
          float vx = p.x - lp.x, vy = p.y - lp.y, vz = p.d;
          if (!(-(p.n.x * vx + p.n.y * vy + p.n.z * vz) > 0.0f)) continue;  // below the horizon
          // The lookup point, moved along the normal by normalOffset_ texel footprints (shadow_map.h).
          if (offset != 0.0f) {
            const float o = offset * p.d;
            vx += p.n.x * o, vy += p.n.y * o, vz += p.n.z * o;
          }
          const float invD = 1.0f / vz;
          // Receiver-plane depth at the texel's centre (shadow_map.h, receiverPlaneThreshold): what the
          // receiver's own surface stored there, whatever its slope; the bias then only covers
          // curvature and rounding.
          const float k = p.n.x * vx + p.n.y * vy + p.n.z * vz;
          const float beta = texel * p.bias;
          const float scale = beta < 1.0f ? znear / (1.0f - beta) : INFINITY;
          const float tx = vx * invD, ty = vy * invD;
          int lit = 0;
          for (const glm::vec2& o : taps) {
            const float qx = tx + o.x * texelTan.x, qy = ty + o.y * texelTan.y;
            lit += m.stored(qx, qy) <= scale * texelCentrePlane(m, qx, qy, p.n, k, invD) ? 1 : 0;
          }
          out[x] = static_cast<uint16_t>(out[x] + lit);
        }
      }
    });
  });
}

void LightSampleTests::finish(ShadowContext& ctx, int total, raster::ImageFloat& visibility) const {
  const float n = static_cast<float>(total);
  forEachReceiver(
      ctx, visibility, [&](int x, int y, const Receiver&) { return static_cast<float>(counts_.at(x, y)) / n; },
      SelfShadow::Handled);
}

}  // namespace penumbra::shadows
