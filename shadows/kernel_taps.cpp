// SIMD tap loops of PCF and PCSS (see kernel_taps.h), compiled once per Highway target.
//
// Exactness, lane by lane against the scalar references at the end of this file:
// - tap coordinates, texel coordinates and thresholds use the scalar expressions' operations in
//   their order (x * y + z is Add(Mul(x, y), z), never MulAdd; -ffp-contract=off keeps the
//   compiler from fusing them); Floor and Div are exact on every target;
// - std::max(lo, v) is (lo < v) ? v : lo and std::min(hi, v) is (v < hi) ? v : hi, so the clamps
//   are written with Lt and IfThenElse: a NaN texel coordinate becomes 0 and a NaN plane value lo,
//   as in the scalar code (Highway's Min / Max leave NaN operands to each target's instruction);
// - clamped texel coordinates are in [0, 8191], so truncation to int32 (ConvertTo) gives the
//   scalar size_t casts' values, and row * stride + column < 2^31 (kernel_taps.h);
// - the lit count is an integer sum (any order); the blocker depths are summed as doubles in tap
//   order: each vector's blocking lanes are compressed, in lane order, to the end of a stack buffer
//   that is then added up one by one. (Any order would do while the depths span less than a
//   factor 2^(29 - log2 n), their sum then being exact in double, but scenes need not keep that.)

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shadows/kernel_taps.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

#include "shadows/kernel_taps.h"

#include "raster/simd.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::shadows {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using DF = hn::CappedTag<float, kTapLanes>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;

// std::max(lo, v) and std::min(hi, v), NaN included (see the file comment).
HWY_INLINE VF maxOf(VF lo, VF v) { return hn::IfThenElse(hn::Lt(lo, v), v, lo); }
HWY_INLINE VF minOf(VF hi, VF v) { return hn::IfThenElse(hn::Lt(v, hi), v, hi); }

// TapMap::stored and TapPlane::threshold with their constants in registers.
struct Lookup {
  DF df;
  DI di;
  const float* data;
  VF ax, bx, ay, by, maxX, maxY;
  hn::Vec<DI> stride;
  VF a, b, c, lo, hi, scale;

  Lookup(const TapMap& m, const TapPlane& p)
      : df(), di(), data(m.data), ax(hn::Set(df, m.ax)), bx(hn::Set(df, m.bx)), ay(hn::Set(df, m.ay)),
        by(hn::Set(df, m.by)), maxX(hn::Set(df, m.maxX)), maxY(hn::Set(df, m.maxY)), stride(hn::Set(di, m.stride)),
        a(hn::Set(df, p.a)), b(hn::Set(df, p.b)), c(hn::Set(df, p.c)), lo(hn::Set(df, p.lo)), hi(hn::Set(df, p.hi)),
        scale(hn::Set(df, p.scale)) {}

  VF stored(VF tx, VF ty) const {
    const VF zero = hn::Zero(df);
    const VF fx = minOf(maxX, maxOf(zero, hn::Add(hn::Mul(ax, tx), bx)));
    const VF fy = minOf(maxY, maxOf(zero, hn::Add(hn::Mul(ay, ty), by)));
    const auto index = hn::Add(hn::Mul(hn::ConvertTo(di, fy), stride), hn::ConvertTo(di, fx));
    return hn::GatherIndex(df, data, index);
  }
  VF threshold(VF tx, VF ty) const {
    return hn::Mul(scale, minOf(hi, maxOf(lo, hn::Add(hn::Add(hn::Mul(a, tx), hn::Mul(b, ty)), c))));
  }
};

// PCSS tap coordinates: centre + (2 frac(p + shift) - 1) * half-extent, per axis.
struct ShiftedTaps {
  const float* px;
  const float* py;
  VF shiftX, shiftY, cx, cy, hx, hy;

  void at(DF df, int i, VF& tx, VF& ty) const {
    const VF one = hn::Set(df, 1.0f), two = hn::Set(df, 2.0f);
    VF p = hn::Add(hn::LoadU(df, px + i), shiftX);
    p = hn::Sub(p, hn::Floor(p));
    tx = hn::Add(cx, hn::Mul(hn::Sub(hn::Mul(two, p), one), hx));
    VF q = hn::Add(hn::LoadU(df, py + i), shiftY);
    q = hn::Sub(q, hn::Floor(q));
    ty = hn::Add(cy, hn::Mul(hn::Sub(hn::Mul(two, q), one), hy));
  }
};

// PCF tap coordinates: centre + rotated offset * texel size (tanY falls as rows grow).
struct RotatedTaps {
  const float* ox;
  const float* oy;
  VF c, s, cx, cy, texelX, texelY;

  void at(DF df, int i, VF& tx, VF& ty) const {
    const VF x = hn::LoadU(df, ox + i), y = hn::LoadU(df, oy + i);
    const VF dx = hn::Sub(hn::Mul(c, x), hn::Mul(s, y));
    const VF dy = hn::Add(hn::Mul(s, x), hn::Mul(c, y));
    tx = hn::Add(cx, hn::Mul(dx, texelX));
    ty = hn::Sub(cy, hn::Mul(dy, texelY));
  }
};

template <class Taps>
HWY_INLINE int countLit(const Lookup& l, const Taps& taps, int n) {
  const DF df;
  const int N = static_cast<int>(hn::Lanes(df));
  size_t lit = 0;
  for (int i = 0; i < n; i += N) {
    VF tx, ty;
    taps.at(df, i, tx, ty);
    auto pass = hn::Le(l.stored(tx, ty), l.threshold(tx, ty));
    if (n - i < N) pass = hn::And(pass, hn::FirstN(df, static_cast<size_t>(n - i)));
    lit += hn::CountTrue(df, pass);
  }
  return static_cast<int>(lit);
}

}  // namespace

int CountLitTapsImpl(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n, float shiftX,
                     float shiftY, float cx, float cy, float hx, float hy) {
  const DF df;
  const ShiftedTaps taps{px, py, hn::Set(df, shiftX), hn::Set(df, shiftY), hn::Set(df, cx), hn::Set(df, cy),
                         hn::Set(df, hx), hn::Set(df, hy)};
  return countLit(Lookup(map, plane), taps, n);
}

int CountLitRotatedTapsImpl(const TapMap& map, const TapPlane& plane, const float* ox, const float* oy, int n, float c,
                            float s, float cx, float cy, float texelX, float texelY) {
  const DF df;
  const RotatedTaps taps{ox, oy, hn::Set(df, c), hn::Set(df, s), hn::Set(df, cx), hn::Set(df, cy),
                         hn::Set(df, texelX), hn::Set(df, texelY)};
  return countLit(Lookup(map, plane), taps, n);
}

BlockerSum SearchBlockersImpl(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                              float shiftX, float shiftY, float cx, float cy, float hx, float hy, float znear) {
  const DF df;
  const int N = static_cast<int>(hn::Lanes(df));
  const Lookup l(map, plane);
  const ShiftedTaps taps{px, py, hn::Set(df, shiftX), hn::Set(df, shiftY), hn::Set(df, cx), hn::Set(df, cy),
                         hn::Set(df, hx), hn::Set(df, hy)};
  const VF zero = hn::Zero(df), inf = hn::Set(df, INFINITY), zn = hn::Set(df, znear);
  // Blocking depths of up to kChunk taps, in tap order, then summed. No branch on the map's values
  // in the first loop, so that the lookups of successive vectors overlap.
  constexpr int kChunk = 256;  // a multiple of every lane count (kTapLanes)
  HWY_ALIGN float depths[kChunk + kTapLanes];  // each vector's store writes all of its lanes
  BlockerSum r;
  for (int begin = 0; begin < n; begin += kChunk) {
    const int end = std::min(n, begin + kChunk);
    size_t k = 0;
    for (int i = begin; i < end; i += N) {
      VF tx, ty;
      taps.at(df, i, tx, ty);
      const VF z = l.stored(tx, ty);
      auto blocks = hn::Gt(z, l.threshold(tx, ty));
      if (end - i < N) blocks = hn::And(blocks, hn::FirstN(df, static_cast<size_t>(end - i)));
      // LightView::depthOf: near / z, +inf where nothing was drawn.
      const VF depth = hn::IfThenElse(hn::Gt(z, zero), hn::Div(zn, z), inf);
      hn::StoreU(hn::Compress(depth, blocks), df, depths + k);
      k += hn::CountTrue(df, blocks);
    }
    for (size_t j = 0; j < k; ++j) r.sum += static_cast<double>(depths[j]);
    r.count += static_cast<int>(k);
  }
  return r;
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::shadows
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::shadows {

HWY_EXPORT(CountLitTapsImpl);
HWY_EXPORT(CountLitRotatedTapsImpl);
HWY_EXPORT(SearchBlockersImpl);

TapPattern::TapPattern(std::span<const glm::vec2> points) : count(static_cast<int>(points.size())) {
  const size_t padded = (points.size() + kTapLanes - 1) / kTapLanes * kTapLanes;
  x.assign(padded, 0.0f);
  y.assign(padded, 0.0f);
  for (size_t i = 0; i < points.size(); ++i) x[i] = points[i].x, y[i] = points[i].y;
}

namespace {
// The entry of a dispatch table for the SIMD target asked for (raster/simd.h).
template <class Table>
auto pick(const Table& table, int64_t simd) {
  auto* fn = table[raster::simdDispatchIndex(simd)];
  return fn ? fn : table[0];
}
}  // namespace

int countLitTaps(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n, float shiftX,
                 float shiftY, float cx, float cy, float hx, float hy, int64_t simd) {
  return pick(HWY_DISPATCH_TABLE(CountLitTapsImpl), simd)(map, plane, px, py, n, shiftX, shiftY, cx, cy, hx, hy);
}

BlockerSum searchBlockers(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                          float shiftX, float shiftY, float cx, float cy, float hx, float hy, float znear, int64_t simd) {
  return pick(HWY_DISPATCH_TABLE(SearchBlockersImpl), simd)(map, plane, px, py, n, shiftX, shiftY, cx, cy, hx, hy, znear);
}

int countLitRotatedTaps(const TapMap& map, const TapPlane& plane, const float* ox, const float* oy, int n, float c,
                        float s, float cx, float cy, float texelX, float texelY, int64_t simd) {
  return pick(HWY_DISPATCH_TABLE(CountLitRotatedTapsImpl), simd)(map, plane, ox, oy, n, c, s, cx, cy, texelX, texelY);
}

// The scalar references: the loops of pcss.cpp and pcf.cpp before they used the kernels above.
namespace {
// PCSS's tap: p += shift; p -= floor(p); centre + (2 p - 1) * h (glm::vec2 arithmetic per axis).
void shiftedTap(float px, float py, float shiftX, float shiftY, float cx, float cy, float hx, float hy, float& tx,
                float& ty) {
  float x = px + shiftX, y = py + shiftY;
  x -= std::floor(x);
  y -= std::floor(y);
  tx = cx + (2.0f * x - 1.0f) * hx;
  ty = cy + (2.0f * y - 1.0f) * hy;
}
}  // namespace

int countLitTapsScalar(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                       float shiftX, float shiftY, float cx, float cy, float hx, float hy) {
  int lit = 0;
  for (int i = 0; i < n; ++i) {
    float tx, ty;
    shiftedTap(px[i], py[i], shiftX, shiftY, cx, cy, hx, hy, tx, ty);
    lit += map.stored(tx, ty) <= plane.threshold(tx, ty) ? 1 : 0;
  }
  return lit;
}

BlockerSum searchBlockersScalar(const TapMap& map, const TapPlane& plane, const float* px, const float* py, int n,
                                float shiftX, float shiftY, float cx, float cy, float hx, float hy, float znear) {
  BlockerSum r;
  for (int i = 0; i < n; ++i) {
    float tx, ty;
    shiftedTap(px[i], py[i], shiftX, shiftY, cx, cy, hx, hy, tx, ty);
    const float z = map.stored(tx, ty);
    if (z > plane.threshold(tx, ty)) {
      r.sum += static_cast<double>(z > 0.0f ? znear / z : INFINITY);
      ++r.count;
    }
  }
  return r;
}

int countLitRotatedTapsScalar(const TapMap& map, const TapPlane& plane, const float* ox, const float* oy, int n,
                              float c, float s, float cx, float cy, float texelX, float texelY) {
  int lit = 0;
  for (int i = 0; i < n; ++i) {
    const float dx = c * ox[i] - s * oy[i], dy = s * ox[i] + c * oy[i];
    const float tx = cx + dx * texelX, ty = cy - dy * texelY;
    lit += map.stored(tx, ty) <= plane.threshold(tx, ty) ? 1 : 0;
  }
  return lit;
}


}  // namespace penumbra::shadows
#endif
