// SIMD tile rasterization (see tile.h), compiled once per Highway target.
//
// Exact 32-bit lanes. Inside a block that an edge crosses, with E(i, j) = E00 + 256 A i + 256 B j
// at the block's pixel centres (bias included), write E00 = 256 q + r with 0 <= r < 256
// (q = E00 >> 8). Then E(i, j) >= 0  <=>  q + A i + B j >= -r / 256  <=>  q + A i + B j >= 0, as
// the left side is an integer and -r/256 lies in (-1, 0]. Because the edge crosses the block,
// |q| <= 7 (|A| + |B|) + 1 <= 2^28 (|A|, |B| <= 2^24, conventions.h), so q + A i + B j fits in
// int32 exactly. Edges that hold for the whole block are replaced by the constant 0 (always in).
//
// Depth per pixel: z = (z0 + zx dx) + zy dy with dx, dy the integer offsets from the triangle's
// plane origin, clamped to the triangle's [zmin, zmax] — the same expression as depthAt() in
// setup.h, evaluated in the same order without FMA, so every target gives the same bits.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/tile_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <bit>

#include "raster/tile.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

// Counters kept in registers during a tile, added to PassStats once at the end. Every tested block
// ends in exactly one of rejectedEdge, rejectedDepth, accepted and partial, so blocks tested is
// their sum (PassStats::blocksTested), not counted on its own.
struct Counters {
  uint64_t rejectedEdge = 0, rejectedDepth = 0, accepted = 0, partial = 0;
  uint64_t pixelsTested = 0, pixelsCovered = 0, pixelsPassed = 0;

  Counters& operator+=(const Counters& o) {
    rejectedEdge += o.rejectedEdge, rejectedDepth += o.rejectedDepth, accepted += o.accepted,
        partial += o.partial;
    pixelsTested += o.pixelsTested, pixelsCovered += o.pixelsCovered, pixelsPassed += o.pixelsPassed;
    return *this;
  }
};

// Coarse depth: every depth of the triangle is at or behind everything stored in block bi.
template <DepthFunc kFunc>
HWY_INLINE bool hiddenByCoarseDepth(const TileJob& job, const SetupTri& t, size_t bi) {
  return (kFunc == DepthFunc::Less && t.zmin >= job.blockMax[bi]) ||
         (kFunc == DepthFunc::Greater && t.zmax <= job.blockMin[bi]);
}

// One row of up to N lanes: coverage from the three edge vectors (inside when all three >= 0)
// and the column mask, depth from the row's plane values clamped to the triangle's range, early
// depth test and write. Returns the lanes that passed, as the low bits; counts covered lanes.
template <DepthFunc kFunc>
HWY_INLINE uint64_t depthTestRow(const TileJob& job, const SetupTri& t, auto e0, auto e1, auto e2,
                                 auto colMask, auto z, float* drow, size_t& covered) {
  const hn::CappedTag<int32_t, 8> di;
  const hn::Rebind<float, decltype(di)> df;
  const auto inside = hn::Gt(hn::Or(hn::Or(e0, e1), e2), hn::Set(di, -1));
  const auto mf = hn::RebindMask(df, hn::And(colMask, inside));
  z = hn::Min(hn::Max(z, hn::Set(df, t.zmin)), hn::Set(df, t.zmax));
  const auto old = hn::LoadU(df, drow);
  auto pass = mf;
  if constexpr (kFunc == DepthFunc::Less)
    pass = hn::And(pass, hn::Lt(z, old));
  else if constexpr (kFunc == DepthFunc::Greater)
    pass = hn::And(pass, hn::Gt(z, old));
  if (job.depthWrite) hn::StoreU(hn::IfThenElse(pass, z, old), df, drow);
  uint8_t bits[8] = {0};
  hn::StoreMaskBits(df, pass, bits);
  covered += hn::CountTrue(df, mf);
  const size_t n = hn::Lanes(df);
  return uint64_t{bits[0]} & (n >= 8 ? 0xffu : ((1u << n) - 1u));
}

// After a triangle wrote pixels `passMask` of block (bx, by): refresh the coarse depth bound the
// test needs from the block's 64 stored values (padding included), widen the other one
// conservatively, and record the hit for the fragment stage.
template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void finishBlock(const TileJob& job, const SetupTri& t, int bx, int by, uint64_t passMask,
                            uint32_t triIndex) {
  const hn::CappedTag<float, 8> df;
  const int N = static_cast<int>(hn::Lanes(df));
  const size_t bi = static_cast<size_t>(by) * static_cast<size_t>(job.blocksX) + static_cast<size_t>(bx);
  constexpr bool less = kFunc == DepthFunc::Less, greater = kFunc == DepthFunc::Greater;
  if (job.depthWrite) {
    const float* depthBlock = job.depth + static_cast<size_t>(by * kBlockSize) * static_cast<size_t>(job.depthStride) +
                              static_cast<size_t>(bx * kBlockSize);
    if (less || greater) {
      auto v = hn::LoadU(df, depthBlock);
      for (int j = 0; j < kBlockSize; ++j) {
        const float* drow = depthBlock + static_cast<size_t>(j) * static_cast<size_t>(job.depthStride);
        for (int i0 = 0; i0 < kBlockSize; i0 += N)
          v = less ? hn::Max(v, hn::LoadU(df, drow + i0)) : hn::Min(v, hn::LoadU(df, drow + i0));
      }
      if (less) {
        job.blockMax[bi] = hn::GetLane(hn::MaxOfLanes(df, v));
        job.blockMin[bi] = std::min(job.blockMin[bi], t.zmin);
      } else {
        job.blockMin[bi] = hn::GetLane(hn::MinOfLanes(df, v));
        job.blockMax[bi] = std::max(job.blockMax[bi], t.zmax);
      }
    } else {
      job.blockMin[bi] = std::min(job.blockMin[bi], t.zmin);
      job.blockMax[bi] = std::max(job.blockMax[bi], t.zmax);
    }
  }
  if constexpr (kWantHits) {
    job.hits->push_back(BlockHit{triIndex, static_cast<uint16_t>(bx), static_cast<uint16_t>(by), passMask});
  }
}

// One 8x8 block of a triangle: coverage from the exact edge values e[k] at the block's (0, 0)
// pixel (bias included; whole[k]: edge k holds for the whole block), coarse depth, SIMD depth test
// and write. Only rows and columns inside the triangle's bounding box are evaluated.
template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void rasterBlock(const TileJob& job, const SetupTri& t, const EdgeCoefficients& ec, int bx, int by,
                            const int64_t e[3], const bool whole[3], uint32_t triIndex, Counters& c) {
  const hn::CappedTag<int32_t, 8> di;
  const hn::Rebind<float, decltype(di)> df;
  const int N = static_cast<int>(hn::Lanes(di));
  const size_t bi = static_cast<size_t>(by) * static_cast<size_t>(job.blocksX) + static_cast<size_t>(bx);
  if (hiddenByCoarseDepth<kFunc>(job, t, bi)) {
    ++c.rejectedDepth;
    return;
  }
  if (whole[0] && whole[1] && whole[2]) ++c.accepted;
  else ++c.partial;
  const int px0 = bx * kBlockSize, py0 = by * kBlockSize;
  int32_t q[3], sa[3], sb[3];
  for (int k = 0; k < 3; ++k) {
    q[k] = whole[k] ? 0 : static_cast<int32_t>(e[k] >> kSubpixelBits);
    sa[k] = whole[k] ? 0 : ec.a[k];
    sb[k] = whole[k] ? 0 : ec.b[k];
  }
  const int rowBegin = std::max(t.minY - py0, 0), rowEnd = std::min(t.maxY - py0 + 1, kBlockSize);
  const int colBegin = std::max(t.minX - px0, 0), colEnd = std::min(t.maxX - px0 + 1, kBlockSize);
  const auto iota = hn::Iota(di, 0);
  const auto colLo = hn::Set(di, colBegin - 1), colHi = hn::Set(di, colEnd);
  uint64_t passMask = 0;
  size_t covered = 0;
  float* depthBlock = job.depth + static_cast<size_t>(py0) * static_cast<size_t>(job.depthStride) + px0;
  for (int i0 = 0; i0 < kBlockSize; i0 += N) {
    if (i0 >= colEnd || i0 + N <= colBegin) continue;
    const auto lane = hn::Add(iota, hn::Set(di, i0));
    const auto colMask = hn::And(hn::Gt(lane, colLo), hn::Lt(lane, colHi));
    // Edge values at row rowBegin, stepped by B per row.
    auto e0 = hn::Add(hn::Set(di, q[0] + sb[0] * rowBegin), hn::Mul(lane, hn::Set(di, sa[0])));
    auto e1 = hn::Add(hn::Set(di, q[1] + sb[1] * rowBegin), hn::Mul(lane, hn::Set(di, sa[1])));
    auto e2 = hn::Add(hn::Set(di, q[2] + sb[2] * rowBegin), hn::Mul(lane, hn::Set(di, sa[2])));
    const auto b0 = hn::Set(di, sb[0]), b1 = hn::Set(di, sb[1]), b2 = hn::Set(di, sb[2]);
    const auto dx = hn::ConvertTo(df, hn::Add(lane, hn::Set(di, px0 - t.minX)));
    const auto zrow = hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.zx), dx));
    for (int j = rowBegin; j < rowEnd; ++j) {
      float* drow = depthBlock + static_cast<size_t>(j) * static_cast<size_t>(job.depthStride) + i0;
      const auto z = hn::Add(zrow, hn::Set(df, t.zy * static_cast<float>(py0 + j - t.minY)));
      passMask |= depthTestRow<kFunc>(job, t, e0, e1, e2, colMask, z, drow, covered) << (j * kBlockSize + i0);
      e0 = hn::Add(e0, b0);
      e1 = hn::Add(e1, b1);
      e2 = hn::Add(e2, b2);
    }
  }
  c.pixelsTested += static_cast<uint64_t>((rowEnd - rowBegin) * (colEnd - colBegin));
  c.pixelsCovered += covered;
  c.pixelsPassed += static_cast<uint64_t>(std::popcount(passMask));
  if (passMask == 0) return;
  finishBlock<kWantHits, kFunc>(job, t, bx, by, passMask, triIndex);
}

// A small triangle's edges 0..2 (lane 3 unused): A, B and q = E(x, y) >> 8 at a pixel (smallEdges).
struct SmallEdges {
  alignas(16) int32_t a[4], b[4], q[4];
};

// Rows y0..y1 of a small triangle over the 8 columns from xs, the pixels [x0, x1] x [y0, y1]
// (inclusive, within those columns) tested; q[k] = E_k(xs, y0) >> 8 (smallEdges), from which the
// edge values at these pixel centres follow in int32 (tile_kernels.cpp's header). Returns the
// pixels that passed, pixel (x, y) as bit 8 (firstRow + y - y0) + x - xs; counts covered pixels.
template <DepthFunc kFunc>
HWY_INLINE uint64_t rasterRows(const TileJob& job, const SetupTri& t, const SmallEdges& se,
                               const int32_t q[3], int xs, int x0, int x1, int y0, int y1, int firstRow,
                               size_t& covered) {
  const hn::CappedTag<int32_t, 8> di;
  const hn::Rebind<float, decltype(di)> df;
  const int N = static_cast<int>(hn::Lanes(di));
  const auto iota = hn::Iota(di, 0);
  const auto b0 = hn::Set(di, se.b[0]), b1 = hn::Set(di, se.b[1]), b2 = hn::Set(di, se.b[2]);
  uint64_t pass = 0;
  float* depthRow0 = job.depth + static_cast<size_t>(y0) * static_cast<size_t>(job.depthStride) + xs;
  for (int i0 = 0; i0 < kBlockSize; i0 += N) {
    if (xs + i0 > x1 || xs + i0 + N <= x0) continue;
    const auto lane = hn::Add(iota, hn::Set(di, i0));
    const auto colMask =
        hn::And(hn::Gt(lane, hn::Set(di, x0 - xs - 1)), hn::Lt(lane, hn::Set(di, x1 - xs + 1)));
    auto e0 = hn::Add(hn::Set(di, q[0]), hn::Mul(lane, hn::Set(di, se.a[0])));
    auto e1 = hn::Add(hn::Set(di, q[1]), hn::Mul(lane, hn::Set(di, se.a[1])));
    auto e2 = hn::Add(hn::Set(di, q[2]), hn::Mul(lane, hn::Set(di, se.a[2])));
    const auto dx = hn::ConvertTo(df, hn::Add(lane, hn::Set(di, xs - t.minX)));
    const auto zrow = hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.zx), dx));
    float* drow = depthRow0 + i0;
    for (int y = y0; y <= y1; ++y) {
      const auto z = hn::Add(zrow, hn::Set(df, t.zy * static_cast<float>(y - t.minY)));
      pass |= depthTestRow<kFunc>(job, t, e0, e1, e2, colMask, z, drow, covered)
              << ((firstRow + y - y0) * kBlockSize + i0);
      drow += job.depthStride;
      e0 = hn::Add(e0, b0);
      e1 = hn::Add(e1, b1);
      e2 = hn::Add(e2, b2);
    }
  }
  return pass;
}

// The pixels [x0, x1] x [y0, y1] (inclusive) of block (bx, by) that a small triangle's bounding
// box covers, the block not hidden by coarse depth; q[k] = E_k(8 bx, y0) >> 8 (smallEdges).
template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void rasterSmallBlock(const TileJob& job, const SetupTri& t, const SmallEdges& se,
                                 const int32_t q[3], int x0, int x1, int y0, int y1, int bx, int by,
                                 uint32_t triIndex, Counters& c) {
  size_t covered = 0;
  const uint64_t pass =
      rasterRows<kFunc>(job, t, se, q, bx * kBlockSize, x0, x1, y0, y1, y0 & (kBlockSize - 1), covered);
  c.pixelsTested += static_cast<uint64_t>((x1 - x0 + 1) * (y1 - y0 + 1));
  c.pixelsCovered += covered;
  if (pass == 0) return;
  c.pixelsPassed += static_cast<uint64_t>(std::popcount(pass));
  finishBlock<kWantHits, kFunc>(job, t, bx, by, pass, triIndex);
}

// Block (bx, by) of a small triangle against coarse depth, counted: true when it must be rasterized.
template <DepthFunc kFunc>
HWY_INLINE bool smallBlockLive(const TileJob& job, const SetupTri& t, int bx, int by, Counters& c) {
  if (hiddenByCoarseDepth<kFunc>(job, t,
                                 static_cast<size_t>(by) * static_cast<size_t>(job.blocksX) + static_cast<size_t>(bx))) {
    ++c.rejectedDepth;
    return false;
  }
  ++c.partial;
  return true;
}

// A small triangle's exact edge values at pixel (x, y), shifted: q[k] = E_k(x, y) >> 8, floor
// division. Its vertices span less than 8 pixels each way and (x, y) lies at most 8 pixels left of
// its bounding box and inside it vertically, so every factor is below 2^12 and |E| below 2^24: int32
// holds it exactly. Moving the point by (i, j) pixels moves E by 256 (A i + B j), so the shifted
// value moves by exactly A i + B j: the blocks after the first step from it (rasterSmall). The
// three edges are formed in the lanes of one 128-bit vector (edgeCoefficients' A, B and bias).
HWY_INLINE SmallEdges smallEdges(const SetupTri& t, int x, int y) {
  SmallEdges se;
  const int32_t sx = x * kSubpixelOne, sy = y * kSubpixelOne;
#if HWY_TARGET == HWY_SCALAR
  const EdgeCoefficients ec = edgeCoefficients(t);
  for (int k = 0; k < 3; ++k) {
    se.a[k] = ec.a[k];
    se.b[k] = ec.b[k];
    se.q[k] = (ec.a[k] * (sx - t.vx[k]) + ec.b[k] * (sy - t.vy[k]) - ec.bias[k]) >> kSubpixelBits;
  }
#else
  const hn::FixedTag<int32_t, 4> d;
  // Lanes 0..2: vertex k; lane 3 holds the next field (vy[0], minX) and maps to itself: unused.
  alignas(16) static constexpr int32_t kNext[4] = {1, 2, 0, 3};
  const auto next = hn::SetTableIndices(d, kNext);
  const auto vx = hn::LoadU(d, t.vx), vy = hn::LoadU(d, t.vy);
  const auto dx = hn::Sub(hn::TableLookupLanes(vx, next), vx),
             dy = hn::Sub(hn::TableLookupLanes(vy, next), vy);
  const auto zero = hn::Zero(d);
  // Top-left rule (conventions.h): bias 0 where dy < 0 or (dy == 0 and dx > 0), else 1.
  const auto topLeft = hn::Or(hn::Lt(dy, zero), hn::And(hn::Eq(dy, zero), hn::Gt(dx, zero)));
  const auto bias = hn::IfThenZeroElse(topLeft, hn::Set(d, 1));
  const auto a = hn::Neg(dy);
  const auto e = hn::Sub(
      hn::Add(hn::Mul(a, hn::Sub(hn::Set(d, sx), vx)), hn::Mul(dx, hn::Sub(hn::Set(d, sy), vy))), bias);
  hn::Store(a, d, se.a);
  hn::Store(dx, d, se.b);
  hn::Store(hn::ShiftRight<kSubpixelBits>(e), d, se.q);
#endif
  return se;
}

// q[k] = se.q[k] + A i + B j for the edges 0..2 (q holds 4 lanes): the shifted edge values i, j
// pixels away (smallEdges says why this is exact).
HWY_INLINE void stepSmallEdges(const SmallEdges& se, int i, int j, int32_t q[4]) {
#if HWY_TARGET == HWY_SCALAR
  for (int k = 0; k < 3; ++k) q[k] = se.q[k] + se.a[k] * i + se.b[k] * j;
#else
  const hn::FixedTag<int32_t, 4> d;
  hn::Store(hn::Add(hn::Load(d, se.q), hn::Add(hn::Mul(hn::Load(d, se.a), hn::Set(d, i)),
                                               hn::Mul(hn::Load(d, se.b), hn::Set(d, j)))),
            d, q);
#endif
}

// The bits of an 8-row mask (bit 8 r + i: row r, column i) whose columns i satisfy lo <= i <= hi.
constexpr uint64_t columnsMask(int lo, int hi) {
  return 0x0101010101010101ull * ((0xffull >> (7 - hi)) & (0xffull << lo) & 0xffull);
}

// A small triangle whose blocks [bx0, bx1] x [by0, by1] (at most 2 x 2) all survived coarse depth
// (counted by the caller), its box [x0, x1] x [y0, y1] at most 8 pixels each way: rasterized as
// one box of rows, not block by block. Each row is one run of 8 pixels from column xs = x0 -- or,
// where that run would leave the tile, the tile's last 8 (padded) columns, which hold the box too:
// the lanes beyond the box read and write back only this tile's own pixels, which no other task
// touches. The passed pixels (bit 8 (y - y0) + (x - xs)) are then cut into the blocks' masks and
// each block finished in the order of the block loop (rows of blocks, then columns), so the
// depths, coarse records, hits and counters are those of rasterizing block by block.
template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void rasterSmallBox(const TileJob& job, const SetupTri& t, int x0, int x1, int y0, int y1, int bx0,
                               int by0, uint32_t triIndex, Counters& c) {
  const int tileEnd = (job.x1 + kBlockSize - 1) & ~(kBlockSize - 1);  // 8-aligned, within the padded row
  const int xs = std::min(x0, tileEnd - kBlockSize);
  const SmallEdges se = smallEdges(t, xs, y0);
  size_t covered = 0;
  const uint64_t box = rasterRows<kFunc>(job, t, se, se.q, xs, x0, x1, y0, y1, 0, covered);
  c.pixelsTested += static_cast<uint64_t>((x1 - x0 + 1) * (y1 - y0 + 1));
  c.pixelsCovered += covered;
  if (box == 0) return;
  c.pixelsPassed += static_cast<uint64_t>(std::popcount(box));
  // Columns: the box's column i is column s + i of block xs / 8, or i - (8 - s) of the next.
  const int s = xs & (kBlockSize - 1), r = y0 & (kBlockSize - 1);
  const uint64_t left = (box << s) & columnsMask(s, 7);
  const uint64_t right = s == 0 ? 0 : (box >> (kBlockSize - s)) & columnsMask(0, s - 1);
  // Rows: the box's row j is row r + j of block y0 / 8, or j - (8 - r) of the next. Block xs / 8 is
  // bx0 (xs moves left of x0 only onto a block's first column, when the box lies in one block
  // column), and a block the box does not reach gets no bits.
  const int top = kBlockSize * r;
  if (const uint64_t m = left << top) finishBlock<kWantHits, kFunc>(job, t, bx0, by0, m, triIndex);
  if (const uint64_t m = right << top) finishBlock<kWantHits, kFunc>(job, t, bx0 + 1, by0, m, triIndex);
  if (r != 0) {
    if (const uint64_t m = left >> (64 - top))
      finishBlock<kWantHits, kFunc>(job, t, bx0, by0 + 1, m, triIndex);
    if (const uint64_t m = right >> (64 - top))
      finishBlock<kWantHits, kFunc>(job, t, bx0 + 1, by0 + 1, m, triIndex);
  }
}

// Whether none of a small triangle's blocks [bx0, bx1] x [by0, by1] (at most 2 x 2) is hidden by
// coarse depth.
template <DepthFunc kFunc>
HWY_INLINE bool smallBlocksLive(const TileJob& job, const SetupTri& t, int bx0, int bx1, int by0, int by1) {
  const size_t bi = static_cast<size_t>(by0) * static_cast<size_t>(job.blocksX) + static_cast<size_t>(bx0);
  const size_t below = static_cast<size_t>(job.blocksX);
  const bool wide = bx1 > bx0, tall = by1 > by0;
  return !hiddenByCoarseDepth<kFunc>(job, t, bi) && !(wide && hiddenByCoarseDepth<kFunc>(job, t, bi + 1)) &&
         !(tall && hiddenByCoarseDepth<kFunc>(job, t, bi + below)) &&
         !(wide && tall && hiddenByCoarseDepth<kFunc>(job, t, bi + below + 1));
}

// A triangle whose vertices span less than 8 pixels each way, its bounding box clamped to the tile
// [x0, x1] x [y0, y1] (inclusive): at most 2 x 2 blocks, each tested against coarse depth. When
// all survive, the box is rasterized at once (rasterSmallBox); otherwise each live block on its
// own (blocks are disjoint, so the order changes nothing but the counters' sum order), the edge
// values derived once a block survives, once per triangle, and stepped to the other blocks.
template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void rasterSmall(const TileJob& job, const SetupTri& t, int x0, int x1, int y0, int y1,
                            uint32_t triIndex, Counters& c) {
  const int bx0 = x0 >> kBlockLog2, bx1 = x1 >> kBlockLog2, by0 = y0 >> kBlockLog2, by1 = y1 >> kBlockLog2;
  if (bx0 == bx1 && by0 == by1) {  // the common case, without the loops
    if (!smallBlockLive<kFunc>(job, t, bx0, by0, c)) return;
    const SmallEdges se = smallEdges(t, bx0 * kBlockSize, y0);
    rasterSmallBlock<kWantHits, kFunc>(job, t, se, se.q, x0, x1, y0, y1, bx0, by0, triIndex, c);
    return;
  }
  if (smallBlocksLive<kFunc>(job, t, bx0, bx1, by0, by1)) {
    c.partial += static_cast<uint64_t>((bx1 - bx0 + 1) * (by1 - by0 + 1));
    rasterSmallBox<kWantHits, kFunc>(job, t, x0, x1, y0, y1, bx0, by0, triIndex, c);
    return;
  }
  SmallEdges se;             // q at (8 bx0, y0)
  alignas(16) int32_t q[4];  // q at the block's first pixel
  bool haveEdges = false;
  for (int by = by0; by <= by1; ++by) {
    const int ry0 = std::max(y0, by * kBlockSize), ry1 = std::min(y1, by * kBlockSize + kBlockSize - 1);
    for (int bx = bx0; bx <= bx1; ++bx) {
      if (!smallBlockLive<kFunc>(job, t, bx, by, c)) continue;
      if (!haveEdges) {
        se = smallEdges(t, bx0 * kBlockSize, y0);
        haveEdges = true;
      }
      stepSmallEdges(se, (bx - bx0) * kBlockSize, ry0 - y0, q);
      rasterSmallBlock<kWantHits, kFunc>(job, t, se, q, std::max(x0, bx * kBlockSize),
                                         std::min(x1, bx * kBlockSize + kBlockSize - 1), ry0, ry1, bx, by,
                                         triIndex, c);
    }
  }
}

// A triangle that spans 8 pixels or more: its blocks [bx0, bx1] x [by0, by1] in the tile, each
// rejected or accepted whole by its exact edge values, then rasterized (rasterBlock).
template <bool kWantHits, DepthFunc kFunc>
HWY_NOINLINE void rasterLarge(const TileJob& job, const SetupTri& t, int bx0, int bx1, int by0, int by1,
                              uint32_t triIndex, Counters& c) {
  const EdgeCoefficients ec = edgeCoefficients(t);
  int64_t e[3];
  for (int k = 0; k < 3; ++k) e[k] = edgeAt(t, ec, k, int64_t{bx0} * kBlockSize, int64_t{by0} * kBlockSize);

  int64_t stepX[3], stepY[3], extMax[3], extMin[3];
  for (int k = 0; k < 3; ++k) {
    const int64_t a = int64_t{ec.a[k]} * kSubpixelOne, b = int64_t{ec.b[k]} * kSubpixelOne;
    stepX[k] = a * kBlockSize;
    stepY[k] = b * kBlockSize;
    // Range of E over the block's pixel centres, relative to its (0, 0) pixel.
    extMax[k] = std::max<int64_t>(0, a * (kBlockSize - 1)) + std::max<int64_t>(0, b * (kBlockSize - 1));
    extMin[k] = std::min<int64_t>(0, a * (kBlockSize - 1)) + std::min<int64_t>(0, b * (kBlockSize - 1));
  }
  for (int by = by0; by <= by1; ++by) {
    int64_t eb[3] = {e[0], e[1], e[2]};
    for (int bx = bx0; bx <= bx1; ++bx) {
      bool reject = false, whole[3];
      for (int k = 0; k < 3; ++k) {
        reject |= eb[k] + extMax[k] < 0;
        whole[k] = eb[k] + extMin[k] >= 0;
      }
      if (reject) {
        ++c.rejectedEdge;
      } else {
        rasterBlock<kWantHits, kFunc>(job, t, ec, bx, by, eb, whole, triIndex, c);
      }
      for (int k = 0; k < 3; ++k) eb[k] += stepX[k];
    }
    for (int k = 0; k < 3; ++k) e[k] += stepY[k];
  }
}

template <bool kWantHits, DepthFunc kFunc>
HWY_INLINE void rasterTriangle(const TileJob& job, const SetupTri& t, uint32_t triIndex, Counters& c) {
  const int x0 = std::max(t.minX, job.x0), x1 = std::min(t.maxX + 1, job.x1);
  const int y0 = std::max(t.minY, job.y0), y1 = std::min(t.maxY + 1, job.y1);
  if (x0 >= x1 || y0 >= y1) return;
  const int bx0 = x0 >> kBlockLog2, bx1 = (x1 - 1) >> kBlockLog2;
  const int by0 = y0 >> kBlockLog2, by1 = (y1 - 1) >> kBlockLog2;
  const int32_t spanX =
      std::max(std::max(t.vx[0], t.vx[1]), t.vx[2]) - std::min(std::min(t.vx[0], t.vx[1]), t.vx[2]);
  const int32_t spanY =
      std::max(std::max(t.vy[0], t.vy[1]), t.vy[2]) - std::min(std::min(t.vy[0], t.vy[1]), t.vy[2]);
  if (spanX < kBlockSize * kSubpixelOne && spanY < kBlockSize * kSubpixelOne) {
    rasterSmall<kWantHits, kFunc>(job, t, x0, x1 - 1, y0, y1 - 1, triIndex, c);
    return;
  }
  Counters large;
  rasterLarge<kWantHits, kFunc>(job, t, bx0, bx1, by0, by1, triIndex, large);
  c += large;
}

// All of a tile's triangles with one depth test, known at compile time.
template <DepthFunc kFunc>
void rasterizeTriangles(const TileJob& job, Counters& c) {
  // The triangles come from memory the setup stage wrote long ago: prefetch a few ahead.
  constexpr uint32_t kAhead = 8;
  if (job.hits) {
    for (uint32_t i = 0; i < job.count; ++i) {
      if (i + kAhead < job.count) __builtin_prefetch(job.tris[i + kAhead]);
      rasterTriangle<true, kFunc>(job, *job.tris[i], i, c);
    }
  } else {
    for (uint32_t i = 0; i < job.count; ++i) {
      if (i + kAhead < job.count) __builtin_prefetch(job.tris[i + kAhead]);
      rasterTriangle<false, kFunc>(job, *job.tris[i], i, c);
    }
  }
}

}  // namespace

void RasterizeTileImpl(const TileJob& job, PassStats& st) {
  Counters c;
  switch (job.func) {
    case DepthFunc::Less:
      rasterizeTriangles<DepthFunc::Less>(job, c);
      break;
    case DepthFunc::Greater:
      rasterizeTriangles<DepthFunc::Greater>(job, c);
      break;
    case DepthFunc::Always:
      rasterizeTriangles<DepthFunc::Always>(job, c);
      break;
  }
  st.blocksTested += c.rejectedEdge + c.rejectedDepth + c.accepted + c.partial;
  st.blocksRejectedEdge += c.rejectedEdge;
  st.blocksRejectedDepth += c.rejectedDepth;
  st.blocksAccepted += c.accepted;
  st.blocksPartial += c.partial;
  st.pixelsTested += c.pixelsTested;
  st.pixelsCovered += c.pixelsCovered;
  st.pixelsDepthPassed += c.pixelsPassed;
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::raster {

HWY_EXPORT(RasterizeTileImpl);

void rasterizeTile(const TileJob& job, PassStats& stats) {
  auto* fn = HWY_DISPATCH_TABLE(RasterizeTileImpl)[simdDispatchIndex(job.simd)];
  (fn ? fn : HWY_DISPATCH_TABLE(RasterizeTileImpl)[0])(job, stats);
}

}  // namespace penumbra::raster
#endif
