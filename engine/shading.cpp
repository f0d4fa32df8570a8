#include "engine/shading.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "engine/gbuffer_pass.h"
#include "engine/texture.h"
#include "raster/timing.h"
#include "shadows/area_light.h"

namespace penumbra::engine {

namespace {

// KHR_lights_punctual's recommended window: 1 inside, smoothly 0 at distance `range` (0: none).
float rangeFalloff(float range, float d2) {
  if (!(range > 0.0f)) return 1.0f;
  const float r = d2 / (range * range);
  const float w = std::clamp(1.0f - r * r, 0.0f, 1.0f);
  return w * w;
}

// The 8-bit value of a linear channel after exposure and the tone map.
uint8_t display(float c, float exposure, ToneMap map) {
  float x = c * exposure;
  if (map == ToneMap::Aces) {
    x = std::max(x, 0.0f);
    x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);  // Narkowicz 2015
  }
  return linearToSrgb(x);
}

// Radiance towards the eye of one G-buffer texel; vy: its row in the visibility images. factors:
// irradianceFactor of area light i at factors[i * stride] (RowFactors), or nullptr to compute it.
glm::vec3 shadeTexel(const Scene& scene, const glm::vec3& eye, const std::vector<raster::ImageFloat>& visibility,
                     const GBufferTexel& g, int x, int vy, const float* factors = nullptr, size_t stride = 0) {
  const Material& mat = gbufferMaterial(scene, g.material);
  const glm::vec3 v = glm::normalize(eye - g.position);
  glm::vec3 c = scene.ambient * g.albedo;
  if (scene.sky) {
    const float up = 0.5f * (1.0f + g.normal.y);
    c = (scene.sky->ground + (scene.sky->sky - scene.sky->ground) * up) * g.albedo;
  }
  auto light = [&](const glm::vec3& l, const glm::vec3& radiance) {
    const float ndl = glm::dot(g.normal, l);
    if (ndl <= 0.0f) return;
    glm::vec3 contrib = g.albedo * ndl;
    if (mat.specular > 0.0f) {
      const glm::vec3 hv = glm::normalize(l + v);
      contrib += glm::vec3(mat.specular * std::pow(std::max(glm::dot(g.normal, hv), 0.0f), mat.shininess) * ndl);
    }
    c += contrib * radiance;
  };
  for (const DirectionalLight& dl : scene.directionalLights) light(-glm::normalize(dl.direction), dl.color * dl.intensity);
  for (const PointLight& pl : scene.pointLights) {
    const glm::vec3 d = pl.position - g.position;
    const float d2 = std::max(glm::dot(d, d), 1e-8f);
    light(d / std::sqrt(d2), pl.color * (pl.intensity * rangeFalloff(pl.range, d2) / d2));
  }
  for (const SpotLight& sl : scene.spotLights) {
    const glm::vec3 d = sl.position - g.position;
    const float d2 = std::max(glm::dot(d, d), 1e-8f);
    const glm::vec3 l = d / std::sqrt(d2);
    // KHR_lights_punctual: smooth between the cones' cosines, squared.
    const float cosOuter = std::cos(sl.outerCone), cosInner = std::cos(sl.innerCone);
    const float t = std::clamp((glm::dot(sl.direction, -l) - cosOuter) / std::max(cosInner - cosOuter, 1e-4f), 0.0f, 1.0f);
    light(l, sl.color * (sl.intensity * t * t * rangeFalloff(sl.range, d2) / d2));
  }
  for (size_t li = 0; li < scene.areaLights.size(); ++li) {
    const shadows::RectLight& al = scene.areaLights[li];
    // Diffuse: rho / pi * E with E = radiance * irradianceFactor (exact, unshadowed), times V.
    const float factor = factors ? factors[li * stride] : shadows::irradianceFactor(al, g.position, g.normal);
    if (factor <= 0.0f) continue;
    const glm::vec3 e = al.color * (al.intensity * factor * visibility[li].at(x, vy));
    c += g.albedo * e * (1.0f / std::numbers::pi_v<float>);
    // Specular: Blinn-Phong towards the light's centre, scaled by the same E.
    const glm::vec3 toLight = glm::normalize(al.center - g.position);
    if (mat.specular > 0.0f && glm::dot(g.normal, toLight) > 0.0f) {
      const glm::vec3 hv = glm::normalize(toLight + v);
      c += e * (mat.specular * std::pow(std::max(glm::dot(g.normal, hv), 0.0f), mat.shininess) /
                std::numbers::pi_v<float>);
    }
  }
  return c;
}

// The area lights' irradianceFactor for every texel of a G-buffer row, in SIMD lanes
// (shadows::irradianceFactors, bit for bit the per-texel function): the row's positions and shading
// normals are copied to coordinate arrays first. Background texels get a value nobody reads.
class RowFactors {
 public:
  const float* compute(const Scene& scene, const raster::Image<GBufferTexel>& gbuffer, int y, int64_t simd) {
    const size_t w = static_cast<size_t>(gbuffer.width());
    buffer_.resize(w * (6 + scene.areaLights.size()));
    float* soa = buffer_.data();
    for (size_t x = 0; x < w; ++x) {
      const GBufferTexel& g = gbuffer.at(static_cast<int>(x), y);
      soa[x] = g.position.x, soa[w + x] = g.position.y, soa[2 * w + x] = g.position.z;
      soa[3 * w + x] = g.normal.x, soa[4 * w + x] = g.normal.y, soa[5 * w + x] = g.normal.z;
    }
    const shadows::SurfacePoints points{soa, soa + w, soa + 2 * w, soa + 3 * w, soa + 4 * w, soa + 5 * w};
    float* out = soa + 6 * w;
    for (size_t li = 0; li < scene.areaLights.size(); ++li)
      shadows::irradianceFactors(scene.areaLights[li], points, static_cast<int>(w), out + li * w, simd);
    return out;
  }

 private:
  std::vector<float> buffer_;
};

}  // namespace

void shadeFrame(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                const std::vector<raster::ImageFloat>& visibility, Frame& frame) {
  const auto t0 = raster::Clock::now();
  const int w = plan.width, h = plan.height;
  const bool layered = frame.spp > 0;
  const bool keepLinear = plan.linearImage;
  raster.run([&] {
    if (keepLinear) frame.linear.resizeParallel(w, h);
    frame.color.resizeParallel(w, h);
  });
  frame.stats.linearImage = keepLinear;
  const glm::vec3 eye = plan.camera.eye;
  const bool plain = plan.exposureScale == 1.0f && plan.toneMap == ToneMap::None;  // the bytes as without them
  raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      RowFactors rowFactors;
      for (int y = rows.begin(); y != rows.end(); ++y) {
        const float* factors = !layered && !scene.areaLights.empty()
                                   ? rowFactors.compute(scene, frame.gbuffer, y, raster.config().simd.shade)
                                   : nullptr;
        for (int x = 0; x < w; ++x) {
          glm::vec3 c = scene.background;
          float alpha = 0.0f;
          if (!layered) {
            const GBufferTexel& g = frame.gbuffer.at(x, y);
            if (g.material >= 0) {
              c = shadeTexel(scene, eye, visibility, g, x, y, factors ? factors + x : nullptr,
                             static_cast<size_t>(frame.gbuffer.width()));
              alpha = 1.0f;
            }
          } else {
            // Box filter: each surface weighted by the share of the pixel's samples it holds.
            const stochastic::ResolvedPixel& rp = frame.resolved.at(x, y);
            if (rp.layers == 1 && rp.layer[0].count == frame.spp && frame.gbuffer.at(x, y).material >= 0) {
              c = shadeTexel(scene, eye, visibility, frame.gbuffer.at(x, y), x, y);  // one surface: exact
              alpha = 1.0f;
            } else if (rp.layers > 0) {
              const float inv = 1.0f / static_cast<float>(frame.spp);
              c = scene.background * (static_cast<float>(rp.background) * inv);
              for (int l = 0; l < rp.layers; ++l) {
                const float wgt = static_cast<float>(rp.layer[l].count) * inv;
                const GBufferTexel& g = frame.layerTexel(l, x, y);
                if (g.material < 0) {
                  c += scene.background * wgt;
                  continue;
                }
                c += shadeTexel(scene, eye, visibility, g, x, y + l * h) * wgt;
                alpha += wgt;
              }
            }
          }
          if (keepLinear) frame.linear.at(x, y) = raster::Float4{c.x, c.y, c.z, alpha};
          if (plain)
            frame.color.at(x, y) = raster::Rgba8{linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z), 255};
          else
            frame.color.at(x, y) = raster::Rgba8{display(c.x, plan.exposureScale, plan.toneMap),
                                                 display(c.y, plan.exposureScale, plan.toneMap),
                                                 display(c.z, plan.exposureScale, plan.toneMap), 255};
        }
      }
    });
  });
  frame.stats.msShade = raster::msSince(t0);
}

}  // namespace penumbra::engine
