// The per-receiver depth tests of MVR and VWSS (light_samples.h, accumulateSampleRow) in SIMD lanes,
// compiled once per Highway target: one lane per receiver of a row, every map of a group in turn
// while the receivers' lanes stay in registers, each tap a gather from the map.
//
// Exactness, lane by lane against accumulateSampleRowReference (light_samples.cpp), by the rules of
// kernel_taps.cpp: the reference's float operations in its order (x * y + z is Add(Mul(x, y), z),
// never MulAdd; -ffp-contract=off), Div and Floor exact on every target, the clamps written with Lt
// and IfThenElse as std::min / std::max, truncation of clamped non-negative texel coordinates. A
// tap offset times the texel size is a scalar product in both. Lanes past the row and receivers
// with nothing to test (d = -1) compute from finite padding and are not counted; their clamped
// indices stay inside the map.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shadows/sample_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

#include "raster/simd.h"
#include "shadows/kernel_taps.h"
#include "shadows/light_samples.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::shadows {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using DF = hn::CappedTag<float, kTapLanes>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;

HWY_INLINE VF maxOf(VF lo, VF v) {
  return hn::IfThenElse(hn::Lt(lo, v), v, lo);
}
HWY_INLINE VF minOf(VF hi, VF v) {
  return hn::IfThenElse(hn::Lt(v, hi), v, hi);
}

}  // namespace

void AccumulateSampleRow(const SampleRow& row, const SampleLookup* maps, int nMaps, const float* tapX,
                         const float* tapY, int taps, uint16_t* counts) {
  const DF df;
  const DI di;
  const DU du;
  const int N = static_cast<int>(hn::Lanes(df));
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f), two = hn::Set(df, 2.0f);
  const VF inf = hn::Set(df, INFINITY);
  HWY_ALIGN int32_t lit[kTapLanes];
  for (int x = 0; x < row.count; x += N) {
    const VF d = hn::LoadU(df, row.d + x);
    const auto valid = hn::Gt(d, zero);
    if (hn::AllFalse(df, valid)) continue;
    const VF px = hn::LoadU(df, row.x + x), py = hn::LoadU(df, row.y + x);
    const VF nx = hn::LoadU(df, row.nx + x), ny = hn::LoadU(df, row.ny + x), nz = hn::LoadU(df, row.nz + x);
    const VF invD0 = hn::LoadU(df, row.invD + x), bias = hn::LoadU(df, row.bias + x);
    const auto subset = hn::Add(hn::LoadU(di, row.subsetOfX + x), hn::Set(di, row.subsetBase));
    auto count = hn::Zero(di);
    for (int mi = 0; mi < nMaps; ++mi) {
      const SampleLookup& m = maps[mi];
      auto active = valid;
      if (m.subset >= 0) active = hn::And(active, hn::RebindMask(df, hn::Eq(subset, hn::Set(di, m.subset))));
      VF vx = hn::Sub(px, hn::Set(df, m.lpx)), vy = hn::Sub(py, hn::Set(df, m.lpy)), vz = d;
      VF k = hn::Add(hn::Add(hn::Mul(nx, vx), hn::Mul(ny, vy)), hn::Mul(nz, vz));
      active = hn::And(active, hn::Gt(hn::Neg(k), zero));  // above the horizon
      if (hn::AllFalse(df, active)) continue;
      VF invD = invD0;
      const float offset = row.normalOffset * m.texel;
      if (offset != 0.0f) {
        const VF o = hn::Mul(hn::Set(df, offset), d);
        vx = hn::Add(vx, hn::Mul(nx, o)), vy = hn::Add(vy, hn::Mul(ny, o)), vz = hn::Add(vz, hn::Mul(nz, o));
        invD = hn::Div(one, vz);
        k = hn::Add(hn::Add(hn::Mul(nx, vx), hn::Mul(ny, vy)), hn::Mul(nz, vz));
      }
      const VF invK = hn::Div(one, k);
      const VF beta = hn::Mul(hn::Set(df, m.texel), bias);
      const VF scale =
          hn::IfThenElse(hn::Lt(beta, one), hn::Div(hn::Set(df, m.znear), hn::Sub(one, beta)), inf);
      const VF tx = hn::Mul(vx, invD), ty = hn::Mul(vy, invD);
      const VF lo = hn::Mul(half, invD), hi = hn::Mul(two, invD);
      const VF ax = hn::Set(df, m.ax), bx = hn::Set(df, m.bx), ay = hn::Set(df, m.ay), by = hn::Set(df, m.by);
      const VF maxX = hn::Set(df, m.maxX), maxY = hn::Set(df, m.maxY);
      const VF invAx = hn::Set(df, m.invAx), invAy = hn::Set(df, m.invAy);
      const auto stride = hn::Set(di, m.stride);
      for (int t = 0; t < taps; ++t) {
        const VF qx = hn::Add(tx, hn::Set(df, tapX[t] * m.texelTanX));
        const VF qy = hn::Add(ty, hn::Set(df, tapY[t] * m.texelTanY));
        const VF fx = minOf(maxX, maxOf(zero, hn::Add(hn::Mul(ax, qx), bx)));
        const VF fy = minOf(maxY, maxOf(zero, hn::Add(hn::Mul(ay, qy), by)));
        const auto index = hn::Add(hn::Mul(hn::ConvertTo(di, fy), stride), hn::ConvertTo(di, fx));
        const VF stored =
            m.bits ? hn::BitCast(df, hn::GatherIndex(du, static_cast<const uint32_t*>(m.data), index))
                   : hn::GatherIndex(df, static_cast<const float*>(m.data), index);
        const VF cx = hn::Mul(hn::Sub(hn::Add(hn::Floor(fx), half), bx), invAx);
        const VF cy = hn::Mul(hn::Sub(hn::Add(hn::Floor(fy), half), by), invAy);
        const VF inv = hn::Mul(hn::Add(hn::Add(hn::Mul(nx, cx), hn::Mul(ny, cy)), nz), invK);
        const auto pass = hn::Le(stored, hn::Mul(scale, minOf(hi, maxOf(lo, inv))));
        count = hn::Sub(count, hn::VecFromMask(di, hn::RebindMask(di, hn::And(pass, active))));  // mask = -1
      }
    }
    hn::Store(count, di, lit);
    const int n = std::min(N, row.count - x);
    for (int i = 0; i < n; ++i) counts[x + i] = static_cast<uint16_t>(counts[x + i] + lit[i]);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::shadows
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::shadows {

HWY_EXPORT(AccumulateSampleRow);

void accumulateSampleRow(const SampleRow& row, std::span<const SampleLookup> maps, const float* tapX,
                         const float* tapY, int taps, uint16_t* counts, int64_t simd) {
  auto fn = HWY_DISPATCH_TABLE(AccumulateSampleRow)[raster::simdDispatchIndex(simd)];
  if (!fn) fn = HWY_DISPATCH_TABLE(AccumulateSampleRow)[0];
  fn(row, maps.data(), static_cast<int>(maps.size()), tapX, tapY, taps, counts);
}

}  // namespace penumbra::shadows
#endif  // HWY_ONCE
