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
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/mat4x4.hpp>

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

// A view of the depth splat: the projection's rows and the target's depth bits.
struct DepthRows {
  ViewRows r;
  uint32_t* bits;
};

// A batch of surfels, coordinate by coordinate: n of them, each array readable up to n rounded up
// to the widest vector (SurfelArrays pads them).
struct SurfelBatch {
  const float *px, *py, *pz, *ux, *uy, *uz, *vx, *vy, *vz;
  int n;
};

// Half the side of a surfel's footprint in its own coordinates, with the margin that closes the
// cracks between linearized neighbours (splat.h).
constexpr float kSurfelHalf = 0.5f + 1.0f / 64.0f;

// texel = nearest(texel, bits): max for reversed depth (kMax), min otherwise; atomically (a read
// first: a write that loses costs no locked instruction) unless on one thread.
template <bool kMax>
inline void depthWrite(uint32_t& slot, uint32_t bits, bool atomic) {
  if (atomic) {
    std::atomic_ref<uint32_t> a(slot);
    uint32_t cur = a.load(std::memory_order_relaxed);
    while ((kMax ? bits > cur : bits < cur) && !a.compare_exchange_weak(cur, bits, std::memory_order_relaxed)) {
    }
  } else {
    slot = kMax ? std::max(slot, bits) : std::min(slot, bits);
  }
}

}  // namespace penumbra::raster::splat_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using namespace splat_detail;

// The projection of splat.h's conventions for a vector of points at a time, the view's constants in
// registers: clip position, screen position, the tests, the pixel's offset and d = z / w.
struct Projector {
  using DF = hn::ScalableTag<float>;
  using DI = hn::RebindToSigned<DF>;
  using DU = hn::RebindToUnsigned<DF>;
  using VF = hn::Vec<DF>;
  DF df;
  DI di;
  DU du;
  VF x0, x1, x2, x3, y0, y1, y2, y3, z0, z1, z2, z3, w0, w1, w2, w3, width, height, zero, half, maxFinite;
  hn::Vec<DI> stride;
  HWY_ALIGN float tail[3 * HWY_MAX_BYTES / sizeof(float)];

  explicit Projector(const ViewRows& v)
      : x0(hn::Set(df, v.x[0])), x1(hn::Set(df, v.x[1])), x2(hn::Set(df, v.x[2])), x3(hn::Set(df, v.x[3])),
        y0(hn::Set(df, v.y[0])), y1(hn::Set(df, v.y[1])), y2(hn::Set(df, v.y[2])), y3(hn::Set(df, v.y[3])),
        z0(hn::Set(df, v.z[0])), z1(hn::Set(df, v.z[1])), z2(hn::Set(df, v.z[2])), z3(hn::Set(df, v.z[3])),
        w0(hn::Set(df, v.w[0])), w1(hn::Set(df, v.w[1])), w2(hn::Set(df, v.w[2])), w3(hn::Set(df, v.w[3])),
        width(hn::Set(df, v.width)), height(hn::Set(df, v.height)), zero(hn::Zero(df)), half(hn::Set(df, 0.5f)),
        maxFinite(hn::Set(df, std::numeric_limits<float>::max())), stride(hn::Set(di, v.stride)) {}

  int lanes() const { return static_cast<int>(hn::Lanes(df)); }

  struct Lanes {
    hn::Mask<DF> ok;
    hn::Vec<DI> ix, iy;
    hn::Vec<DU> offset;  // y * stride + x, 0 where culled
    hn::Vec<DU> depth;   // bits of d = z / w, -0 as +0
  };

  // Points [i, i + lanes) of xyz (3 n floats; past n: culled).
  Lanes at(const float* xyz, int i, int n) {
    VF px, py, pz;
    const auto valid = hn::FirstN(df, static_cast<size_t>(n - i));
    if (i + lanes() <= n) {
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
    Lanes l;
    l.ok = ok;
    // Kept lanes have 0 <= sx < width <= 16384: truncation is floor and is exact. Culled lanes are
    // zeroed first (their sx may be NaN or huge).
    l.ix = hn::ConvertTo(di, hn::IfThenElseZero(ok, sx));
    l.iy = hn::ConvertTo(di, hn::IfThenElseZero(ok, sy));
    l.offset = hn::IfThenElseZero(hn::RebindMask(du, ok), hn::BitCast(du, hn::Add(hn::Mul(l.iy, stride), l.ix)));
    // d = z / w in [-0, 1] when kept; clearing the sign bit maps -0 to +0.
    l.depth = hn::And(hn::BitCast(du, hn::Div(cz, cw)), hn::Set(du, 0x7FFFFFFFu));
    return l;
  }
};

// Projects points [0, n) (xyz: 3 n floats, n <= kBatch) into view v: offsets[i] = y * stride + x
// of the pixel and depths[i] = the depth key, or offset 0 and kCulled. Returns the kept count.
uint32_t ProjectBatch(const float* xyz, int n, const ViewRows& v, bool reversed, uint32_t* offsets, uint32_t* depths) {
  Projector p(v);
  const auto one = hn::Set(p.du, kOneBits), culled = hn::Set(p.du, kCulled);
  uint32_t kept = 0;
  for (int i = 0; i < n; i += p.lanes()) {
    const Projector::Lanes l = p.at(xyz, i, n);
    const auto depth = reversed ? hn::Sub(one, l.depth) : l.depth;
    hn::StoreU(l.offset, p.du, offsets + i);
    hn::StoreU(hn::IfThenElse(hn::RebindMask(p.du, l.ok), depth, culled), p.du, depths + i);
    kept += static_cast<uint32_t>(hn::CountTrue(p.df, l.ok));
  }
  return kept;
}

// The depth splat's projection (splat.h, "Depth-only splatting"): ProjectBatch's, the bits of
// d = z / w as they are. rect (x0, y0, x1, y1) grows to hold every kept texel.
uint32_t ProjectDepthBatch(const float* xyz, int n, const DepthRows& dv, uint32_t* offsets, uint32_t* depths,
                           int32_t* rect) {
  Projector p(dv.r);
  const auto culled = hn::Set(p.du, kCulled);
  auto minX = hn::Set(p.di, rect[0]), minY = hn::Set(p.di, rect[1]);
  auto maxX = hn::Set(p.di, rect[2] - 1), maxY = hn::Set(p.di, rect[3] - 1);
  const auto big = hn::Set(p.di, std::numeric_limits<int32_t>::max()), none = hn::Set(p.di, -1);
  uint32_t kept = 0;
  for (int i = 0; i < n; i += p.lanes()) {
    const Projector::Lanes l = p.at(xyz, i, n);
    const auto oki = hn::RebindMask(p.di, l.ok);
    hn::StoreU(l.offset, p.du, offsets + i);
    hn::StoreU(hn::IfThenElse(hn::RebindMask(p.du, l.ok), l.depth, culled), p.du, depths + i);
    minX = hn::Min(minX, hn::IfThenElse(oki, l.ix, big)), minY = hn::Min(minY, hn::IfThenElse(oki, l.iy, big));
    maxX = hn::Max(maxX, hn::IfThenElse(oki, l.ix, none)), maxY = hn::Max(maxY, hn::IfThenElse(oki, l.iy, none));
    kept += static_cast<uint32_t>(hn::CountTrue(p.df, l.ok));
  }
  rect[0] = hn::GetLane(hn::MinOfLanes(p.di, minX));
  rect[1] = hn::GetLane(hn::MinOfLanes(p.di, minY));
  rect[2] = hn::GetLane(hn::MaxOfLanes(p.di, maxX)) + 1;
  rect[3] = hn::GetLane(hn::MaxOfLanes(p.di, maxY)) + 1;
  return kept;
}

// One surfel candidate centre (x, y), scalar: splat.h's coverage and depth, the operations of the
// SIMD pass below. Returns the depth bits, or kCulled when the centre is not covered.
inline uint32_t surfelCandidate(int x, int y, float sx, float sy, float d, float m00, float m01, float m10, float m11,
                                float du, float dv) {
  const float qx = (static_cast<float>(x) + 0.5f) - sx, qy = (static_cast<float>(y) + 0.5f) - sy;
  const float a = m00 * qx + m01 * qy, b = m10 * qx + m11 * qy;
  float dc = d + (a * du + b * dv);
  if (!(std::abs(a) <= kSurfelHalf && std::abs(b) <= kSurfelHalf) || std::isnan(dc)) return kCulled;
  const float lo = d * 0.5f, twice = d * 2.0f, hi = twice < 1.0f ? twice : 1.0f;
  dc = dc < lo ? lo : dc;
  dc = dc > hi ? hi : dc;
  return std::bit_cast<uint32_t>(dc) & 0x7FFFFFFFu;
}

// Surfels (splat.h): per vector of lanes the point's projection and tests (ProjectDepthBatch's
// operations), its footprint's screen edges, their inverse and depth steps, and its box of candidate
// centres; the first 2 x 2 centres of every lane's box in SIMD (a footprint up to about a texel has
// no more), into offsets / depths (kCulled: not covered) that are then written; the rest of larger
// boxes one by one. rect grows to hold every texel written. Returns the surfels that passed the
// point tests.
uint32_t SplatSurfelBatch(const SurfelBatch& b, const DepthRows& dv, bool reversed, bool atomic, int32_t* rect) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::RebindToUnsigned<decltype(df)> du;
  using VF = hn::Vec<decltype(df)>;
  const ViewRows& v = dv.r;
  const int N = static_cast<int>(hn::Lanes(df));
  const auto S = [&](float x) { return hn::Set(df, x); };
  const auto zero = hn::Zero(df), half = S(0.5f), one = S(1.0f), two = S(2.0f), maxFinite = S(std::numeric_limits<float>::max());
  const auto width = S(v.width), height = S(v.height);
  const auto halfW = S(0.5f * v.width), negHalfH = S(-0.5f * v.height), h = S(kSurfelHalf);
  const auto reach = S(static_cast<float>(kMaxSurfelReach));
  const auto R = hn::Set(di, kMaxSurfelReach), oneI = hn::Set(di, 1);
  const auto lastX = hn::Set(di, static_cast<int32_t>(v.width) - 1), lastY = hn::Set(di, static_cast<int32_t>(v.height) - 1);
  const auto stride = hn::Set(di, v.stride);
  const auto signMask = hn::Set(du, 0x7FFFFFFFu);
  const auto big = hn::Set(di, std::numeric_limits<int32_t>::max()), none = hn::Set(di, -1);
  auto minX = hn::Set(di, rect[0] < rect[2] ? rect[0] : INT32_MAX), minY = hn::Set(di, rect[0] < rect[2] ? rect[1] : INT32_MAX);
  auto maxX = hn::Set(di, rect[0] < rect[2] ? rect[2] - 1 : -1), maxY = hn::Set(di, rect[0] < rect[2] ? rect[3] - 1 : -1);
  constexpr int kLanes = HWY_MAX_BYTES / 4;
  HWY_ALIGN uint32_t offsets[kLanes], depths[kLanes];
  HWY_ALIGN float Lsx[kLanes], Lsy[kLanes], Ld[kLanes], L00[kLanes], L01[kLanes], L10[kLanes], L11[kLanes];
  HWY_ALIGN float Ldu[kLanes], Ldv[kLanes];
  HWY_ALIGN int32_t Li0[kLanes], Li1[kLanes], Lj0[kLanes], Lj1[kLanes], Lbig[kLanes];
  uint32_t kept = 0;
  const auto write = [&](uint32_t offset, uint32_t bits) {
    reversed ? depthWrite<true>(dv.bits[offset], bits, atomic) : depthWrite<false>(dv.bits[offset], bits, atomic);
  };
  for (int i = 0; i < b.n; i += N) {
    const auto px = hn::LoadU(df, b.px + i), py = hn::LoadU(df, b.py + i), pz = hn::LoadU(df, b.pz + i);
    const auto row = [&](const float* m, VF x, VF y, VF z) {
      return hn::Add(hn::Add(hn::Mul(S(m[0]), x), hn::Mul(S(m[1]), y)), hn::Add(hn::Mul(S(m[2]), z), S(m[3])));
    };
    const auto lin = [&](const float* m, VF x, VF y, VF z) {
      return hn::Add(hn::Add(hn::Mul(S(m[0]), x), hn::Mul(S(m[1]), y)), hn::Mul(S(m[2]), z));
    };
    const auto cx = row(v.x, px, py, pz), cy = row(v.y, px, py, pz), cz = row(v.z, px, py, pz), cw = row(v.w, px, py, pz);
    const auto X = hn::Div(cx, cw), Y = hn::Div(cy, cw), d = hn::Div(cz, cw);
    const auto sx = hn::Mul(hn::Add(hn::Mul(X, half), half), width);
    const auto sy = hn::Mul(hn::Sub(half, hn::Mul(Y, half)), height);
    auto ok = hn::And(hn::FirstN(df, static_cast<size_t>(b.n - i)), hn::And(hn::Gt(cw, zero), hn::Le(cw, maxFinite)));
    ok = hn::And(ok, hn::And(hn::Ge(cz, zero), hn::Le(cz, cw)));
    // Within reach of the view: a footprint whose centre lies just outside covers its border texels.
    ok = hn::And(ok, hn::And(hn::Ge(sx, hn::Neg(reach)), hn::Lt(sx, hn::Add(width, reach))));
    ok = hn::And(ok, hn::And(hn::Ge(sy, hn::Neg(reach)), hn::Lt(sy, hn::Add(height, reach))));
    kept += static_cast<uint32_t>(hn::CountTrue(df, ok));
    if (hn::AllFalse(df, ok)) continue;
    const auto k = hn::Div(one, cw);
    // Screen edges and depth steps of u and v.
    const auto ux = hn::LoadU(df, b.ux + i), uy = hn::LoadU(df, b.uy + i), uz = hn::LoadU(df, b.uz + i);
    const auto vx = hn::LoadU(df, b.vx + i), vy = hn::LoadU(df, b.vy + i), vz = hn::LoadU(df, b.vz + i);
    const auto ruw = lin(v.w, ux, uy, uz), rvw = lin(v.w, vx, vy, vz);
    const auto Ax = hn::Mul(halfW, hn::Mul(hn::Sub(lin(v.x, ux, uy, uz), hn::Mul(X, ruw)), k));
    const auto Ay = hn::Mul(negHalfH, hn::Mul(hn::Sub(lin(v.y, ux, uy, uz), hn::Mul(Y, ruw)), k));
    const auto Bx = hn::Mul(halfW, hn::Mul(hn::Sub(lin(v.x, vx, vy, vz), hn::Mul(X, rvw)), k));
    const auto By = hn::Mul(negHalfH, hn::Mul(hn::Sub(lin(v.y, vx, vy, vz), hn::Mul(Y, rvw)), k));
    const auto Du = hn::Mul(hn::Sub(lin(v.z, ux, uy, uz), hn::Mul(d, ruw)), k);
    const auto Dv = hn::Mul(hn::Sub(lin(v.z, vx, vy, vz), hn::Mul(d, rvw)), k);
    const auto inv = hn::Div(one, hn::Sub(hn::Mul(Ax, By), hn::Mul(Ay, Bx)));
    const auto m00 = hn::Mul(By, inv), m01 = hn::Neg(hn::Mul(Bx, inv));
    const auto m10 = hn::Neg(hn::Mul(Ay, inv)), m11 = hn::Mul(Ax, inv);
    // The box of candidate centres: s +- (|A| + |B|) h per axis, at most `reach` (NaN: reach).
    auto ex = hn::Mul(hn::Add(hn::Abs(Ax), hn::Abs(Bx)), h), ey = hn::Mul(hn::Add(hn::Abs(Ay), hn::Abs(By)), h);
    ex = hn::IfThenElse(hn::Le(ex, reach), ex, reach), ey = hn::IfThenElse(hn::Le(ey, reach), ey, reach);
    const auto sxk = hn::IfThenElseZero(ok, sx), syk = hn::IfThenElseZero(ok, sy);
    const auto ix = hn::ConvertTo(di, hn::Floor(sxk)), iy = hn::ConvertTo(di, hn::Floor(syk));
    auto i0 = hn::ConvertTo(di, hn::Ceil(hn::Sub(hn::Sub(sxk, ex), half)));
    auto i1 = hn::ConvertTo(di, hn::Floor(hn::Sub(hn::Add(sxk, ex), half)));
    auto j0 = hn::ConvertTo(di, hn::Ceil(hn::Sub(hn::Sub(syk, ey), half)));
    auto j1 = hn::ConvertTo(di, hn::Floor(hn::Sub(hn::Add(syk, ey), half)));
    i0 = hn::Max(i0, hn::Max(hn::Zero(di), hn::Sub(ix, R))), i1 = hn::Min(i1, hn::Min(lastX, hn::Add(ix, R)));
    j0 = hn::Max(j0, hn::Max(hn::Zero(di), hn::Sub(iy, R))), j1 = hn::Min(j1, hn::Min(lastY, hn::Add(iy, R)));
    const auto okI = hn::RebindMask(di, ok);
    const auto lo = hn::Mul(d, half), twice = hn::Mul(d, two);
    const auto hi = hn::IfThenElse(hn::Lt(twice, one), twice, one);
    // The box's first 2 x 2 centres, lanes at once (a second column or row only where some lane's
    // box has one: boxes of footprints under half a texel hold one centre at most).
    const bool twoColumns = !hn::AllFalse(di, hn::And(okI, hn::Gt(i1, i0)));
    const bool twoRows = !hn::AllFalse(di, hn::And(okI, hn::Gt(j1, j0)));
    for (int c = 0; c < 4; ++c) {
      if (((c & 1) && !twoColumns) || ((c >> 1) && !twoRows)) continue;
      const auto x = hn::Add(i0, hn::Set(di, c & 1)), y = hn::Add(j0, hn::Set(di, c >> 1));
      const auto qx = hn::Sub(hn::Add(hn::ConvertTo(df, x), half), sx);
      const auto qy = hn::Sub(hn::Add(hn::ConvertTo(df, y), half), sy);
      const auto a = hn::Add(hn::Mul(m00, qx), hn::Mul(m01, qy)), bb = hn::Add(hn::Mul(m10, qx), hn::Mul(m11, qy));
      auto dc = hn::Add(d, hn::Add(hn::Mul(a, Du), hn::Mul(bb, Dv)));
      auto cover = hn::And(hn::Le(hn::Abs(a), h), hn::Le(hn::Abs(bb), h));
      cover = hn::AndNot(hn::IsNaN(dc), cover);
      const auto inBox = hn::AndNot(hn::Or(hn::Gt(x, i1), hn::Gt(y, j1)), okI);
      const auto coverI = hn::And(inBox, hn::RebindMask(di, cover));
      dc = hn::IfThenElse(hn::Lt(dc, lo), lo, dc);
      dc = hn::IfThenElse(hn::Gt(dc, hi), hi, dc);
      // The covered lanes' texels, one by one through the mask's bits.
      hn::Store(hn::BitCast(du, hn::Add(hn::Mul(y, stride), x)), du, offsets);
      hn::Store(hn::And(hn::BitCast(du, dc), signMask), du, depths);
      uint8_t maskBits[8] = {};
      hn::StoreMaskBits(di, coverI, maskBits);
      uint64_t covered = 0;
      std::memcpy(&covered, maskBits, sizeof(covered));
      for (; covered != 0; covered &= covered - 1) {
        const int l = std::countr_zero(covered);
        write(offsets[l], depths[l]);
      }
      minX = hn::Min(minX, hn::IfThenElse(coverI, x, big)), minY = hn::Min(minY, hn::IfThenElse(coverI, y, big));
      maxX = hn::Max(maxX, hn::IfThenElse(coverI, x, none)), maxY = hn::Max(maxY, hn::IfThenElse(coverI, y, none));
    }
    // Boxes wider than 2 texels: their other centres one by one.
    const auto wide = hn::And(okI, hn::Or(hn::Gt(hn::Sub(i1, i0), oneI), hn::Gt(hn::Sub(j1, j0), oneI)));
    if (hn::AllFalse(di, wide)) continue;
    hn::Store(hn::VecFromMask(di, wide), di, Lbig);
    hn::Store(sx, df, Lsx), hn::Store(sy, df, Lsy), hn::Store(d, df, Ld);
    hn::Store(m00, df, L00), hn::Store(m01, df, L01), hn::Store(m10, df, L10), hn::Store(m11, df, L11);
    hn::Store(Du, df, Ldu), hn::Store(Dv, df, Ldv);
    hn::Store(i0, di, Li0), hn::Store(i1, di, Li1), hn::Store(j0, di, Lj0), hn::Store(j1, di, Lj1);
    for (int l = 0; l < N; ++l) {
      if (!Lbig[l]) continue;
      for (int y = Lj0[l]; y <= Lj1[l]; ++y)
        for (int x = Li0[l]; x <= Li1[l]; ++x) {
          if (x - Li0[l] < 2 && y - Lj0[l] < 2) continue;  // done in SIMD
          const uint32_t bits = surfelCandidate(x, y, Lsx[l], Lsy[l], Ld[l], L00[l], L01[l], L10[l], L11[l], Ldu[l], Ldv[l]);
          if (bits == kCulled) continue;
          write(static_cast<uint32_t>(y * v.stride + x), bits);
          minX = hn::Min(minX, hn::Set(di, x)), minY = hn::Min(minY, hn::Set(di, y));
          maxX = hn::Max(maxX, hn::Set(di, x)), maxY = hn::Max(maxY, hn::Set(di, y));
        }
    }
  }
  const int32_t x0 = hn::GetLane(hn::MinOfLanes(di, minX)), x1 = hn::GetLane(hn::MaxOfLanes(di, maxX)) + 1;
  if (x0 < x1) {
    rect[0] = x0, rect[1] = hn::GetLane(hn::MinOfLanes(di, minY));
    rect[2] = x1, rect[3] = hn::GetLane(hn::MaxOfLanes(di, maxY)) + 1;
  }
  return kept;
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::raster {
HWY_EXPORT(ProjectBatch);
HWY_EXPORT(ProjectDepthBatch);
HWY_EXPORT(SplatSurfelBatch);

namespace {

using ProjectFn = std::remove_cvref_t<decltype(HWY_DISPATCH_TABLE(ProjectBatch)[0])>;
using ProjectDepthFn = std::remove_cvref_t<decltype(HWY_DISPATCH_TABLE(ProjectDepthBatch)[0])>;

// The projection of the SIMD target asked for (simd.h).
ProjectFn projectFor(int64_t simd) {
  ProjectFn fn = HWY_DISPATCH_TABLE(ProjectBatch)[simdDispatchIndex(simd)];
  return fn ? fn : HWY_DISPATCH_TABLE(ProjectBatch)[0];
}
ProjectDepthFn projectDepthFor(int64_t simd) {
  ProjectDepthFn fn = HWY_DISPATCH_TABLE(ProjectDepthBatch)[simdDispatchIndex(simd)];
  return fn ? fn : HWY_DISPATCH_TABLE(ProjectDepthBatch)[0];
}
using SurfelFn = std::remove_cvref_t<decltype(HWY_DISPATCH_TABLE(SplatSurfelBatch)[0])>;
SurfelFn surfelFor(int64_t simd) {
  SurfelFn fn = HWY_DISPATCH_TABLE(SplatSurfelBatch)[simdDispatchIndex(simd)];
  return fn ? fn : HWY_DISPATCH_TABLE(SplatSurfelBatch)[0];
}
using namespace splat_detail;

constexpr uint32_t kExpMask = 0x7F800000u;  // exponent all ones: Inf or NaN

// A view's matrix by rows and its target's size (keys: null; splatPoints sets them).
ViewRows viewRows(const SplatView& v, int width, int height, int stride) {
  ViewRows r;
  for (int c = 0; c < 4; ++c) {  // glm is column-major: m[c][r] is column c, row r
    r.x[c] = v.viewProj[c][0];
    r.y[c] = v.viewProj[c][1];
    r.z[c] = v.viewProj[c][2];
    r.w[c] = v.viewProj[c][3];
  }
  r.width = static_cast<float>(width);
  r.height = static_cast<float>(height);
  r.stride = stride;
  r.keys = v.target ? v.target->data() : nullptr;
  return r;
}
ViewRows viewRows(const SplatView& v) { return viewRows(v, v.target->width(), v.target->height(), v.target->stride()); }

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

// The depth splat's writes of one projected batch (kCulled: skipped), with the target line of a
// later point prefetched.
template <bool kMax>
void scatterDepth(uint32_t* target, const uint32_t* offsets, const uint32_t* depths, int n, bool atomic) {
  for (int i = 0; i < n; ++i) {
    if (i + kPrefetch < n) __builtin_prefetch(target + offsets[i + kPrefetch], 1);
    if (depths[i] != kCulled) depthWrite<kMax>(target[offsets[i]], depths[i], atomic);
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

namespace {

// The views of a depth splat as the projection reads them; throws for a bad target.
std::vector<DepthRows> depthRows(std::span<const DepthSplatView> views, const char* who) {
  std::vector<DepthRows> rows(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    Image<uint32_t>* t = views[v].target;
    if (!t || t->width() < 1 || t->height() < 1 || t->width() > kMaxTargetSize || t->height() > kMaxTargetSize)
      throw std::invalid_argument(std::string(who) + ": view " + std::to_string(v) + " needs a target of 1 to " +
                                  std::to_string(kMaxTargetSize) + " pixels a side");
    rows[v].r = viewRows(SplatView{views[v].viewProj, nullptr}, t->width(), t->height(), t->stride());
    rows[v].bits = t->data();
  }
  return rows;
}

// The kernels of one call: the SIMD target's projection and surfel splat, the depth direction.
struct DepthKernels {
  ProjectDepthFn project;
  SurfelFn surfel;
  bool reversed;
};

// Surfels coordinate by coordinate (SurfelBatch's arrays), each array padded with zeros to a
// multiple of kBatch.
struct SurfelArrays {
  std::vector<float> c[9];  // px, py, pz, ux, uy, uz, vx, vy, vz

  void fill(const glm::vec3* p, const SurfelAxes* a, size_t n) {
    const size_t padded = (n + kBatch - 1) / kBatch * kBatch;
    for (std::vector<float>& v : c) v.assign(padded, 0.0f);
    for (size_t i = 0; i < n; ++i) {
      c[0][i] = p[i].x, c[1][i] = p[i].y, c[2][i] = p[i].z;
      c[3][i] = a[i].u.x, c[4][i] = a[i].u.y, c[5][i] = a[i].u.z;
      c[6][i] = a[i].v.x, c[7][i] = a[i].v.y, c[8][i] = a[i].v.z;
    }
  }
  SurfelBatch batch(size_t first, int n) const {
    return {c[0].data() + first, c[1].data() + first, c[2].data() + first, c[3].data() + first, c[4].data() + first,
            c[5].data() + first, c[6].data() + first, c[7].data() + first, c[8].data() + first, n};
  }
};

// One batch into one view: points (xyz, n of them) or surfels (sb); grows the view's rectangle and
// the count of points that passed the tests.
void splatBatchInto(const DepthKernels& kn, const float* xyz, const SurfelBatch* sb, int n, const DepthRows& row,
                    bool atomic, SplatRect& rect, uint64_t& written) {
  int32_t box[4] = {rect.empty() ? INT32_MAX : rect.x0, rect.empty() ? INT32_MAX : rect.y0, rect.empty() ? 0 : rect.x1,
                    rect.empty() ? 0 : rect.y1};
  if (sb) {
    written += kn.surfel(*sb, row, kn.reversed, atomic, box);
  } else {
    HWY_ALIGN uint32_t offsets[kBatch];
    HWY_ALIGN uint32_t depths[kBatch];
    written += kn.project(xyz, n, row, offsets, depths, box);
    kn.reversed ? scatterDepth<true>(row.bits, offsets, depths, n, atomic)
                : scatterDepth<false>(row.bits, offsets, depths, n, atomic);
  }
  if (box[0] < box[2]) rect = {box[0], box[1], box[2], box[3]};
}

// Clouds up to this many bytes (positions, and surfel axes) are splatted view by view: one task per
// view of a pass walks every point and is the only writer of its map (no atomics), the cloud read
// again from the last-level cache for every view. Larger clouds go chunk by chunk, each chunk's
// batches into every view of the pass while in L1, atomically.
constexpr size_t kViewMajorBytes = size_t{4} << 20;

}  // namespace

SplatStats splatDepth(std::span<const glm::vec3> points, std::span<const SurfelAxes> surfels,
                      std::span<const DepthSplatView> views, DepthKey key, int viewsPerPass, int64_t simd,
                      std::span<SplatRect> touched) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points are read as packed xyz floats");
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = points.size(), m = views.size();
  if (!surfels.empty() && surfels.size() != n)
    throw std::invalid_argument("splatDepth: " + std::to_string(surfels.size()) + " surfel axes for " +
                                std::to_string(n) + " points (give one per point, or none)");
  if (!touched.empty() && touched.size() != m)
    throw std::invalid_argument("splatDepth: " + std::to_string(touched.size()) + " touched rectangles for " +
                                std::to_string(m) + " views");
  if (viewsPerPass < 0 || static_cast<size_t>(viewsPerPass) > m)
    throw std::invalid_argument("splatDepth: viewsPerPass " + std::to_string(viewsPerPass) + " outside [0, " +
                                std::to_string(m) + "]");
  const std::vector<DepthRows> rows = depthRows(views, "splatDepth");
  SplatStats stats;
  stats.points = n;
  stats.views = m;
  for (SplatRect& r : touched) r = {};
  if (n > 0 && m > 0) {
    const DepthKernels kn{projectDepthFor(simd), surfelFor(simd), key == DepthKey::ReversedZOverW};
    const bool withSurfels = !surfels.empty();
    SurfelArrays soa;  // transposed once for every view
    if (withSurfels) soa.fill(points.data(), surfels.data(), n);
    const size_t k = viewsPerPass == 0 ? m : static_cast<size_t>(viewsPerPass);
    const size_t chunks = (n + kSplatChunk - 1) / kSplatChunk;
    bool sharedTargets = false;  // then a view's task is not its map's only writer
    for (size_t a = 0; a < m && !sharedTargets; ++a)
      for (size_t b = a + 1; b < m && !sharedTargets; ++b) sharedTargets = views[a].target == views[b].target;
    const bool viewMajor = n * (sizeof(glm::vec3) + (withSurfels ? sizeof(SurfelAxes) : 0)) <= kViewMajorBytes;
    const bool atomic = tbb::this_task_arena::max_concurrency() > 1 && (!viewMajor || sharedTargets);
    std::vector<ChunkCounts> counts(chunks);
    std::vector<SplatRect> rects(chunks * m);  // per chunk and view: the texels it wrote
    for (size_t v0 = 0; v0 < m; v0 += k) {
      const size_t v1 = std::min(m, v0 + k);
      if (viewMajor) {
        tbb::parallel_for(v0, v1, [&](size_t v) {
          uint64_t written = 0;
          for (size_t b = 0; b < n; b += kBatch) {
            const int cnt = static_cast<int>(std::min<size_t>(kBatch, n - b));
            const SurfelBatch sb = soa.batch(b, cnt);
            splatBatchInto(kn, &points[b].x, withSurfels ? &sb : nullptr, cnt, rows[v], atomic, rects[v], written);
          }
          std::atomic_ref<uint64_t>(counts[0].written).fetch_add(written, std::memory_order_relaxed);
        });
      } else {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks, 1), [&](const tbb::blocked_range<size_t>& tr) {
          for (size_t c = tr.begin(); c != tr.end(); ++c) {
            const size_t begin = c * kSplatChunk, end = std::min(n, begin + kSplatChunk);
            for (size_t b = begin; b < end; b += kBatch) {
              const int cnt = static_cast<int>(std::min<size_t>(kBatch, end - b));
              const SurfelBatch sb = soa.batch(b, cnt);
              for (size_t v = v0; v < v1; ++v)
                splatBatchInto(kn, &points[b].x, withSurfels ? &sb : nullptr, cnt, rows[v], atomic, rects[c * m + v],
                               counts[c].written);
            }
          }
        });
      }
      ++stats.passes;
    }
    for (size_t c = 0; c < chunks; ++c) {
      stats.written += counts[c].written;
      stats.nonFinite += countNonFinite(points.data() + c * kSplatChunk, std::min(n, (c + 1) * kSplatChunk) - c * kSplatChunk);
    }
    if (!touched.empty())
      for (size_t c = 0; c < chunks; ++c)
        for (size_t v = 0; v < m; ++v) touched[v].add(rects[c * m + v]);
  }
  stats.culled = static_cast<uint64_t>(n) * m - stats.written;
  stats.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

struct DepthSplatter::State {
  struct Batch {
    HWY_ALIGN float xyz[3 * kBatch];
    SurfelAxes axes[kBatch];
    SurfelArrays soa;
    int n = 0;
    uint64_t added = 0, written = 0;
    std::vector<SplatRect> rects;  // per view
  };
  std::vector<DepthRows> rows;
  bool surfels = false;
  DepthKernels kn{};
  tbb::enumerable_thread_specific<Batch> batches;
  std::vector<SplatRect> touched;

  void write(Batch& b) {
    b.rects.resize(rows.size());
    std::vector<glm::vec3> p(static_cast<size_t>(b.n));
    std::memcpy(p.data(), b.xyz, p.size() * sizeof(glm::vec3));
    if (surfels) b.soa.fill(p.data(), b.axes, p.size());
    const SurfelBatch sb = surfels ? b.soa.batch(0, b.n) : SurfelBatch{};
    for (size_t v = 0; v < rows.size(); ++v)
      splatBatchInto(kn, b.xyz, surfels ? &sb : nullptr, b.n, rows[v], true, b.rects[v], b.written);
    b.n = 0;
  }
};

DepthSplatter::DepthSplatter(std::span<const DepthSplatView> views, DepthKey key, bool surfels, int64_t simd)
    : state_(new State) {
  try {
    state_->rows = depthRows(views, "DepthSplatter");
  } catch (...) {
    delete state_;
    throw;
  }
  state_->kn = {projectDepthFor(simd), surfelFor(simd), key == DepthKey::ReversedZOverW};
  state_->surfels = surfels;
  state_->touched.assign(views.size(), SplatRect{});
}

DepthSplatter::~DepthSplatter() { delete state_; }

void DepthSplatter::add(glm::vec3 p, const SurfelAxes& axes) {
  State::Batch& b = state_->batches.local();
  const size_t i = 3 * static_cast<size_t>(b.n);
  b.xyz[i] = p.x, b.xyz[i + 1] = p.y, b.xyz[i + 2] = p.z;
  b.axes[b.n] = axes;
  ++b.added;
  if (++b.n == kBatch) state_->write(b);
}

void DepthSplatter::flush() {
  for (State::Batch& b : state_->batches) {
    if (b.n > 0) state_->write(b);
    for (size_t v = 0; v < b.rects.size(); ++v) state_->touched[v].add(b.rects[v]);
    b.rects.clear();
  }
}

uint64_t DepthSplatter::points() const {
  uint64_t n = 0;
  for (const State::Batch& b : state_->batches) n += b.added;
  return n;
}

SplatRect DepthSplatter::touched(size_t view) const { return state_->touched.at(view); }

void clearDepthBits(Image<uint32_t>& depth, DepthKey key, const SplatRect* rect) {
  const uint32_t empty = emptyDepthBits(key);
  if (!rect) {
    const size_t stride = static_cast<size_t>(depth.stride());
    forRows(depth.paddedRows(), [&](int y) { std::fill(depth.row(y), depth.row(y) + stride, empty); });
    return;
  }
  const int x0 = std::max(rect->x0, 0), x1 = std::min(rect->x1, depth.width());
  const int y0 = std::max(rect->y0, 0), y1 = std::min(rect->y1, depth.height());
  if (x0 >= x1 || y0 >= y1) return;
  forRows(y1 - y0, [&](int y) { std::fill(depth.row(y0 + y) + x0, depth.row(y0 + y) + x1, empty); });
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
