// Percentage-closer filtering (Reeves, Salesin, Cook 1987): one shadow map from the light centre,
// V = the fraction of depth comparisons that pass over a fixed kernel around the receiver's texel.
// Two kernels: a regular grid (side x side taps over [-radius, radius]^2 texels) and a Poisson disk
// (best-candidate points in the disk of the given radius) rotated per pixel by a hashed angle,
// which trades the grid's banding for noise. Comparisons use the receiver-plane depth at each tap.
// The penumbra width is fixed (radius texels at every distance): no contact hardening.
// docs/techniques/pcf.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include <vector>

#include <glm/vec2.hpp>

#include "shadows/technique.h"

namespace penumbra::shadows {

TechniqueInfo pcfTechnique();

// n points in the unit disk by Mitchell's best-candidate algorithm (each new point the farthest of
// 8 * (i + 1) hashed candidates from those placed): a Poisson-disk-like set, deterministic.
std::vector<glm::vec2> poissonDisk(int n, uint32_t seed = 0x5eed);

}  // namespace penumbra::shadows
