#include "stochastic/resolve.h"

#include <algorithm>

namespace penumbra::stochastic {

bool resolvePixel(const uint32_t* ref, int spp, std::span<const uint32_t> surface, const Sample* samples,
                  ResolvedPixel& o) {
  o = ResolvedPixel{};
  uint32_t surf[kMaxSpp];
  uint16_t count[kMaxSpp];
  int n = 0;
  auto surfaceOf = [&](uint32_t r) { return r == kStaticRef ? kStaticSurface : surface[r]; };
  for (int k = 0; k < spp; ++k) {
    if (ref[k] == kNoTriangle) {
      ++o.background;
      continue;
    }
    const uint32_t sid = surfaceOf(ref[k]);
    int j = 0;
    while (j < n && surf[j] != sid) ++j;
    if (j == n) {
      surf[n] = sid;
      count[n++] = 0;
    }
    ++count[j];
  }
  int order[kMaxSpp];
  for (int j = 0; j < n; ++j) order[j] = j;
  std::sort(order, order + n, [&](int a, int b) { return count[a] != count[b] ? count[a] > count[b] : surf[a] < surf[b]; });
  o.layers = static_cast<uint8_t>(std::min(n, kMaxLayers));
  for (int l = 0; l < o.layers; ++l) {
    ResolvedLayer& L = o.layer[l];
    const int j = order[l];
    L.surface = surf[j];
    L.count = count[j];
    // The median sample in time of this surface.
    int want = (count[j] - 1) / 2;
    for (int k = 0; k < spp; ++k) {
      if (ref[k] == kNoTriangle || surfaceOf(ref[k]) != surf[j] || want-- > 0) continue;
      L.sample = static_cast<uint16_t>(k);
      L.triangle = ref[k] == kStaticRef ? kNoTriangle : ref[k];
      L.at = samples ? samples[k] : Sample{};
      break;
    }
  }
  if (n <= kMaxLayers) return false;
  for (int l = kMaxLayers; l < n; ++l) o.layer[0].count = static_cast<uint16_t>(o.layer[0].count + count[order[l]]);
  return true;
}

ResolvedPixel resolveUntouched(bool covered, int spp) {
  ResolvedPixel o;
  if (covered) {
    o.layers = 1;
    o.layer[0].surface = kStaticSurface;
    o.layer[0].count = static_cast<uint16_t>(spp);
    o.layer[0].sample = static_cast<uint16_t>((spp - 1) / 2);
    o.layer[0].triangle = kNoTriangle;
  } else {
    o.background = static_cast<uint16_t>(spp);
  }
  return o;
}

}  // namespace penumbra::stochastic
