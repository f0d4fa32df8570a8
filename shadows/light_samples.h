// Shared by the techniques that sample the light with views (MVR, VWSS): the stratified light
// points, and the per-receiver depth tests against one light sample's depth map.
//
// Per receiver, computed once: its light-space position (x, y, d), 1/d, its normal in light space
// and the bias factor bias + slope_bias * tan(theta) for the ray from the light's centre (views'
// origins lie on the light, so theta hardly changes between them). Per map, a tap is then a few
// multiplications, one division and one load: lit when the light sample is above the receiver's
// tangent plane (its own closed surface hides the rest) and the stored value passes
// near / (d (1 - beta)), beta = the map's texel footprint per unit depth times the bias factor.
// Thread-safety: one object per technique run; accumulate() runs rows in parallel in the
// context's arena, each receiver's count written by one task.
#pragma once

#include <glm/vec2.hpp>
#include <span>
#include <vector>

#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

// Light-space points (world units from the centre along right and up) of n stratified samples:
// a Hammersley set over the rectangle. MVR and VWSS use the same points.
std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n);

// Interleaved light samples (Keller & Heidrich 2001, interleaved sampling): the n points split
// into k x k subsets, each a Hammersley set of its own (n / k^2 points, the first n % k^2 subsets
// one more) under a Cranley-Patterson shift ((s + 0.5) / k^2, radicalInverse2(s)), wrapped on the
// light; pixel (x, y) uses subset (x mod k) + k (y mod k) only. The N maps then sit at N distinct
// light points across every k x k block, and a wide penumbra shows fine noise instead of N
// stacked copies of the occluder's edge (at k^2 times fewer samples per pixel). k = 1: exactly
// lightSamplePoints, one subset; k is lowered until k^2 <= n (every subset holds a point).
struct LightSampleSet {
  std::vector<glm::vec2> points;
  std::vector<int> subset;  // per point
  std::vector<int> count;   // points per subset (k * k)
  int k = 1;
};
LightSampleSet interleavedLightSamples(const RectLight& light, int n, int k);
// The "interleave" parameter of MVR and VWSS (k, 1 = off).
ParamSpec interleaveParam();

class LightSampleTests {
 public:
  void prepare(ShadowContext& ctx, BiasParams bias, int interleave = 1);
  // counts(x, y) += the taps (offsets in texels of `map`) that pass, for the light sample at
  // light-space point lightPoint whose depth map is `map`; with interleaving, only at the pixels
  // of `subset` (-1: every pixel).
  void accumulate(ShadowContext& ctx, const ShadowMap& map, glm::vec2 lightPoint, std::span<const glm::vec2> taps,
                  int subset = -1);
  // V = counts / (taps * points of the pixel's subset) (exactly 1 when every tap passed);
  // background 1, behind the light 0.
  void finish(ShadowContext& ctx, int taps, const LightSampleSet& samples, raster::ImageFloat& visibility) const;

 private:
  struct Prepared {
    float x, y, d, invD, bias;
    glm::vec3 n;
  };
  float normalOffset_ = 0.0f;  // texels (BiasParams::normal)
  int interleave_ = 1;
  int width_ = 0, height_ = 0;
  std::vector<Prepared> prep_;
  raster::Image<uint16_t> counts_;
};

}  // namespace penumbra::shadows
