// Shared by the techniques that sample the light with views (MVR, VWSS): the stratified light
// points, and the per-receiver depth tests against one light sample's depth map.
//
// Per receiver, computed once: its light-space position (x, y, d), 1/d, its normal in light space
// and the bias factor bias + slope_bias * tan(theta) for the ray from the light's centre (views'
// origins lie on the light, so theta hardly changes between them). Per map, a tap is then a few
// multiplications, one division and one load: lit when the light sample is above the receiver's
// tangent plane (its own closed surface hides the rest) and the stored value passes
// near / (d (1 - beta)), beta = the map's texel footprint per unit depth times the bias factor.
// Thread-safety: one object per technique run; accumulate() runs rows in parallel in the
// context's arena, each receiver's count written by one task.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <span>
#include <string>
#include <vector>

#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

// Light-space points (world units from the centre along right and up) of n stratified samples:
// a Hammersley set over the rectangle. MVR and VWSS use the same points.
std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n);

// n Poisson-disk points over the rectangle (light space, as lightSamplePoints): best-candidate
// sampling (Mitchell 1991), each point the farthest from those before it of 32 uniform candidates
// (counter-based hash of (n, point, candidate): deterministic), distances in world units so a long
// light gets isotropic spacing. The distribution the VWSS paper's light samples follow.
std::vector<glm::vec2> poissonDiskPoints(const RectLight& light, int n);

// Interleaved light samples (Keller & Heidrich 2001, interleaved sampling): the n points split
// into k x k subsets, each a Hammersley set of its own (n / k^2 points, the first n % k^2 subsets
// one more) under a Cranley-Patterson shift ((s + 0.5) / k^2, radicalInverse2(s)), wrapped on the
// light; pixel (x, y) uses subset (x mod k) + k (y mod k) only. The N maps then sit at N distinct
// light points across every k x k block, and a wide penumbra shows fine noise instead of N
// stacked copies of the occluder's edge (at k^2 times fewer samples per pixel). k = 1: exactly
// lightSamplePoints, one subset; k is lowered until k^2 <= n (every subset holds a point).
struct LightSampleSet {
  std::vector<glm::vec2> points;
  std::vector<int> subset;  // per point
  std::vector<int> count;   // points per subset (k * k)
  int k = 1;
};
LightSampleSet interleavedLightSamples(const RectLight& light, int n, int k);
// The light samples the "samples" parameter names: "hammersley" (interleavedLightSamples) or
// "poisson" (poissonDiskPoints; with interleaving, point i goes to subset i mod k^2).
LightSampleSet lightSamples(const RectLight& light, int n, int k, const std::string& pattern);
// The "interleave" parameter of MVR and VWSS (k, 1 = off).
ParamSpec interleaveParam();
// The "samples" parameter of MVR and VWSS: hammersley (default) or poisson.
ParamSpec samplePatternParam();
// The "fit" parameter of MVR and VWSS: each light sample's map fitted to the receivers (choice 0),
// or to the receivers cut to the casters' box as that sample sees it (1; makeLightView).
ParamSpec mapFitParam(int defaultIndex);

// The taps of the depth-map techniques' per-map PCF (mvr, vwss: pcf=5): the texel, then its four
// neighbours (offsets in texels). pcf=1 takes the first.
inline constexpr glm::vec2 kPcfTaps[5] = {{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};

// A light sample's depth map as the tests read it, in place: its view, and the stored values
// (near / depth, 0 = nothing drawn) as a rasterized map's floats (ShadowMap) or as a splatted map's
// float bit patterns (raster/splat.h, splatDepth), `stride` elements between rows.
struct SampleMap {
  LightView view;
  const float* depth = nullptr;         // one of the two
  const uint32_t* depthBits = nullptr;
  int stride = 0;
  glm::vec2 lightPoint{0.0f};           // the view's origin on the light (light space)
  int subset = -1;                      // with interleaving, the pixels of this subset only; -1: all

  static SampleMap of(const ShadowMap& map, glm::vec2 lightPoint, int subset = -1);
  static SampleMap ofBits(const LightView& view, const raster::Image<uint32_t>& bits, glm::vec2 lightPoint,
                          int subset = -1);
};

// The kernel's form of a SampleMap: its lookup constants (kernel_taps.h TapMap's, with the
// reciprocals of the texel centres, TexelCentres) and the per-map constants of the test.
struct SampleLookup {
  const void* data = nullptr;
  bool bits = false;  // data holds float bit patterns (uint32_t) rather than floats
  int32_t stride = 0;
  float ax = 0, bx = 0, ay = 0, by = 0, maxX = 0, maxY = 0, invAx = 0, invAy = 0;
  float texelTanX = 0, texelTanY = 0;  // one texel in tangent units, per axis
  float texel = 0;                     // texelWorld(1)
  float znear = 0;
  float lpx = 0, lpy = 0;
  int32_t subset = -1;
};

// The receivers of one row as the kernel reads them: light-space position, 1 / d, the bias factor
// and the light-space geometric normal per receiver, as separate arrays padded to a multiple of
// kTapLanes (padding and receivers with nothing to test have d = -1); lane subsets x mod k.
struct SampleRow {
  const float *x, *y, *d, *invD, *bias, *nx, *ny, *nz;
  const int32_t* subsetOfX;  // (x mod k), padded like the rest
  int32_t subsetBase = 0;    // k (y mod k)
  int count = 0;             // receivers in the row (the arrays hold it rounded up to kTapLanes)
  float normalOffset = 0;    // BiasParams::normal
};

// counts[x] += the taps that pass over every map of `maps` whose subset is the receiver's (or -1),
// per receiver of the row. The SIMD kernel (every target, chosen by `simd` as raster/simd.h says)
// and the plain reference give the same counts: the same float operations in the same order
// (kernel_taps.h's rules).
void accumulateSampleRow(const SampleRow& row, std::span<const SampleLookup> maps, const float* tapX,
                         const float* tapY, int taps, uint16_t* counts, int64_t simd = 0);
void accumulateSampleRowReference(const SampleRow& row, std::span<const SampleLookup> maps, const float* tapX,
                                  const float* tapY, int taps, uint16_t* counts);

class LightSampleTests {
 public:
  void prepare(ShadowContext& ctx, BiasParams bias, int interleave = 1);
  // counts(x, y) += the taps (offsets in texels of each map) that pass, for each light sample of
  // `maps` (a group kept in memory together: each receiver is read once per group); with
  // interleaving, only at the pixels of each map's subset. Rows in parallel in the context's arena,
  // the SIMD kernel of its RasterConfig::simd.taps.
  void accumulate(ShadowContext& ctx, std::span<const SampleMap> maps, std::span<const glm::vec2> taps);
  // The same, one map.
  void accumulate(ShadowContext& ctx, const ShadowMap& map, glm::vec2 lightPoint, std::span<const glm::vec2> taps,
                  int subset = -1);
  // V = counts / (taps * points of the pixel's subset) (exactly 1 when every tap passed);
  // background 1, behind the light 0.
  void finish(ShadowContext& ctx, int taps, const LightSampleSet& samples, raster::ImageFloat& visibility) const;
  const raster::Image<uint16_t>& counts() const { return counts_; }

 private:
  float normalOffset_ = 0.0f;  // texels (BiasParams::normal)
  int interleave_ = 1;
  int width_ = 0, height_ = 0, padded_ = 0;
  // Per receiver, row by row (padded_ per row): see SampleRow.
  std::vector<float> x_, y_, d_, invD_, bias_, nx_, ny_, nz_;
  std::vector<int32_t> subsetOfX_;
  raster::Image<uint16_t> counts_;
};

}  // namespace penumbra::shadows
