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
// (signed mean: > 0 too bright) against the exact V.
// Thread-safety: runs in the given rasterizer's arena; one suite at a time per rasterizer.
#pragma once

#include <cmath>
#include <string>
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

std::vector<ShadowStressRow> runShadowStress(raster::Rasterizer& rast);

}  // namespace penumbra::apps
