// Point splatting (see splat.h for the conventions and the determinism contract), the projection
// compiled once per Highway target.
//
// Work decomposition: a pass (K views) is one tbb::parallel_for over chunks of kSplatChunk points.
// A chunk is walked in batches of kBatch points; each batch is projected into each view of the pass
// while its positions are in L1, in two steps:
//   project  SIMD lanes of points (ProjectBatch below): the clip position, the tests, the pixel
//            offset and the depth key, with exactly the float operations of splat.h in the same
//            order (no FMA: IEEE add, mul and div give the same bits on every target). Culled
//            lanes get the depth key kCulled, which no point can have (keys are <= 0x3F800000).
//   scatter  scalar: the atomic min of each kept key, with the target line of a later point
//            prefetched kPrefetch points ahead. A target is read before any compare-exchange: a
//            write that loses costs a load instead of a locked instruction (which would also wait
//            for the loads in flight; prefetches are not ordered by it). On a one-thread arena the
//            min is a plain load, conditional move and store: same result, about 1.5x faster
//            (the locked instructions and the mispredicted "is it smaller" branches go).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/splat.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "raster/conventions.h"
#include "raster/splat.h"

// Shared by every target's code and the dispatching code (this file is compiled once per target).
#ifndef PENUMBRA_RASTER_SPLAT_SHARED
#define PENUMBRA_RASTER_SPLAT_SHARED
namespace penumbra::raster::splat_detail {

// Points projected before they are written: 256 points are 3 KiB of positions and 2 KiB of
// offsets and depth keys, all in L1 for the K views of the pass. A multiple of every target's lanes.
constexpr int kBatch = 256;
static_assert(kSplatChunk % kBatch == 0);
// Prefetch distance in points: about the number of cache misses a core keeps in flight (10-16
// line-fill buffers) times a little.
constexpr int kPrefetch = 16;

constexpr uint32_t kOneBits = 0x3F800000u;  // bits(1.0f): the largest depth key
constexpr uint32_t kCulled = 0xFFFFFFFFu;   // depth key of a culled lane

// A view as the projection reads it: the matrix by rows, clip_r = (r[0] x + r[1] y) + (r[2] z + r[3]).
struct ViewRows {
  float x[4], y[4], z[4], w[4];
  float width, height;
  int32_t stride;
  uint64_t* keys;
};

}  // namespace penumbra::raster::splat_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using namespace splat_detail;

// Projects points [0, n) (xyz: 3 n floats, n <= kBatch) into view v: offsets[i] = y * stride + x
// of the pixel and depths[i] = the depth key, or offset 0 and kCulled. Returns the kept count.
uint32_t ProjectBatch(const float* xyz, int n, const ViewRows& v, bool reversed, uint32_t* offsets, uint32_t* depths) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::RebindToUnsigned<decltype(df)> du;
  const int N = static_cast<int>(hn::Lanes(df));
  const auto x0 = hn::Set(df, v.x[0]), x1 = hn::Set(df, v.x[1]), x2 = hn::Set(df, v.x[2]), x3 = hn::Set(df, v.x[3]);
  const auto y0 = hn::Set(df, v.y[0]), y1 = hn::Set(df, v.y[1]), y2 = hn::Set(df, v.y[2]), y3 = hn::Set(df, v.y[3]);
  const auto z0 = hn::Set(df, v.z[0]), z1 = hn::Set(df, v.z[1]), z2 = hn::Set(df, v.z[2]), z3 = hn::Set(df, v.z[3]);
  const auto w0 = hn::Set(df, v.w[0]), w1 = hn::Set(df, v.w[1]), w2 = hn::Set(df, v.w[2]), w3 = hn::Set(df, v.w[3]);
  const auto width = hn::Set(df, v.width), height = hn::Set(df, v.height);
  const auto zero = hn::Zero(df), half = hn::Set(df, 0.5f), maxFinite = hn::Set(df, std::numeric_limits<float>::max());
  const auto stride = hn::Set(di, v.stride);
  const auto signMask = hn::Set(du, 0x7FFFFFFFu), one = hn::Set(du, kOneBits), culled = hn::Set(du, kCulled);
  HWY_ALIGN float tail[3 * HWY_MAX_BYTES / sizeof(float)];
  uint32_t kept = 0;
  for (int i = 0; i < n; i += N) {
    hn::Vec<decltype(df)> px, py, pz;
    auto valid = hn::FirstN(df, static_cast<size_t>(n - i));
    if (i + N <= n) {
      hn::LoadInterleaved3(df, xyz + 3 * i, px, py, pz);
    } else {  // the last, partial vector: from a zero-padded copy (zeros give w = 0: culled anyway)
      std::memset(tail, 0, sizeof(tail));
      std::memcpy(tail, xyz + 3 * i, static_cast<size_t>(3 * (n - i)) * sizeof(float));
      hn::LoadInterleaved3(df, tail, px, py, pz);
    }
    const auto cx = hn::Add(hn::Add(hn::Mul(x0, px), hn::Mul(x1, py)), hn::Add(hn::Mul(x2, pz), x3));
    const auto cy = hn::Add(hn::Add(hn::Mul(y0, px), hn::Mul(y1, py)), hn::Add(hn::Mul(y2, pz), y3));
    const auto cz = hn::Add(hn::Add(hn::Mul(z0, px), hn::Mul(z1, py)), hn::Add(hn::Mul(z2, pz), z3));
    const auto cw = hn::Add(hn::Add(hn::Mul(w0, px), hn::Mul(w1, py)), hn::Add(hn::Mul(w2, pz), w3));
    const auto sx = hn::Mul(hn::Add(hn::Mul(hn::Div(cx, cw), half), half), width);
    const auto sy = hn::Mul(hn::Sub(half, hn::Mul(hn::Div(cy, cw), half)), height);
    // Ordered comparisons: false for NaN. w <= FLT_MAX rejects w = +Inf, and then z <= w and the
    // screen bounds reject an infinite z, x or y.
    auto ok = hn::And(valid, hn::And(hn::Gt(cw, zero), hn::Le(cw, maxFinite)));
    ok = hn::And(ok, hn::And(hn::Ge(cz, zero), hn::Le(cz, cw)));
    ok = hn::And(ok, hn::And(hn::Ge(sx, zero), hn::Lt(sx, width)));
    ok = hn::And(ok, hn::And(hn::Ge(sy, zero), hn::Lt(sy, height)));
    // Kept lanes have 0 <= sx < width <= 16384: truncation is floor and is exact. Culled lanes are
    // zeroed first (their sx may be NaN or huge).
    const auto ix = hn::ConvertTo(di, hn::IfThenElseZero(ok, sx));
    const auto iy = hn::ConvertTo(di, hn::IfThenElseZero(ok, sy));
    const auto offset = hn::BitCast(du, hn::Add(hn::Mul(iy, stride), ix));  // < 2^28 (conventions.h)
    // d = z / w in [-0, 1] when kept; clearing the sign bit maps -0 to +0.
    auto depth = hn::And(hn::BitCast(du, hn::Div(cz, cw)), signMask);
    if (reversed) depth = hn::Sub(one, depth);
    const auto oku = hn::RebindMask(du, ok);
    hn::StoreU(hn::IfThenElseZero(oku, offset), du, offsets + i);
    hn::StoreU(hn::IfThenElse(oku, depth, culled), du, depths + i);
    kept += static_cast<uint32_t>(hn::CountTrue(df, ok));
  }
  return kept;
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::raster {
HWY_EXPORT(ProjectBatch);

namespace {

using ProjectFn = std::remove_cvref_t<decltype(HWY_DISPATCH_TABLE(ProjectBatch)[0])>;

// The projection of the SIMD target asked for (simd.h).
ProjectFn projectFor(int64_t simd) {
  ProjectFn fn = HWY_DISPATCH_TABLE(ProjectBatch)[simdDispatchIndex(simd)];
  return fn ? fn : HWY_DISPATCH_TABLE(ProjectBatch)[0];
}
using namespace splat_detail;

constexpr uint32_t kExpMask = 0x7F800000u;  // exponent all ones: Inf or NaN

ViewRows viewRows(const SplatView& v) {
  ViewRows r;
  for (int c = 0; c < 4; ++c) {  // glm is column-major: m[c][r] is column c, row r
    r.x[c] = v.viewProj[c][0];
    r.y[c] = v.viewProj[c][1];
    r.z[c] = v.viewProj[c][2];
    r.w[c] = v.viewProj[c][3];
  }
  r.width = static_cast<float>(v.target->width());
  r.height = static_cast<float>(v.target->height());
  r.stride = v.target->stride();
  r.keys = v.target->data();
  return r;
}

// slot = min(slot, key), atomically. Reads first: when the key loses (the common case once a
// pixel has a few points) no locked instruction is issued.
inline void atomicMin(uint64_t& slot, uint64_t key) {
  std::atomic_ref<uint64_t> a(slot);
  uint64_t cur = a.load(std::memory_order_relaxed);
  while (key < cur && !a.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
  }
}

// payloads: per point of the batch, or null for the index (firstIndex + i). kAtomic = false when
// the call runs on one thread (the arena has one slot): nothing else writes the targets, and a
// plain min (a conditional move and a store, no branch to mispredict) is exact too.
template <bool kAtomic>
void scatter(uint64_t* target, const uint32_t* offsets, const uint32_t* depths, const uint32_t* payloads,
             uint32_t firstIndex, int n) {
  for (int i = 0; i < n; ++i) {
    if (i + kPrefetch < n) __builtin_prefetch(target + offsets[i + kPrefetch], 1);
    if (depths[i] == kCulled) continue;
    const uint32_t payload = payloads ? payloads[i] : firstIndex + static_cast<uint32_t>(i);
    const uint64_t key = uint64_t{depths[i]} << 32 | payload;
    if constexpr (kAtomic) {
      atomicMin(target[offsets[i]], key);
    } else {
      uint64_t& slot = target[offsets[i]];
      slot = std::min(slot, key);
    }
  }
}

uint64_t countNonFinite(const glm::vec3* p, size_t n) {
  uint64_t bad = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool finite = (std::bit_cast<uint32_t>(p[i].x) & kExpMask) != kExpMask &&
                        (std::bit_cast<uint32_t>(p[i].y) & kExpMask) != kExpMask &&
                        (std::bit_cast<uint32_t>(p[i].z) & kExpMask) != kExpMask;
    bad += finite ? 0 : 1;
  }
  return bad;
}

struct ChunkCounts {
  uint64_t written = 0, nonFinite = 0;
};

// One pass: views [v0, v1) over every chunk.
void splatPass(std::span<const glm::vec3> points, std::span<const uint32_t> payloads, const std::vector<ViewRows>& rows,
               size_t v0, size_t v1, bool reversed, bool firstPass, ProjectFn project, std::vector<ChunkCounts>& counts) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points are read as packed xyz floats");
  const size_t n = points.size();
  const bool atomic = tbb::this_task_arena::max_concurrency() > 1;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, counts.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    HWY_ALIGN uint32_t offsets[kBatch];
    HWY_ALIGN uint32_t depths[kBatch];
    for (size_t c = r.begin(); c != r.end(); ++c) {
      const size_t begin = c * kSplatChunk, end = std::min(n, begin + kSplatChunk);
      ChunkCounts& cc = counts[c];
      if (firstPass) cc.nonFinite = countNonFinite(points.data() + begin, end - begin);
      for (size_t b = begin; b < end; b += kBatch) {
        const int m = static_cast<int>(std::min<size_t>(kBatch, end - b));
        const float* xyz = &points[b].x;
        const uint32_t* pay = payloads.empty() ? nullptr : payloads.data() + b;
        for (size_t v = v0; v < v1; ++v) {
          cc.written += project(xyz, m, rows[v], reversed, offsets, depths);
          if (atomic) scatter<true>(rows[v].keys, offsets, depths, pay, static_cast<uint32_t>(b), m);
          else scatter<false>(rows[v].keys, offsets, depths, pay, static_cast<uint32_t>(b), m);
        }
      }
    }
  });
}

template <class F>
void forRows(int rows, F&& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 4), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) f(y);
  });
}

}  // namespace

void clearKeys(Image<uint64_t>& keys) {
  const size_t stride = static_cast<size_t>(keys.stride());
  forRows(keys.paddedRows(), [&](int y) { std::fill(keys.row(y), keys.row(y) + stride, kEmptyKey); });
}

SplatStats splatPoints(std::span<const glm::vec3> points, std::span<const uint32_t> payloads,
                       std::span<const SplatView> views, DepthKey key, int viewsPerPass, int64_t simd) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = points.size(), m = views.size();
  if (!payloads.empty() && payloads.size() != n)
    throw std::invalid_argument("splatPoints: " + std::to_string(payloads.size()) + " payloads for " +
                                std::to_string(n) + " points (give one per point, or none for the index)");
  if (payloads.empty() && n > uint64_t{UINT32_MAX} + 1)
    throw std::invalid_argument("splatPoints: more than 2^32 points cannot use the index as payload");
  if (viewsPerPass < 0 || static_cast<size_t>(viewsPerPass) > m)
    throw std::invalid_argument("splatPoints: viewsPerPass " + std::to_string(viewsPerPass) + " outside [0, " +
                                std::to_string(m) + "]");
  std::vector<ViewRows> rows;
  rows.reserve(m);
  for (size_t v = 0; v < m; ++v) {
    const Image<uint64_t>* t = views[v].target;
    if (!t) throw std::invalid_argument("splatPoints: view " + std::to_string(v) + " has no target");
    if (t->width() < 1 || t->height() < 1 || t->width() > kMaxTargetSize || t->height() > kMaxTargetSize)
      throw std::invalid_argument("splatPoints: view " + std::to_string(v) + " target must be 1 to " +
                                  std::to_string(kMaxTargetSize) + " pixels a side");
    rows.push_back(viewRows(views[v]));
  }

  SplatStats stats;
  stats.points = n;
  stats.views = m;
  if (n > 0 && m > 0) {
    const size_t k = viewsPerPass == 0 ? m : static_cast<size_t>(viewsPerPass);
    std::vector<ChunkCounts> counts((n + kSplatChunk - 1) / kSplatChunk);
    for (size_t v0 = 0; v0 < m; v0 += k) {
      splatPass(points, payloads, rows, v0, std::min(m, v0 + k), key == DepthKey::ReversedZOverW, v0 == 0,
                projectFor(simd), counts);
      ++stats.passes;
    }
    for (const ChunkCounts& c : counts) {
      stats.written += c.written;
      stats.nonFinite += c.nonFinite;
    }
  }
  stats.culled = static_cast<uint64_t>(n) * m - stats.written;
  stats.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

struct PointSplatter::State {
  struct Batch {
    HWY_ALIGN float xyz[3 * kBatch];
    HWY_ALIGN uint32_t payload[kBatch];
    int n = 0;
    uint64_t added = 0;
  };
  std::vector<ViewRows> rows;
  bool reversed = false;
  ProjectFn project = nullptr;
  tbb::enumerable_thread_specific<Batch> batches;

  void write(Batch& b) {
    HWY_ALIGN uint32_t offsets[kBatch];
    HWY_ALIGN uint32_t depths[kBatch];
    for (const ViewRows& r : rows) {
      project(b.xyz, b.n, r, reversed, offsets, depths);
      scatter<true>(r.keys, offsets, depths, b.payload, 0, b.n);
    }
    b.n = 0;
  }
};

PointSplatter::PointSplatter(std::span<const SplatView> views, DepthKey key, int64_t simd) : state_(new State) {
  state_->project = projectFor(simd);
  for (size_t v = 0; v < views.size(); ++v) {
    const Image<uint64_t>* t = views[v].target;
    if (!t || t->width() < 1 || t->height() < 1 || t->width() > kMaxTargetSize || t->height() > kMaxTargetSize) {
      delete state_;
      throw std::invalid_argument("PointSplatter: view " + std::to_string(v) + " needs a target of 1 to " +
                                  std::to_string(kMaxTargetSize) + " pixels a side");
    }
    state_->rows.push_back(viewRows(views[v]));
  }
  state_->reversed = key == DepthKey::ReversedZOverW;
}

PointSplatter::~PointSplatter() { delete state_; }

void PointSplatter::add(glm::vec3 p, uint32_t payload) {
  State::Batch& b = state_->batches.local();
  b.xyz[3 * b.n] = p.x;
  b.xyz[3 * b.n + 1] = p.y;
  b.xyz[3 * b.n + 2] = p.z;
  b.payload[b.n] = payload;
  ++b.added;
  if (++b.n == kBatch) state_->write(b);
}

void PointSplatter::flush() {
  for (State::Batch& b : state_->batches)
    if (b.n > 0) state_->write(b);
}

uint64_t PointSplatter::points() const {
  uint64_t n = 0;
  for (const State::Batch& b : state_->batches) n += b.added;
  return n;
}

void resolveDepth(const Image<uint64_t>& keys, DepthKey key, ImageFloat& depth, float emptyValue) {
  depth.resize(keys.width(), keys.height());
  const int w = keys.width();
  forRows(keys.height(), [&](int y) {
    const uint64_t* k = keys.row(y);
    float* d = depth.row(y);
    for (int x = 0; x < w; ++x) {
      const uint32_t hi = static_cast<uint32_t>(k[x] >> 32);
      const uint32_t bits = key == DepthKey::ZOverW ? hi : kOneBits - hi;
      d[x] = k[x] == kEmptyKey ? emptyValue : std::bit_cast<float>(bits);
    }
  });
}

void resolvePayload(const Image<uint64_t>& keys, Image<uint32_t>& payload, uint32_t emptyValue) {
  payload.resize(keys.width(), keys.height());
  const int w = keys.width();
  forRows(keys.height(), [&](int y) {
    const uint64_t* k = keys.row(y);
    uint32_t* p = payload.row(y);
    for (int x = 0; x < w; ++x) p[x] = k[x] == kEmptyKey ? emptyValue : static_cast<uint32_t>(k[x]);
  });
}

void resolveColor(const Image<uint64_t>& keys, ImageRgba8& color, Rgba8 background) {
  color.resize(keys.width(), keys.height());
  const int w = keys.width();
  forRows(keys.height(), [&](int y) {
    const uint64_t* k = keys.row(y);
    Rgba8* c = color.row(y);
    for (int x = 0; x < w; ++x) c[x] = k[x] == kEmptyKey ? background : unpackRgba8(static_cast<uint32_t>(k[x]));
  });
}

}  // namespace penumbra::raster
#endif  // HWY_ONCE
