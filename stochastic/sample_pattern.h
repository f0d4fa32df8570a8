// The samples of a pixel: S samples (1 to kMaxSpp), each at the pixel centre (x, y) with a time t
// in [0, 1) and a lens position (u, v) in the unit disk. Deterministic: a counter-based hash of
// (pixel, sample, frame), no global random state, identical across runs and thread counts.
//
// Time is stratified (jittered): sample k of a pixel has t in [k/S, (k+1)/S), so the samples of a
// pixel are sorted by time and a time interval [t0, t1] maps to the index range
// [floor(t0 S), floor(t1 S)]; the bounding methods rely on this. The lens points are a 2D
// low-discrepancy set (the R2 sequence of Roberts, 2018) with a per-pixel random shift (a
// Cranley-Patterson rotation), mapped to the disk by Shirley and Chiu's concentric map; which lens
// point goes with which time stratum is a per-pixel random permutation, so time and lens are
// decorrelated (a fixed pairing would turn motion into a shear of the defocus).
//
// Why pixel centres (no x, y jitter): the main pipeline samples pixel centres, so a static triangle
// seen through a pinhole covers all or none of a pixel's samples and takes the ordinary path (one
// coverage test shared by all of them), and a frame with no motion and a pinhole is the ordinary
// frame bit for bit. Spatial antialiasing is not this module's subject.
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>

namespace penumbra::stochastic {

inline constexpr int kMaxSpp = 64;

struct Sample {
  float t = 0.0f;            // shutter time in [0, 1); 0 when there is no motion
  float u = 0.0f, v = 0.0f;  // lens position in the unit disk (or square, LensShape); 0 for a pinhole
};

// The lens's shape: the unit disk of a camera's round aperture, or the square [-1, 1]^2 of a
// rectangular area light used as a lens (stochastic soft shadow maps, shadows/sssm.h: the shear of
// coverage.h then scales u and v by the light's half-width and half-height).
enum class LensShape : uint8_t { Disk, Square };

// Block stratification of a square lens with one sample per pixel (Liktor et al. 2015, section
// 7.1): the n^2 pixels of each n x n block of pixels take the n^2 cells of an n x n grid of the lens
// square, one each, in an order permuted per block by the hash (block, frame), jittered inside the
// cell by the hash (pixel, frame). Neighbouring pixels then see different parts of the light. With
// motion the block's pixels also take the n^2 strata of the shutter, [k/n^2, (k+1)/n^2), in a second
// permutation per block (time and lens stratum independent), jittered by the hash (pixel, frame);
// the lens points are the same with or without motion.
inline constexpr int kMaxBlockStrata = 8;

struct SamplePattern {
  int spp = 16;                 // samples per pixel, [1, kMaxSpp]
  uint32_t frame = 0;           // seeds the hash: another frame, other samples
  bool motion = true;           // draw times (else t = 0)
  bool lens = true;             // draw lens positions (else u = v = 0)
  LensShape shape = LensShape::Disk;
  int blockStrata = 0;          // square lens, spp 1: n x n pixel blocks stratify the lens (n in
                                // [2, kMaxBlockStrata]); 0 or 1: the pixel's R2 point, as for spp > 1
  // Every sample at this (t, u, v) instead (tests: the stochastic rasterizer then renders the
  // triangle at one time and lens position, which the main pipeline can render too).
  std::optional<Sample> fixed;
};

// The S samples of pixel (x, y), sorted by time, into out[0 .. spp). A square lens takes the R2
// points (or the block strata) in [-1, 1)^2 directly, without the concentric map.
void pixelSamples(const SamplePattern& p, int x, int y, Sample* out);

// Shirley and Chiu's concentric map from [0, 1)^2 to the unit disk (area preserving, low
// distortion), in float (the sample pattern) or double (the accumulation reference).
template <class T>
void concentricDisk(T a, T b, T& u, T& v) {
  const T x = T(2) * a - T(1), y = T(2) * b - T(1);
  if (x == T(0) && y == T(0)) {
    u = v = T(0);
    return;
  }
  constexpr T kQuarter = std::numbers::pi_v<T> / T(4);
  T r, phi;
  if (std::abs(x) > std::abs(y)) {
    r = x;
    phi = kQuarter * (y / x);
  } else {
    r = y;
    phi = T(2) * kQuarter - kQuarter * (x / y);
  }
  u = r * std::cos(phi);
  v = r * std::sin(phi);
}

// Counter-based hash (the murmur3 64-bit finalizer over a mixed key) and a float in [0, 1).
uint64_t sampleHash(uint64_t a, uint64_t b, uint64_t c);
inline float unitFloat(uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }

}  // namespace penumbra::stochastic
