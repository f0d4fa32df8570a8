// Point splatting (DESIGN.md "The pipeline", item 7; Marrs et al. 2018, "View-Warped Multi-View
// Soft Shadows", section 3.2): N world-space points projected into M views in one traversal of the
// points, each point landing in one pixel of each view, resolved by a 64-bit atomic min.
//
// Conventions
// - Projection, per point p and view (the raster/ conventions, conventions.h), in float with no
//   FMA contraction (penumbra_options), so the result is a function of the inputs alone:
//     clip_r = (m[0][r] p.x + m[1][r] p.y) + (m[2][r] p.z + m[3][r])   for r = x, y, z, w
//   (bit for bit glm's viewProj * vec4(p, 1)),
//     sx = (clip.x / w * 0.5 + 0.5) * width,   sy = (0.5 - clip.y / w * 0.5) * height,
//   and the point lands in pixel (floor(sx), floor(sy)): pixel (i, j) covers [i, i+1) x [j, j+1).
// - Skipped (culled) for a view unless: w is finite and > 0, 0 <= z <= w, 0 <= sx < width and
//   0 <= sy < height. So clip x = -w lands in column 0 and x = w (sx = width) is skipped; y = w
//   lands in row 0 and y = -w is skipped. NaN and Inf fail these tests: a point with a non-finite
//   coordinate (or a view whose matrix makes its clip position non-finite) is never written.
// - Key (64 bits): high 32 bits the depth key, low 32 bits the payload (the caller's per-point
//   uint32, e.g. a packed RGBA8 color, or the point index when none is given). The smallest key
//   wins: the nearest point, ties in depth broken by the smaller payload. An empty pixel holds
//   kEmptyKey = UINT64_MAX, which no point can produce (depth keys are <= 0x3F800000).
// - Depth key, from d = z / w in [0, 1] (-0 is taken as +0):
//     ZOverW          key = bits(d), the IEEE-754 pattern. For non-negative floats the pattern's
//                     order as an integer equals the numeric order, so min = nearest (standard
//                     depth, DepthFunc::Less, 0 at the near plane).
//     ReversedZOverW  key = bits(1.0f) - bits(d) = 0x3F800000 - bits(d). For reversed depth, where
//                     larger d is nearer (shadows/light_view.h: clip z = near, w = depth, so
//                     d = near / depth, DepthFunc::Greater, 0 = nothing). The integer mirror is
//                     exact and keeps every bit of d; the float 1 - d would have a resolution of
//                     2^-24 (every d below 2^-25 rounds to 1) and throw away the far-range
//                     precision that reversed depth exists for.
//   resolveDepth inverts the key, so both give back d itself.
// - Determinism: min is commutative and associative and keys are totally ordered, so each pixel
//   holds the min over the points that landed in it whatever the order of the writes: the targets
//   are byte-identical at any thread count and any K. Stats are integer sums of per-chunk counts.
//
// Modes (the paper's): the views are processed in passes of K (viewsPerPass) views; each pass is
// one parallel traversal of the points in fixed chunks of kSplatChunk points, and each chunk is
// projected into the K views of the pass in turn while it is in cache. K = 1: one view per
// traversal ("serial" in the paper); 1 < K < M: "partially parallel"; K = M: all views in one
// traversal ("fully parallel"). Threads come from the caller: splatPoints runs tbb::parallel_for in
// the current task arena, so call it through Rasterizer::run to use that rasterizer's threads (a
// one-thread arena gives the single-threaded mode).
//
// The projection runs in SIMD lanes (Highway; the target a call names, simd.h, the best by default)
// with the same float operations on every target, so every target gives the same bits.
//
// Thread-safety: pure functions of their arguments. Within splatPoints the targets are written
// concurrently only through std::atomic_ref (on a one-thread arena, by plain loads and stores);
// the caller must not touch them during the call. Several views may share one target (the pixel
// gets the min over both). Distinct calls may run concurrently on distinct targets.
#pragma once

#include <algorithm>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <span>

#include "raster/image.h"
#include "raster/simd.h"

namespace penumbra::raster {

inline constexpr uint64_t kEmptyKey = UINT64_MAX;
// Points per chunk: 4096 points are 48 KiB of positions, reused from L2 by the K views of a pass.
// Fixed, never derived from the thread count, so scheduling cannot change what is computed.
inline constexpr int kSplatChunk = 4096;

enum class DepthKey : uint8_t {
  ZOverW,          // key = bits(z / w): smaller z / w is nearer
  ReversedZOverW,  // key = 0x3F800000 - bits(z / w): larger z / w is nearer
};

struct SplatView {
  glm::mat4 viewProj{1.0f};            // world -> clip
  Image<uint64_t>* target = nullptr;   // keys; its size is the view's size, 1..kMaxTargetSize a side
};

struct SplatStats {
  uint64_t points = 0;     // N
  uint64_t views = 0;      // M
  uint64_t passes = 0;     // traversals of the points: ceil(M / K)
  uint64_t written = 0;    // (point, view) pairs that passed every test and went to the atomic min
  uint64_t culled = 0;     // (point, view) pairs skipped: written + culled = points * views
  uint64_t nonFinite = 0;  // points with a NaN/Inf coordinate (culled in every view)
  double ms = 0;           // wall clock of the whole call
};

// Packing of an RGBA8 color into a payload: r in bits 0-7, g 8-15, b 16-23, a 24-31.
inline constexpr uint32_t packRgba8(Rgba8 c) {
  return uint32_t{c.r} | (uint32_t{c.g} << 8) | (uint32_t{c.b} << 16) | (uint32_t{c.a} << 24);
}
inline constexpr Rgba8 unpackRgba8(uint32_t v) {
  return {static_cast<uint8_t>(v), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v >> 16),
          static_cast<uint8_t>(v >> 24)};
}

// Sets every key (padding included) to kEmptyKey, rows in parallel in the caller's arena.
void clearKeys(Image<uint64_t>& keys);

// Splats points into views (see the conventions above). payloads: one per point, or empty for the
// point index (then at most 2^32 points). viewsPerPass: K in [1, M], or 0 for M. The targets are
// not cleared: the call takes the min with what they hold, so several calls accumulate.
// Throws std::invalid_argument for a payload count other than 0 or N, a null target, a target size
// outside 1..kMaxTargetSize, or K outside [0, M].
// simd: the projection's SIMD target (simd.h; 0: the best).
SplatStats splatPoints(std::span<const glm::vec3> points, std::span<const uint32_t> payloads,
                       std::span<const SplatView> views, DepthKey key, int viewsPerPass = 0, int64_t simd = 0);

// Streaming splats, for producers that emit points one at a time from several threads (a fragment
// stage: view-warped shadows' unbuffered mode). Points are gathered in a per-thread batch of 256
// and, when it fills (and at flush()), projected and written exactly as splatPoints does (the same
// projection, tests and keys), always with atomic min: the targets end up byte-identical to
// splatPoints over the same points in any order. add() is safe from many threads; flush() must be
// called once every add() has returned, by one thread. Payloads are given per point.
class PointSplatter {
 public:
  PointSplatter(std::span<const SplatView> views, DepthKey key, int64_t simd = 0);
  ~PointSplatter();
  PointSplatter(const PointSplatter&) = delete;
  PointSplatter& operator=(const PointSplatter&) = delete;
  void add(glm::vec3 p, uint32_t payload);
  void flush();
  uint64_t points() const;  // added so far (after flush: all)

 private:
  struct State;
  State* state_;
};

// ---- Depth-only splatting -------------------------------------------------------------------
//
// The paper's own form (Marrs et al. 2018, Listing 2: a 32-bit InterlockedMax of asuint(z / w)):
// no payload, and the key is the depth's own float bit pattern, so the target *is* a depth map
// read in place (std::bit_cast<float>(bits)), with no resolve pass. For non-negative floats the bit
// patterns order as the values do, so the nearest point is
//   ReversedZOverW  the largest d: an atomic max; an empty texel holds 0 = bits(0.0f), the reversed
//                   depth maps' "nothing drawn" (shadows/light_view.h);
//   ZOverW          the smallest d: an atomic min; an empty texel holds bits(1.0f), the far plane.
// Projection, culling and the texel a point lands in are those of splatPoints above (the same
// float operations), so the depth at each texel is bit for bit resolveDepth(splatPoints(...)) of
// the same points (emptyValue 0 or 1), at any thread count, K or SIMD target.
//
// Surfels (Zwicker et al. 2001's surface elements, without their reconstruction filter): a point
// given with two edge vectors u and v stands for the parallelogram p + a u + b v, |a|, |b| <= 1/2,
// of its surface (view-warped shadows give each point the footprint of its source pixel on its
// triangle), and is rasterized like a tiny quad: it covers the texels whose *centres* lie inside
// the parallelogram as projected into the view -- neither the texel a point happens to fall in
// (the paper's splat, which bloats a silhouette by up to a texel where points are dense and leaves
// holes where they are sparse) nor more -- and writes there the depth of its plane at that centre,
// as rasterizing the surface would (not its own depth off the centre, which a shadow test reads as
// a step of up to half a texel times the slope: the paper's self-shadowing bands, Fig. 11).
// Per view, with the point at screen s (as above) and depth d = z / w, k = 1 / w, X = x / w,
// Y = y / w, and for an edge vector e the rows' linear parts r_x . e, ... (in the projection's
// association: (m0 e.x + m1 e.y) + m2 e.z):
//     screen edge  J e = (0.5 width (r_x.e - X r_w.e) k, -0.5 height (r_y.e - Y r_w.e) k),
//     depth step   D e = (r_z.e - d r_w.e) k,
// A = J u, B = J v, det = A.x B.y - A.y B.x; a texel centre c (i + 0.5, j + 0.5), q = c - s:
//     a = (B.y q.x - B.x q.y) / det,   b = (A.x q.y - A.y q.x) / det,
//     covered iff |a| <= h and |b| <= h, h = 1/2 + 1/64 (the linearized parallelograms of
//     neighbouring surfels meet only to first order: the margin guards the seams between them),
//     depth d(c) = d + (a D u + b D v)  (z / w is affine in screen position over a plane: exact
//     up to rounding), bounded to [d / 2, min(2 d, 1)].
// The candidate centres are those of the box s +- (|A| + |B|) h per axis (at most 9 texels a side,
// around the point's own texel: a footprint seen at a grazing angle covers more, and its far part
// is dropped), inside the view. The point's own screen position may lie up to kMaxSurfelReach
// texels outside the view (plain points: inside it): a footprint centred just past the border
// covers the border texels, which a source view coarser than the map would otherwise leave empty
// (a light leak along the map's edge). A degenerate footprint (det 0 or not finite) covers nothing. Points without edge
// vectors write the texel they fall in with their own depth, as above.
//
// Touched rectangles: per view, the smallest rectangle holding every texel written by the call
// (clearDepthBits of it restores an empty map without touching the rest).
inline constexpr uint32_t emptyDepthBits(DepthKey key) { return key == DepthKey::ReversedZOverW ? 0u : 0x3F800000u; }

// A surfel's edge vectors (world units; see above).
struct SurfelAxes {
  glm::vec3 u{0.0f}, v{0.0f};
};
// The surfel box's largest half-width in texels beyond the point's own texel.
inline constexpr int kMaxSurfelReach = 4;

struct DepthSplatView {
  glm::mat4 viewProj{1.0f};
  Image<uint32_t>* target = nullptr;  // depth bits (see above); 1..kMaxTargetSize a side
};

// Texels [x0, x1) x [y0, y1); empty when x0 >= x1.
struct SplatRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
  void add(const SplatRect& o) {
    if (o.empty()) return;
    if (empty()) {
      *this = o;
      return;
    }
    x0 = std::min(x0, o.x0), y0 = std::min(y0, o.y0), x1 = std::max(x1, o.x1), y1 = std::max(y1, o.y1);
  }
};

// Splats points (and, for surfels, their edge vectors: empty or one per point) into the views'
// depth maps, K views per traversal (viewsPerPass: [1, M] or 0 for M), taking the nearest with what
// the targets hold. touched: empty, or one per view, set to the rectangle of texels the call wrote
// (a view sharing its target with another gets its own). Throws std::invalid_argument as
// splatPoints, and for an edge-vector count other than 0 or N or a touched count other than 0 or M.
// SplatStats::written counts the (point, view) pairs that passed the point tests (a surfel among
// them may cover no centre).
SplatStats splatDepth(std::span<const glm::vec3> points, std::span<const SurfelAxes> surfels,
                      std::span<const DepthSplatView> views, DepthKey key, int viewsPerPass = 0, int64_t simd = 0,
                      std::span<SplatRect> touched = {});

// Sets the texels of `rect` (clipped to the image) to emptyDepthBits(key), rows in parallel in the
// caller's arena; the whole image, padding included, when rect is null.
void clearDepthBits(Image<uint32_t>& depth, DepthKey key, const SplatRect* rect = nullptr);

// Streaming depth splats, for producers that emit points one at a time from several threads (a
// fragment stage: view-warped shadows' unbuffered mode): as PointSplatter, per-thread batches of
// 256 projected and written exactly as splatDepth does, so the maps end up bit for bit those of
// splatDepth over the same points (and edge vectors, with surfels) in any order. add() is safe from many
// threads; flush() once every add() has returned, by one thread; touched() after flush().
class DepthSplatter {
 public:
  DepthSplatter(std::span<const DepthSplatView> views, DepthKey key, bool surfels, int64_t simd = 0);
  ~DepthSplatter();
  DepthSplatter(const DepthSplatter&) = delete;
  DepthSplatter& operator=(const DepthSplatter&) = delete;
  void add(glm::vec3 p, const SurfelAxes& axes = {});  // axes: read with surfels only
  void flush();
  uint64_t points() const;                 // added so far (after flush: all)
  SplatRect touched(size_t view) const;    // the texels written into view `view`

 private:
  struct State;
  State* state_;
};

// Resolve: each output is resized to the keys' size; visible pixels only, rows in parallel.
// depth = d (z / w, see DepthKey) of the winning point, emptyValue where no point landed.
void resolveDepth(const Image<uint64_t>& keys, DepthKey key, ImageFloat& depth, float emptyValue);
// payload = low 32 bits of the key, emptyValue where no point landed.
void resolvePayload(const Image<uint64_t>& keys, Image<uint32_t>& payload, uint32_t emptyValue = UINT32_MAX);
// color = unpackRgba8(payload), background where no point landed.
void resolveColor(const Image<uint64_t>& keys, ImageRgba8& color, Rgba8 background);

}  // namespace penumbra::raster
