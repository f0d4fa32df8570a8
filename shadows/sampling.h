// Counter-based random numbers and low-discrepancy point sets for the shadow techniques and the
// ground truth. No global state: every value is a pure function of its counters, so results do not
// depend on thread count or scheduling (DESIGN.md, "Determinism").
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>

namespace penumbra::shadows {

// A 32-bit hash of three counters (a "lowbias32"-style finalizer applied in sequence). Avalanche
// is good enough for per-pixel rotations and jitter; it is not for cryptography.
constexpr uint32_t mix32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
constexpr uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  return mix32(a ^ mix32(b ^ mix32(c + 0x9e3779b9U)));
}
// A float in [0, 1) from the top 24 bits of a hash.
constexpr float unitFloat(uint32_t h) { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }

// Van der Corput radical inverse in base 2, in [0, 1).
constexpr uint32_t reverseBits32(uint32_t v) {
  v = ((v >> 1) & 0x55555555U) | ((v & 0x55555555U) << 1);
  v = ((v >> 2) & 0x33333333U) | ((v & 0x33333333U) << 2);
  v = ((v >> 4) & 0x0f0f0f0fU) | ((v & 0x0f0f0f0fU) << 4);
  v = ((v >> 8) & 0x00ff00ffU) | ((v & 0x00ff00ffU) << 8);
  return (v >> 16) | (v << 16);
}
constexpr float radicalInverse2(uint32_t i) { return static_cast<float>(reverseBits32(i) >> 8) * (1.0f / 16777216.0f); }

// Point i of the n-point Hammersley set in [0,1)^2: ((i + 0.5) / n, radicalInverse2(i) + 0.5/n
// wrapped). Stratified: every row and column of an n x 1 and 1 x n grid holds one point, and for n
// a power of two every elementary interval of area 1/n holds one.
inline glm::vec2 hammersley(uint32_t i, uint32_t n) {
  const float inv = 1.0f / static_cast<float>(n);
  float y = radicalInverse2(i) + 0.5f * inv;
  if (y >= 1.0f) y -= 1.0f;
  return {(static_cast<float>(i) + 0.5f) * inv, y};
}

}  // namespace penumbra::shadows
