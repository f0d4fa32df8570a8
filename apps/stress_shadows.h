// The shadows stress suite of `penumbra stress --suite shadows`: every technique of the registry on
// numerically hard configurations -- depth ranges (far / near) up to 1e5 (the views clamp near at
// 1e-5 of far), receivers 1e-4 below
// their occluder, overlapping occluders at very different depths (the light-bleeding case of the
// moment techniques), and curved and touching geometry where V is known exactly
// (docs/techniques/reference.md): a faceted sphere at grazing light (the terminator: V = the
// fraction of the light above each facet's plane), receivers 1e-4 above a caster's surface (V = 1:
// their own surface's neighbour must not shadow them) and the foot of a cube on the ground (contact:
// V = the fraction of the light in front of the cube's face). Judged: no NaN or Inf and V in
// [0, 1]. Reported: the light bleeding (largest V where the receiver is in full umbra), the
// over-darkening (smallest V where it is fully lit) and, for the exact cases, the RMSE and the bias
// (signed mean: > 0 too bright) against the exact V. Two more cases: a light far wider than the
// map's extent (every kernel wider than the map) and a step (two occluders at different heights
// meeting edge to edge: non-planar blockers).
// Thread-safety: runs in the given rasterizer's arena; one suite at a time per rasterizer.
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "raster/pipeline.h"

namespace penumbra::apps {

struct ShadowStressRow {
  std::string technique, name, param;
  size_t receivers = 0;
  size_t umbra = 0, lit = 0;  // receivers classified as in full umbra / fully lit (analytically)
  size_t nonFinite = 0;      // NaN or Inf values of V
  size_t outOfRange = 0;     // V outside [0, 1]
  double bleed = 0;          // max V over receivers in full umbra (0 is right)
  double darkening = 0;      // 1 - min V over fully lit receivers (0 is right)
  double rmse = NAN, bias = NAN;  // against the exact V, for the exact cases (NaN otherwise)
  bool ok() const { return nonFinite == 0 && outOfRange == 0; }
  std::string json() const;
};

// Every registry technique at its defaults, then the variants below (technique, settings; their
// rows' technique is "name settings"): microquads and the search structures, whose depth
// discontinuities, contact and depth range differ from the defaults'.
std::vector<ShadowStressRow> runShadowStress(raster::Rasterizer& rast);
const std::vector<std::pair<std::string, std::string>>& shadowStressVariants();

// The summed-area tables of the pre-filtered techniques (raster/sat.h) at 4096^2 on an ESSM-like
// image: exp(-80 u) with u rising from 0 at one corner to 1 at the other (values from 1 down to
// e^-80), queried by boxes of 1 to 16 texels at fractional positions along the diagonal, against
// the brute-force area-weighted sum in long double. Per table: the worst error of the box mean,
// the worst error relative to the exact mean, and the worst ratio of the error to the table's
// stated bound (quantization for integer and tiled, rounding for float and double; <= 1 is right).
struct SatPrecisionRow {
  std::string table;
  int size = 0;
  size_t queries = 0;
  double maxError = 0, maxRelative = 0, maxBoundRatio = 0;
  bool ok() const { return std::isfinite(maxError) && maxBoundRatio <= 1.0; }
  std::string json() const;
};

std::vector<SatPrecisionRow> runSatPrecision(int size = 4096);

}  // namespace penumbra::apps
