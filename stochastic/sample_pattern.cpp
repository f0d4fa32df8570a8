#include "stochastic/sample_pattern.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra::stochastic {

uint64_t sampleHash(uint64_t a, uint64_t b, uint64_t c) {
  uint64_t h = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full ^
               (c + 0x165667B19E3779F9ull) * 0x27D4EB2F165667C5ull;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

namespace {

float fract(float x) { return x - std::floor(x); }

// perm[0 .. n) = a permutation of 0 .. n-1, Fisher-Yates driven by sampleHash(key, frame, salt + k).
void hashPermutation(int* perm, int n, uint64_t key, uint32_t frame, uint64_t salt) {
  for (int k = 0; k < n; ++k) perm[k] = k;
  for (int k = n - 1; k > 0; --k) {
    const uint64_t h = sampleHash(key, frame, salt + static_cast<uint64_t>(k));
    const int j = static_cast<int>((h >> 32) % static_cast<uint64_t>(k + 1));
    const int tmp = perm[k];
    perm[k] = perm[j];
    perm[j] = tmp;
  }
}

// Block stratification (sample_pattern.h): pixel (x, y)'s cell of the n x n lens grid, jittered.
void blockStratum(const SamplePattern& p, int x, int y, uint64_t pixel, Sample& o) {
  const int n = p.blockStrata;
  const auto bx = static_cast<uint32_t>(x / n), by = static_cast<uint32_t>(y / n);
  const uint64_t block = (static_cast<uint64_t>(by) << 32) | bx;
  int perm[kMaxBlockStrata * kMaxBlockStrata];
  hashPermutation(perm, n * n, block, p.frame, 0x200u);
  const int cell = perm[(y % n) * n + (x % n)];
  const uint64_t jitter = sampleHash(pixel, p.frame, 2);
  const float fn = static_cast<float>(n);
  const float a = (static_cast<float>(cell % n) + unitFloat(jitter)) / fn;
  const float b = (static_cast<float>(cell / n) + unitFloat(jitter << 24)) / fn;
  // a, b < 1 (unitFloat < 1 - 2^-24 and the cell index < n), so u, v stay in [-1, 1).
  o.u = std::min(2.0f * a - 1.0f, std::nextafter(1.0f, 0.0f));
  o.v = std::min(2.0f * b - 1.0f, std::nextafter(1.0f, 0.0f));
  if (!p.motion) return;
  // Time: the block's n^2 pixels take the n^2 strata of the shutter, in another permutation (so a
  // pixel's time stratum and lens cell are independent), jittered by the hash (pixel, frame, 3).
  int tperm[kMaxBlockStrata * kMaxBlockStrata];
  hashPermutation(tperm, n * n, block, p.frame, 0x300u);
  const float strata = fn * fn;
  const float t =
      (static_cast<float>(tperm[(y % n) * n + (x % n)]) + unitFloat(sampleHash(pixel, p.frame, 3))) / strata;
  o.t = std::min(t, std::nextafter(1.0f, 0.0f));
}

}  // namespace

void pixelSamples(const SamplePattern& p, int x, int y, Sample* out) {
  const int s = p.spp;
  if (p.fixed) {
    for (int k = 0; k < s; ++k) out[k] = *p.fixed;
    return;
  }
  const uint64_t pixel = (static_cast<uint64_t>(static_cast<uint32_t>(y)) << 32) | static_cast<uint32_t>(x);
  // Per-pixel permutation of the lens points (Fisher-Yates driven by the hash).
  int perm[kMaxSpp];
  hashPermutation(perm, s, pixel, p.frame, 0x100u);
  const uint64_t shift = sampleHash(pixel, p.frame, 1);
  const float su = unitFloat(shift), sv = unitFloat(shift << 24);
  constexpr double kG = 1.32471795724474602596;  // plastic number: R2 uses 1/g and 1/g^2
  const float a1 = static_cast<float>(1.0 / kG), a2 = static_cast<float>(1.0 / (kG * kG));
  for (int k = 0; k < s; ++k) {
    Sample& o = out[k];
    if (p.motion) {
      const float jitter = unitFloat(sampleHash(pixel, p.frame, 0x10000u + static_cast<uint64_t>(k)));
      const float t = (static_cast<float>(k) + jitter) / static_cast<float>(s);
      // Rounding may give (k + ~1) / S == (k + 1) / S: keep the sample inside its stratum, below 1.
      const float hi = std::nextafter(static_cast<float>(k + 1) / static_cast<float>(s), 0.0f);
      o.t = t < hi ? t : hi;
    } else {
      o.t = 0.0f;
    }
    if (p.lens && p.shape == LensShape::Square && p.blockStrata > 1 && s == 1) {
      blockStratum(p, x, y, pixel, o);
    } else if (p.lens) {
      const float i = static_cast<float>(perm[k]) + 0.5f;
      const float a = fract(i * a1 + su), b = fract(i * a2 + sv);
      if (p.shape == LensShape::Square) {
        o.u = 2.0f * a - 1.0f;
        o.v = 2.0f * b - 1.0f;
      } else {
        concentricDisk(a, b, o.u, o.v);
      }
    } else {
      o.u = o.v = 0.0f;
    }
  }
}

}  // namespace penumbra::stochastic
