// Shared blocks of the pre-filtered soft shadows (ESSM, SAVSM, VSSM, CSSM and the post-filtered
// soft VSM): one map of the normalized linear depth z from the light centre (moments.h: a
// MomentMap of (z, z^2), unfiltered), its min/max pyramid, and the PCSS geometry of a receiver in
// that map's texels: the blocker search box (the light's frustum from the receiver cut at the near
// plane) and the penumbra box for a blocker depth (the same with the blockers on one plane).
//
// Conventions
// - Texel coordinates are continuous: texel (i, j) covers [i, i + 1) x [j, j + 1) (raster/sat.h),
//   so LightView::toMap gives them directly.
// - Depths: z = (d - zNear) / (zFar - zNear) (moments.h); a receiver's z_r is its biased depth
//   (shadow_map.h biasedDepth), or with `receiver_plane` on, the depth of its tangent plane at the
//   centre of each sub-kernel (Isidoro 2006, as PCSS's taps): a tilted receiver is then not its own
//   blocker across a wide kernel.
// - Boxes are half-extents around the receiver's texel position; the search box's is
//   (w/2, h/2) (1/near - 1/d_r) in tangent units (pcss.h), the penumbra box's
//   (w/2, h/2) (1/d_b - 1/d_r).
//
// Thread-safety: a PrefilterMap is written by preparePrefilterMap and immutable afterwards.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/ext/vector_double2.hpp>
#include <glm/vec2.hpp>
#include <limits>
#include <string>
#include <vector>

#include "raster/kernels.h"
#include "raster/sat.h"
#include "shadows/moments.h"
#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

struct PrefilterMap {
  MomentMap map;                  // (z, z^2) per texel, unfiltered
  raster::ImageFloat z;           // z alone, for taps and the pyramid
  raster::MinMaxPyramid pyramid;  // of z
  float zMin = 0, zMax = 1;       // over the texels a caster covers (z < 1)
  // Texels no caster covers hold z = 1 (the far plane): never a blocker.
  static bool empty(float zn) { return zn >= 1.0f; }
  double tpx = 1, tpy = 1;  // texels per tangent unit along x and y

  // View depth of a normalized depth.
  double viewDepth(double zn) const {
    return static_cast<double>(map.zNear) + zn * static_cast<double>(map.zFar - map.zNear);
  }
  // z at texel coordinates (nearest texel, clamped to the map).
  float zAt(double x, double y) const;
};

// Renders the map (times.msMaps) and builds the pyramid (times.msFilter). What a technique does not
// read is not made: without `moments`, only z is rendered (map.texels stays empty); without
// `pyramid`, m.pyramid stays empty (zMin and zMax are found all the same).
struct PrefilterNeeds {
  bool moments = true, pyramid = true;
};
void preparePrefilterMap(ShadowContext& ctx, const ParamSet& params, PrefilterMap& m,
                         PrefilterNeeds needs = {});

// One receiver in the map.
struct ReceiverKernel {
  double cx = 0, cy = 0;  // texel coordinates
  double zr = 0;          // normalized biased depth at the receiver
  double biasZ = 0;       // the bias, in normalized depth (unbiased z - zr)
  double dr = 0;          // view depth
  double sx = 0, sy = 0;  // blocker search half-extents, texels
  ReceiverPlane plane;
  bool usePlane = false;
  // The plane's threshold near / d (ReceiverPlane::threshold) as a function of texel coordinates,
  // scale * clamp(lx x + ly y + l0, lo, hi), and the map's normalization of d: set by
  // receiverKernel, read by zrAt (in double: no float conversions or divisions by the texel size).
  double lx = 0, ly = 0, l0 = 0, lo = 0, hi = 0, scale = 0, znear = 0, zNear = 0, invRange = 1;

  // z_r at texel coordinates (x, y): the tangent plane's there with `receiver_plane`, else zr.
  double zrAt(double x, double y) const;
};
inline double ReceiverKernel::zrAt(double x, double y) const {
  if (!usePlane) return zr;
  const double t = scale * std::clamp(lx * x + ly * y + l0, lo, hi);  // near / biased depth
  const double z = ((t > 0.0 ? znear / t : std::numeric_limits<double>::infinity()) - zNear) * invRange;
  return z >= 0.0 ? std::min(z, 1.0) : (z < 0.0 ? 0.0 : 1.0);  // as MomentMap::normalizedDepth
}

ReceiverKernel receiverKernel(const PrefilterMap& m, const ShadowContext& ctx, const Receiver& r,
                              BiasParams b, bool usePlane);
// A box [x0, x1) x [y0, y1) against a min/max pyramid of the map's depths (HSM): mn, mx bound the
// texels the pyramid covers (a little more than the box), lo, hi the receiver plane's depth there
// (at the covered rectangle's corners: 1/d is linear in the map, so d is monotone along lines).
struct PlaneBounds {
  double mn = 0, mx = 0, lo = 0, hi = 0;
};
inline PlaneBounds planeBounds(const raster::MinMaxPyramid& pyramid, const ReceiverKernel& k, double x0,
                               double y0, double x1, double y1) {
  float mn = 0, mx = 0;
  int cov[4];
  raster::queryMinMax(pyramid, static_cast<int>(std::floor(x0)), static_cast<int>(std::floor(y0)),
                      static_cast<int>(std::ceil(x1)), static_cast<int>(std::ceil(y1)), mn, mx, cov);
  const double p00 = k.zrAt(cov[0], cov[1]), p10 = k.zrAt(cov[2], cov[1]);
  const double p01 = k.zrAt(cov[0], cov[3]), p11 = k.zrAt(cov[2], cov[3]);
  return {static_cast<double>(mn), static_cast<double>(mx), std::min(std::min(p00, p10), std::min(p01, p11)),
          std::max(std::max(p00, p10), std::max(p01, p11))};
}

// Penumbra half-extents in texels for a blocker at normalized depth zb, at least minHalf texels.
glm::dvec2 penumbraHalf(const PrefilterMap& m, const ShadowContext& ctx, const ReceiverKernel& k, double zb,
                        double minHalf = 0.5);

// HSM (needs m.pyramid): no blocker in k's search box is nearer than the smallest depth the
// min/max pyramid finds over it, so the light's frustum from the receiver cut at that depth
// (smaller than at the near plane) holds every blocker; repeated (up to 4 times) while the box
// shrinks by more than 10%. True when it shrank.
bool shrinkSearchBox(const PrefilterMap& m, const ShadowContext& ctx, ReceiverKernel& k);

// Which tiles of a tile grid (tile x tile texels) the search boxes of the receivers reach (shrunk
// by shrinkSearchBox with `hsm`); counts the receivers scanned. Marks are byte stores of 1
// (order-independent, deterministic).
std::vector<uint8_t> tilesReached(ShadowContext& ctx, const PrefilterMap& m, BiasParams b, int tile,
                                  int tilesX, int tilesY, bool hsm = false);

// The parameters of the SAT techniques: the depth map's, "receiver_plane" (on/off) and
// "subdivision" (n x n sub-kernels, 1 = none).
std::vector<ParamSpec> prefilterParams(int defaultSubdivision);

// "search": hsm (shrinkSearchBox) or near (the frustum cut at the near plane); defaultIndex 0 or 1.
ParamSpec searchParam(int defaultIndex = 0);

// "n of m tiles (p%) built" for notes.
std::string tileNote(size_t built, size_t total);

}  // namespace penumbra::shadows
