// The ray-traced ground truth for area-light visibility (DESIGN.md, "Shadows"), registered as the
// technique "reference". For every receiver x with geometric (face) normal n (Receiver::normal)
//     V(x) = (1/A) * integral over the light of v(x, y) dA_y,
// v(x, y) = 1 when y is in front of the one-sided light, above x's geometric tangent plane
// (dot(n, y - x) > 0) and the segment x-y is free: the plain (not cosine-weighted) visible fraction
// of the light's whole area (docs/techniques/reference.md). It is estimated with Embree 3 occlusion
// rays from x to the points of a stratified jittered grid on the light.
//
// Sampling: light uv (s, t) in [0,1]^2 (area_light.h) is cut into exactly `samples` cells of equal
// area, in rows of (nearly) square cells on the light (sampleGrid); each cell holds one point,
// jittered uniformly inside it by hash3(pixel x, pixel y, 2 * sample + dimension) (sampling.h),
// samples numbered row by row. Random numbers depend on the pixel and the sample only, so the
// image is the same at every thread count and in every run. V = (unoccluded samples) / samples.
//
// Moving casters (ShadowInputs::castersOpen, motion-blurred soft shadows): the casters are an
// Embree scene of two time steps, each vertex moving on the straight line from its open to its
// close position as the rasterizer's time-continuous triangles do, and each ray has a time. A
// receiver of a static surface (Receiver::wholeShutter) averages v over light and shutter time,
//     V(x) = integral over t in [0, 1] of (1/A) integral over the light of v(x, y, t) dA_y dt,
// sample s at time fract(r + s / phi) (the golden-ratio sequence, r = hash3(px, py, 2^31 - 1)):
// for each s the pair (light point, time) is uniform over its cell times the shutter, so the
// estimate is unbiased, and the times of a receiver's samples are spread evenly. A receiver on a
// moving surface is placed at one time (Receiver::time) and its rays are all at that time.
// Background texels get 1, receivers on or behind the light plane (dot(x - center, normal) <= 0)
// get 0, as forEachReceiver. A sample below the tangent plane is blocked (not traced).
//
// Rays: the origin is x moved off its face by eps along n (the side every traced ray leaves
// towards), and the ray runs from there to y:
//     eps = 2e-6 * D + 4e-6 * max_i |x_i|,
// D the diagonal of the bounding box of the light's corners and the receivers in front of it (the
// scene's scale: a world-unit offset that grows with the scene, not with the distance to the
// light), the second term about 32 float ulps of x (the rounding of a rasterized position off its
// triangle's plane). The ray stops at t = 1 - 1e-4, short of the light itself, so geometry lying in
// the light plane (a lamp's frame) does not block it. A segment is blocked when any caster triangle
// meets it (either face; Embree's robust traversal, so the answer does not depend on the BVH's
// shape). The receiver's own face cannot block a ray above its plane.
//
// Estimator error: where v depends on s only (a straight shadow edge parallel to the light's up
// axis), only the cell of each row holding the edge is random: on a square light with N = k^2
// samples the standard deviation is at most 0.5 / (k * sqrt(k)) = 0.5 * N^(-3/4), and the RMSE over
// a penumbra ramp is sqrt(1/6) * N^(-3/4) = 0.41 * N^(-3/4) (tests/shadows/ground_truth_test.cpp
// measures 0.404 to 0.422 for N = 16 to 4096 against the analytic penumbra).
//
// Cache (ShadowInputs::cache, result_cache.h): the image is stored under a key (groundTruthKey)
// that hashes everything it depends on; the engine keeps it in a file that is used only when its
// magic, version, key, size and payload hash all match (engine/result_cache.h). A cache that cannot
// be written is skipped (and said so in the notes), never an error.
//
// Thread-safety: RayScene is immutable after construction; traceVisibility may be called on one
// scene from several threads. The other functions are pure (computeGroundTruth uses its cache).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "raster/image.h"
#include "shadows/technique.h"

// Embree's handles, declared as Embree declares them (rtcore_device.h, rtcore_scene.h), so that this
// header does not pull Embree into every user.
struct RTCDeviceTy;
struct RTCSceneTy;

namespace penumbra::shadows {

struct GroundTruthOptions {
  int samples = 1024;    // rays per receiver, [1, 65536]; the grid may round it up (sampleGrid)
  ResultCache* cache = nullptr;  // null: none
  // Moving casters: every caster vertex at shutter open and close (ShadowInputs::castersOpen);
  // empty: static.
  std::span<const glm::vec3> castersOpen{}, castersClose{};
};

// The stratified grid of exactly `samples` cells of equal area 1/samples on the light (uv units),
// as close to square on the light as whole numbers allow: `rows` rows along the height,
//     rows = clamp(round(sqrt(samples * height / width)), 1, samples),
// row j holding n_j = floor(samples / rows) cells, plus one for the first samples % rows rows, and
// a height of n_j / samples in v (so every cell is 1/n_j wide and n_j / samples high: area
// 1/samples). On a square light with a perfect square (1024: 32 x 32) it is the plain grid.
// Throws std::invalid_argument when samples is outside [1, 65536].
struct SampleGrid {
  int rows = 1, samples = 1;
  int count() const { return samples; }
  int base() const { return samples / rows; }       // cells of the shorter rows
  int longRows() const { return samples % rows; }   // rows holding base() + 1
  int cellsIn(int row) const { return base() + (row < longRows() ? 1 : 0); }
  int rowStart(int row) const { return row * base() + std::min(row, longRows()); }  // cells before `row`
};
SampleGrid sampleGrid(const RectLight& light, int samples);

// The casters as an Embree scene (its own device), built at construction with
// RTC_BUILD_QUALITY_HIGH and robust traversal. The build runs Embree's TBB loops in the caller's
// arena (call it inside Rasterizer::run). Referenced vertices are copied, so `casters` need not
// outlive it; triangles with a non-finite vertex are left out (counted). Throws
// std::invalid_argument for an index out of range and std::runtime_error naming the Embree error
// when Embree fails.
class RayScene {
 public:
  // open, close: the casters' vertices at shutter open and close (both or neither; each as long as
  // casters.positions): a scene of two time steps.
  explicit RayScene(const Geometry& casters, std::span<const glm::vec3> open = {},
                    std::span<const glm::vec3> close = {});
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  size_t triangles() const { return triangles_; }  // kept
  size_t dropped() const { return dropped_; }      // triangles with a non-finite vertex, left out
  bool moves() const { return moves_; }            // two time steps: rays carry a time
  // Rays per Embree call in traceVisibility: the widest packet Embree runs natively on this CPU
  // (16, 8 or 4: rtcOccluded16/8/4, every ray of a packet from one receiver), else 1 (rtcOccluded1).
  int packetWidth() const { return packetWidth_; }
  RTCSceneTy* handle() const { return scene_; }

 private:
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  size_t triangles_ = 0, dropped_ = 0;
  int packetWidth_ = 1;
  bool moves_ = false;
};

// Fills `out` (resized to the receivers' size) with V for every receiver, rows in parallel with
// tbb::parallel_for in the caller's arena (call it inside Rasterizer::run to use the rasterizer's
// threads). Returns the number of rays traced. force1: trace with rtcOccluded1 even where packets
// are supported (the tests compare the two paths).
uint64_t traceVisibility(const RayScene& scene, const ReceiverImage& receivers, const RectLight& light,
                         SampleGrid grid, raster::ImageFloat& out, bool force1 = false);

// A 64-bit hash of everything the ground truth image depends on: a format version, the three
// corners of every caster triangle in order (positions the indices reference, and the indices),
// the receivers' size and for each texel its valid flag and, when valid, its position and normal,
// the light's geometry (center, right, up, width, height: not its color or intensity, which V does
// not depend on) and the sample count; with moving casters also each referenced vertex's open and
// close positions and each valid receiver's time. A chain of splitmix64 finalizers over 64-bit words (float
// bits, so -0 and +0 differ): deterministic, not cryptographic.
uint64_t groundTruthKey(const Geometry& casters, const ReceiverImage& receivers, const RectLight& light,
                        int samples, std::span<const glm::vec3> open = {},
                        std::span<const glm::vec3> close = {});

// What computeGroundTruth did.
struct GroundTruthStats {
  SampleGrid grid;
  int packetWidth = 0;              // RayScene::packetWidth (0: no scene built, the cache held the image)
  size_t triangles = 0;             // casters traced against (0 on a cache hit)
  size_t dropped = 0;               // casters left out: a non-finite vertex
  uint64_t receivers = 0;           // receivers traced (valid, in front of the light)
  uint64_t rays = 0;                // rays traced (0 on a cache hit)
  uint64_t key = 0;                 // 0 when no cache was given
  std::string cacheEntry;           // the cache's name of the key, "" when no cache was given
  bool cacheHit = false, cacheWritten = false;
  bool moving = false;     // the casters moved: a scene of two time steps
  std::string cacheError;  // why the cache was not written, or ""
  double msPrepare = 0;    // key, cache lookup, scene build
  double msTrace = 0;      // tracing, cache write
  // One line for ShadowContext::notes: grid, rays, Mrays/s, what the cache did.
  std::string summary() const;
};

// The whole ground truth for one light in the caller's arena: cache lookup, scene build, tracing,
// cache write.
GroundTruthStats computeGroundTruth(const Geometry& casters, const ReceiverImage& receivers,
                                    const RectLight& light, const GroundTruthOptions& options,
                                    raster::ImageFloat& out);

// "reference": parameter "samples" (Int, default 1024, [1, 65536]; see sampleGrid). Traces the
// culled casters (ShadowContext::casterGeometry); prepare builds the scene (msMaps) unless the
// cache holds the image, evaluate traces (msEvaluate). Not benchmarked (isReference).
TechniqueInfo referenceTechnique();

}  // namespace penumbra::shadows
