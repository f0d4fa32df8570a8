// Shared building blocks of the pre-filtered moment shadow maps (VSM, EVSM, ESM): a moment map
// rendered from the light centre with the pipeline's full pass (a fragment stage writing moments of
// the depth into a Float4 target), pre-filtered with a Gaussian blur (raster/kernels.h), sampled
// bilinearly, and the Chebyshev bound the variance-based techniques share.
//
// Conventions
// - Depth: the moments are of the normalized linear depth along the light axis,
//       z = (d - zNear) / (zFar - zNear)  in [0, 1] (clamped),
//   d = LightView::toView(p).z, zNear = the view's near plane (ShadowContext::nearPlane), zFar =
//   1.01 * the farthest receiver's depth (LightRegion::hi.z). z grows away from the light. Every
//   texel holds the moments of the nearest caster it sees (depth test DepthFunc::Greater on the
//   reversed depth near / d, as in shadow_map.h); texels that see no caster hold the moments of
//   z = 1 (the far plane: nothing occludes there).
// - Moments per technique (raster::Float4 channels r, g, b, a; unused channels are 0):
//       VSM    (z, z^2)                      Donnelly & Lauritzen 2006
//       EVSM2  (w+, w+^2)                    Lauritzen & McCool 2008, w+ = exp(c+ z)
//       EVSM4  (w+, w+^2, w-, w-^2)          w- = -exp(-c- z)
//       ESM    (exp(c z))                    Annen et al. 2008, Salvi 2008
// - Float32 bound: every stored moment is at most exp(2 c z) (EVSM) or exp(c z) (ESM) with z in
//   [0, 1]; it must stay below FLT_MAX = 3.4e38 = e^88.72, so c <= 44 for EVSM and c <= 88 for
//   ESM. The techniques' parameter ranges enforce this (evsm.h, esm.h); the blur is a convex
//   combination, so it never exceeds the largest input.
// - Pre-filter: a Gaussian of a fixed sigma in texels over the whole map. The penumbra it produces
//   has a fixed width in the map, whatever the blocker-receiver distance: contact hardening is lost
//   (the family's known failure, next to light bleeding).
// - Map coordinates: LightView::toMap (texel (i, j) centre at (i + 0.5, j + 0.5)); bilinear
//   lookups clamp to the edge texels, so receivers outside the map read the edge.
//
// Thread-safety: a MomentMap is written by renderMomentMap / filterMomentMap (one thread driving the
// rasterizer's arena) and is immutable afterwards: any number of threads may sample it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "raster/image.h"
#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

enum class MomentKind { Vsm, Evsm2, Evsm4, Esm };

// The warp from normalized depth z in [0, 1] to the stored moments.
struct MomentWarp {
  MomentKind kind = MomentKind::Vsm;
  float cPos = 0.0f;  // EVSM c+ / ESM c; EVSM [0, 42], ESM [1, 88]
  float cNeg = 0.0f;  // EVSM4 c-, [0, 42]

  int channels() const {
    switch (kind) {
      case MomentKind::Vsm:
        return 2;
      case MomentKind::Evsm2:
        return 2;
      case MomentKind::Evsm4:
        return 4;
      case MomentKind::Esm:
        return 1;
    }
    return 0;
  }
  // The moments of one depth z in [0, 1] (see the table above).
  raster::Float4 moments(float z) const {
    switch (kind) {
      case MomentKind::Vsm:
        return {z, z * z, 0.0f, 0.0f};
      case MomentKind::Evsm2: {
        const float p = std::exp(cPos * z);
        return {p, p * p, 0.0f, 0.0f};
      }
      case MomentKind::Evsm4: {
        const float p = std::exp(cPos * z), n = -std::exp(-cNeg * z);
        return {p, p * p, n, n * n};
      }
      case MomentKind::Esm:
        return {std::exp(cPos * z), 0.0f, 0.0f, 0.0f};
    }
    return {};
  }
  const char* name() const {
    switch (kind) {
      case MomentKind::Vsm:
        return "vsm";
      case MomentKind::Evsm2:
        return "evsm2";
      case MomentKind::Evsm4:
        return "evsm4";
      case MomentKind::Esm:
        return "esm";
    }
    return "";
  }
};

// Bilinearly filtered moments, in double (the variance E[m^2] - E[m]^2 cancels digits).
struct MomentSample {
  double m[4] = {0, 0, 0, 0};
};

struct MomentMap {
  LightView view;
  float zNear = 0.0f, zFar = 1.0f;  // view depths mapped to z = 0 and z = 1
  MomentWarp warp;
  raster::ImageFloat4 texels;

  // z = (d - zNear) / (zFar - zNear), clamped to [0, 1] (NaN d gives 1: treated as the far plane).
  float normalizedDepth(float d) const {
    const float z = (d - zNear) / (zFar - zNear);
    return z >= 0.0f ? std::min(z, 1.0f) : (z < 0.0f ? 0.0f : 1.0f);
  }
  // Bilinear lookup at continuous map coordinates (texel centres at +0.5), clamped to the edge
  // texels (a NaN coordinate reads texel 0).
  MomentSample sample(glm::vec2 mapPos) const;
};

// The parameters every moment technique has: "map_size", "bias", "slope_bias" (shadow_map.h
// depthMapParams: the receiver's slope-scaled bias, in texel footprints) and "filter_sigma".
std::vector<ParamSpec> momentMapParams(double defaultSigma = 2.0);
// "min_variance" (normalized depth^2) and "bleed_reduction", for VSM and EVSM.
std::vector<ParamSpec> chebyshevParams(double defaultMinVariance);

// The triangles a moment map draws: every caster triangle (index triples, in order) not wholly
// behind the light plane, beyond zFar or outside one side of the view's frustum. Not the region's
// culled CasterSet: the Chebyshev bound and ESM's ratio are exact only when a receiver's own surface
// is in the map around it (the lit part of a filter region must hold the receiver's depth, not the
// far plane's; Donnelly & Lauritzen 2006 render receivers as casters), and cullCasters drops
// surfaces that cannot block anything, such as the ground everything stands on. Without them, lit
// texels hold z = 1 > z_r and ESM's shadows shrink by up to exp(c (1 - z_r)).
std::vector<uint32_t> momentCasters(const Geometry& casters, const LightView& view, float zFar);

// Renders momentCasters(ctx.in.casters, ...) into map.texels (map.view and map.warp set by the
// caller; map.zNear = view.znear, map.zFar = 1.01 * region.hi.z are set here) with
// Rasterizer::draw, one varying (the view depth d), and adds the pass's stats to ctx.mapPasses.
void renderMomentMap(ShadowContext& ctx, MomentMap& map);
// The same pass with only the normalized depth z of each texel written, into `z` (1 where no
// caster covers it): map.texels stays empty. For techniques that need z alone (4 bytes a texel
// instead of 16).
void renderNormalizedDepth(ShadowContext& ctx, MomentMap& map, raster::ImageFloat& z);
// Gaussian blur of the used channels, sigma in texels (0: none), in the rasterizer's arena.
void filterMomentMap(ShadowContext& ctx, MomentMap& map, float sigma);

// The whole prepare stage of a moment technique: view from the light centre (map_size), render
// (timed into ctx.times.msMaps), filter (ctx.times.msFilter), and a note.
void prepareMomentMap(ShadowContext& ctx, const ParamSet& params, MomentWarp warp, MomentMap& map);

// The receiver's normalized depth: biasedDepth (shadow_map.h) converted to z, clamped to [0, 1].
// v = view-space position (v.z > 0), n = world-space normal.
inline float receiverDepth(const MomentMap& map, glm::vec3 v, glm::vec3 n, BiasParams bias) {
  return map.normalizedDepth(biasedDepth(map.view, v, n, bias));
}

// One-sided Chebyshev (Cantelli) inequality, Donnelly & Lauritzen 2006, section 3: for occluder
// depths with mean mu and variance s^2 = max(E[x^2] - mu^2, minVariance), the fraction of the
// filter region at depth >= t is bounded by
//     p_max(t) = s^2 / (s^2 + (t - mu)^2)   for t > mu,   1 otherwise.
// In [0, 1]; guarded so that s^2 = 0 = t - mu (only possible with minVariance = 0) gives 1.
inline double chebyshevUpperBound(double mean, double meanSq, double t, double minVariance) {
  if (!(t > mean)) return 1.0;
  const double variance = std::max(meanSq - mean * mean, minVariance);
  const double d = t - mean;
  const double den = variance + d * d;
  return den > 0.0 ? std::clamp(variance / den, 0.0, 1.0) : 1.0;
}

// The EVSM bound at normalized receiver depth z (EVSM2: the positive warp; EVSM4: the smaller of
// both): each warp's minimum variance is minVariance scaled by its squared derivative at z, so it
// stays minVariance in units of z^2 (Lauritzen & McCool 2008).
inline double evsmBound(const MomentSample& s, const MomentWarp& warp, double z, double minVariance) {
  const double cPos = static_cast<double>(warp.cPos), cNeg = static_cast<double>(warp.cNeg);
  // Positive warp: t = exp(c+ z), minimum variance scaled by (dw/dz)^2 = (c+ t)^2.
  const double tPos = std::exp(cPos * z);
  double p = chebyshevUpperBound(s.m[0], s.m[1], tPos, minVariance * (cPos * tPos) * (cPos * tPos));
  if (warp.kind == MomentKind::Evsm4) {
    // Negative warp: t = -exp(-c- z), dw/dz = c- exp(-c- z) = -c- t.
    const double tNeg = -std::exp(-cNeg * z);
    p = std::min(p, chebyshevUpperBound(s.m[2], s.m[3], tNeg, minVariance * (cNeg * tNeg) * (cNeg * tNeg)));
  }
  return p;
}

// Light-bleeding reduction (Lauritzen, GPU Gems 3, ch. 8, "Summed-Area Variance Shadow Maps",
// section 8.4.3): bounds below `amount` are treated as fully shadowed and the rest rescaled,
//     p' = clamp((p - amount) / (1 - amount), 0, 1),   amount in [0, 0.99].
// It darkens (and so narrows) every penumbra a little along with the bleeding.
inline double reduceLightBleeding(double p, double amount) {
  return std::clamp((p - amount) / (1.0 - amount), 0.0, 1.0);
}

}  // namespace penumbra::shadows
