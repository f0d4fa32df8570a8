// Resolve: a pixel's S samples grouped into at most kMaxLayers surfaces with their sample counts
// (a box filter), largest count first, each with a representative sample (the median one in time
// of the samples it holds). The engine shades each surface once and blends them by their counts.
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <cstdint>
#include <span>

#include "stochastic/sample_pattern.h"

namespace penumbra::stochastic {

inline constexpr int kMaxLayers = 3;
inline constexpr uint32_t kStaticSurface = 0xFFFFFFFEu;  // the static layer's texel of the pixel
inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
// What covers a sample, in the per-sample buffers: a triangle index, kStaticRef (the static layer
// drawn by the ordinary path) or kNoTriangle.
inline constexpr uint32_t kStaticRef = kStaticSurface;

struct ResolvedLayer {
  uint32_t surface = 0;      // StochasticInput::surface of the triangle, or kStaticSurface
  uint16_t count = 0;        // samples of the pixel on this surface
  uint16_t sample = 0;       // the representative sample: the median one in time
  uint32_t triangle = 0;     // the triangle that covers it (kNoTriangle for the static layer)
  Sample at;                 // its time and lens position
};
struct ResolvedPixel {
  uint16_t background = 0;   // samples that hit nothing
  uint8_t layers = 0;        // surfaces, largest count first (ties: smaller surface id first)
  ResolvedLayer layer[kMaxLayers];
  // A pixel seeing more than kMaxLayers surfaces adds the rest's counts to layer 0 (rare: counted
  // in StochasticStats::pixelsMerged).
};

// The pixel whose samples are covered by ref[0 .. spp) (see kStaticRef); surface[t] groups
// triangle t's samples; samples: the pixel's samples (null: every sample is static or background,
// and the layers' `at` stay zero). Returns true when more than kMaxLayers surfaces were merged.
bool resolvePixel(const uint32_t* ref, int spp, std::span<const uint32_t> surface, const Sample* samples,
                  ResolvedPixel& out);

// What resolvePixel gives for a pixel no triangle reached: its samples all static (covered) or
// all background.
ResolvedPixel resolveUntouched(bool covered, int spp);

}  // namespace penumbra::stochastic
