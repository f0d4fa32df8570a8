// Triangle setup and vertex projection in SIMD lanes (setup.h setupLanes, projectVertices),
// compiled once per Highway target.
//
// projectVertices: one lane per vertex, the projection in double lanes with projectVertex's
// operations in its order; lrint (round to nearest even, the default mode) is Round.
//
// setupLanes: one lane per triangle, as many lanes as the target holds doubles (2 on SSE, 4 on AVX2, 8 on
// AVX-512). Bounding boxes are int32 lanes; the doubled area, the edge values and the planes are
// double lanes: every integer setupTriangle forms in int64 is below 2^50 in magnitude, so the
// double operations here give it exactly, and the planes repeat setupTriangle's operations in the
// same order (no FMA: -ffp-contract=off). The one difference double arithmetic could make is the
// sign of a zero (+0 * -1 is -0 where the integer product is 0), so the edge values get + 0.0,
// which turns -0 into +0 and leaves every other value alone.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/setup_lanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

#include "raster/setup.h"
#include "raster/simd.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

// double -> float rounded to nearest, overflowing to infinity as IEEE 754 (and static_cast on
// x86) does. Highway's scalar fallback saturates to the largest float instead: there the lanes
// that overflow are set to infinity of their sign.
template <class DF, class V>
HWY_INLINE hn::Vec<DF> DemoteIeee(DF df, V v) {
  auto r = hn::DemoteTo(df, v);
#if HWY_TARGET == HWY_SCALAR || HWY_TARGET == HWY_EMU128
  const hn::DFromV<V> dd;
  uint8_t bits[8] = {};
  hn::StoreMaskBits(dd, hn::Ge(hn::Abs(v), hn::Set(dd, 0x1.ffffffp127)), bits);
  r = hn::IfThenElse(hn::LoadMaskBits(df, bits), hn::CopySign(hn::Set(df, HUGE_VALF), r), r);
#endif
  return r;
}

// The lanes' results, one array per field, before they are written out as records.
struct Lanes {
  alignas(64) int32_t vx[3][kSetupGroup], vy[3][kSetupGroup];
  alignas(64) int32_t minX[kSetupGroup], minY[kSetupGroup], maxX[kSetupGroup], maxY[kSetupGroup];
  alignas(64) float plane[4][3][kSetupGroup];  // z, then 1/w, l1/w1, l2/w2: constant, x, y
  alignas(64) float zmin[kSetupGroup], zmax[kSetupGroup];
  uint8_t noSample[kSetupGroup], degenerate[kSetupGroup], front[kSetupGroup];
};

}  // namespace

uint32_t SetupLanesImpl(const SetupGroupIn& in, int n, CullMode cull, const Viewport& vp, SetupTri* tris,
                        SetupAttr* attrs, uint64_t verdicts[4]) {
  const bool wantAttrs = attrs != nullptr;
  const hn::ScalableTag<double> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<float, decltype(dd)> df;
  const size_t N = hn::Lanes(dd);
  Lanes L;
  const auto zeroI = hn::Zero(di);
  const auto lastX = hn::Set(di, vp.width - 1), lastY = hn::Set(di, vp.height - 1);
  const auto zero = hn::Zero(dd), subpixel = hn::Set(dd, static_cast<double>(kSubpixelOne));
  for (size_t l0 = 0; l0 < static_cast<size_t>(n); l0 += N) {
    const auto x0 = hn::LoadU(di, in.x[0] + l0), x1 = hn::LoadU(di, in.x[1] + l0), x2 = hn::LoadU(di, in.x[2] + l0);
    const auto y0 = hn::LoadU(di, in.y[0] + l0), y1 = hn::LoadU(di, in.y[1] + l0), y2 = hn::LoadU(di, in.y[2] + l0);
    // Pixel i is sampled at 256 i: candidates ceil(min / 256) .. floor(max / 256), clamped.
    const auto minx = hn::Min(hn::Min(x0, x1), x2), maxx = hn::Max(hn::Max(x0, x1), x2);
    const auto miny = hn::Min(hn::Min(y0, y1), y2), maxy = hn::Max(hn::Max(y0, y1), y2);
    const auto bx0 = hn::Max(hn::Neg(hn::ShiftRight<kSubpixelBits>(hn::Neg(minx))), zeroI);
    const auto bx1 = hn::Min(hn::ShiftRight<kSubpixelBits>(maxx), lastX);
    const auto by0 = hn::Max(hn::Neg(hn::ShiftRight<kSubpixelBits>(hn::Neg(miny))), zeroI);
    const auto by1 = hn::Min(hn::ShiftRight<kSubpixelBits>(maxy), lastY);
    hn::StoreU(bx0, di, L.minX + l0);
    hn::StoreU(bx1, di, L.maxX + l0);
    hn::StoreU(by0, di, L.minY + l0);
    hn::StoreU(by1, di, L.maxY + l0);
    const auto noSample = hn::Or(hn::Gt(bx0, bx1), hn::Gt(by0, by1));

    const auto X0 = hn::PromoteTo(dd, x0), X1 = hn::PromoteTo(dd, x1), X2 = hn::PromoteTo(dd, x2);
    const auto Y0 = hn::PromoteTo(dd, y0), Y1 = hn::PromoteTo(dd, y1), Y2 = hn::PromoteTo(dd, y2);
    // Doubled signed area in y-down fixed point, (v1 - v0) x (v2 - v0); negative: front-facing.
    const auto area = hn::Sub(hn::Mul(hn::Sub(X1, X0), hn::Sub(Y2, Y0)), hn::Mul(hn::Sub(Y1, Y0), hn::Sub(X2, X0)));
    const auto front = hn::Lt(area, zero);
    uint8_t bits[3][8] = {};
    hn::StoreMaskBits(di, noSample, bits[0]);
    hn::StoreMaskBits(dd, hn::Eq(area, zero), bits[1]);
    hn::StoreMaskBits(dd, front, bits[2]);
    const auto frontI = hn::LoadMaskBits(di, bits[2]);  // the same lanes, for int32 and float
    const auto frontF = hn::LoadMaskBits(df, bits[2]);
    for (size_t l = 0; l < N; ++l) {
      L.noSample[l0 + l] = (bits[0][l / 8] >> (l % 8)) & 1;
      L.degenerate[l0 + l] = (bits[1][l / 8] >> (l % 8)) & 1;
      L.front[l0 + l] = (bits[2][l / 8] >> (l % 8)) & 1;
    }
    // Ordered vertices: front-facing triangles swap vertices 1 and 2, so the area is positive.
    const auto ox1 = hn::IfThenElse(frontI, x2, x1), ox2 = hn::IfThenElse(frontI, x1, x2);
    const auto oy1 = hn::IfThenElse(frontI, y2, y1), oy2 = hn::IfThenElse(frontI, y1, y2);
    hn::StoreU(x0, di, L.vx[0] + l0);
    hn::StoreU(ox1, di, L.vx[1] + l0);
    hn::StoreU(ox2, di, L.vx[2] + l0);
    hn::StoreU(y0, di, L.vy[0] + l0);
    hn::StoreU(oy1, di, L.vy[1] + l0);
    hn::StoreU(oy2, di, L.vy[2] + l0);
    const auto P1x = hn::IfThenElse(front, X2, X1), P2x = hn::IfThenElse(front, X1, X2);
    const auto P1y = hn::IfThenElse(front, Y2, Y1), P2y = hn::IfThenElse(front, Y1, Y2);

    // The barycentric planes of setupTriangle, l1 = E_20 / area and l2 = E_01 / area.
    const auto inv = hn::Div(hn::Set(dd, 1.0), hn::Abs(area));
    const auto ox = hn::PromoteTo(dd, hn::ShiftLeft<kSubpixelBits>(bx0));
    const auto oy = hn::PromoteTo(dd, hn::ShiftLeft<kSubpixelBits>(by0));
    const auto a1 = hn::Sub(P2y, Y0), b1 = hn::Sub(X0, P2x);  // edge 2 -> 0
    const auto a2 = hn::Sub(Y0, P1y), b2 = hn::Sub(P1x, X0);  // edge 0 -> 1
    const auto e1 = hn::Add(hn::Add(hn::Mul(a1, hn::Sub(ox, P2x)), hn::Mul(b1, hn::Sub(oy, P2y))), zero);
    const auto e2 = hn::Add(hn::Add(hn::Mul(a2, hn::Sub(ox, X0)), hn::Mul(b2, hn::Sub(oy, Y0))), zero);
    const auto l1 = hn::Mul(e1, inv), l2 = hn::Mul(e2, inv);
    const auto l1x = hn::Mul(hn::Mul(a1, subpixel), inv), l1y = hn::Mul(hn::Mul(b1, subpixel), inv);
    const auto l2x = hn::Mul(hn::Mul(a2, subpixel), inv), l2y = hn::Mul(hn::Mul(b2, subpixel), inv);
    const auto plane = [&](auto s0, auto d1, auto d2, float (&p)[3][kSetupGroup]) {
      hn::StoreU(DemoteIeee(df, hn::Add(hn::Add(s0, hn::Mul(d1, l1)), hn::Mul(d2, l2))), df, p[0] + l0);
      hn::StoreU(DemoteIeee(df, hn::Add(hn::Mul(d1, l1x), hn::Mul(d2, l2x))), df, p[1] + l0);
      hn::StoreU(DemoteIeee(df, hn::Add(hn::Mul(d1, l1y), hn::Mul(d2, l2y))), df, p[2] + l0);
    };
    const auto z0 = hn::LoadU(df, in.z[0] + l0);
    const auto z1 = hn::IfThenElse(frontF, hn::LoadU(df, in.z[2] + l0), hn::LoadU(df, in.z[1] + l0));
    const auto z2 = hn::IfThenElse(frontF, hn::LoadU(df, in.z[1] + l0), hn::LoadU(df, in.z[2] + l0));
    const auto Z0 = hn::PromoteTo(dd, z0);
    plane(Z0, hn::Sub(hn::PromoteTo(dd, z1), Z0), hn::Sub(hn::PromoteTo(dd, z2), Z0), L.plane[0]);
    // std::min / std::max over {z0, z1, z2}: the first of equal values (+0 and -0 included).
    auto zmin = z0, zmax = z0;
    zmin = hn::IfThenElse(hn::Lt(z1, zmin), z1, zmin);
    zmin = hn::IfThenElse(hn::Lt(z2, zmin), z2, zmin);
    zmax = hn::IfThenElse(hn::Lt(zmax, z1), z1, zmax);
    zmax = hn::IfThenElse(hn::Lt(zmax, z2), z2, zmax);
    hn::StoreU(zmin, df, L.zmin + l0);
    hn::StoreU(zmax, df, L.zmax + l0);
    if (wantAttrs) {
      const auto w0 = hn::PromoteTo(dd, hn::LoadU(df, in.iw[0] + l0));
      const auto iw1 = hn::LoadU(df, in.iw[1] + l0), iw2 = hn::LoadU(df, in.iw[2] + l0);
      const auto w1 = hn::PromoteTo(dd, hn::IfThenElse(frontF, iw2, iw1));
      const auto w2 = hn::PromoteTo(dd, hn::IfThenElse(frontF, iw1, iw2));
      plane(w0, hn::Sub(w1, w0), hn::Sub(w2, w0), L.plane[1]);
      plane(zero, w1, zero, L.plane[2]);
      plane(zero, zero, w2, L.plane[3]);
    }
  }

  // Records, lane by lane, with setupTriangle's order of verdicts.
  uint32_t kept = 0;
  for (int l = 0; l < n; ++l) {
    const bool front = L.front[l] != 0;
    SetupResult res = SetupResult::Ok;
    if (L.noSample[l]) res = SetupResult::NoSample;
    else if (L.degenerate[l]) res = SetupResult::Degenerate;
    else if ((cull == CullMode::Back && !front) || (cull == CullMode::Front && front)) res = SetupResult::CulledFacing;
    ++verdicts[static_cast<int>(res)];
    if (res != SetupResult::Ok) continue;
    kept |= 1u << l;
    SetupTri& t = *tris++;
    for (int k = 0; k < 3; ++k) t.vx[k] = L.vx[k][l], t.vy[k] = L.vy[k][l];
    t.minX = L.minX[l], t.minY = L.minY[l], t.maxX = L.maxX[l], t.maxY = L.maxY[l];
    t.z0 = L.plane[0][0][l], t.zx = L.plane[0][1][l], t.zy = L.plane[0][2][l];
    t.zmin = L.zmin[l], t.zmax = L.zmax[l];
    t.primitive = in.primitive[l];
    if (wantAttrs) {
      SetupAttr& a = *attrs++;
      a.sw0 = L.plane[1][0][l], a.swx = L.plane[1][1][l], a.swy = L.plane[1][2][l];
      a.s10 = L.plane[2][0][l], a.s1x = L.plane[2][1][l], a.s1y = L.plane[2][2][l];
      a.s20 = L.plane[3][0][l], a.s2x = L.plane[3][1][l], a.s2y = L.plane[3][2][l];
      a.order[0] = 0;
      a.order[1] = front ? 2 : 1;
      a.order[2] = front ? 1 : 2;
      a.frontFacing = front;
    }
  }
  return kept;
}

uint64_t ProjectVerticesImpl(const float* clip, size_t n, const Viewport& vp, const GuardPlanes& guard,
                             ScreenVert* out) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<float, decltype(dd)> df;
  const size_t N = hn::Lanes(dd);
  constexpr size_t kMaxN = HWY_MAX_BYTES / sizeof(double);
  alignas(64) float tail[4 * kMaxN] = {};
  alignas(64) int32_t sx[kMaxN], sy[kMaxN], flags[kMaxN];
  alignas(64) float sz[kMaxN], siw[kMaxN];
  const auto width = hn::Set(dd, static_cast<double>(vp.width)), height = hn::Set(dd, static_cast<double>(vp.height));
  const auto half = hn::Set(dd, 0.5), subpixel = hn::Set(dd, static_cast<double>(kSubpixelOne));
  const auto halfSubpixel = hn::Set(dd, static_cast<double>(kSubpixelOne / 2));
  const auto zeroD = hn::Zero(dd);
  const auto zeroF = hn::Zero(df);
  uint64_t nonFinite = 0;
  for (size_t i0 = 0; i0 < n; i0 += N) {
    const size_t m = std::min(N, n - i0);
    const float* src = clip + 4 * i0;
    if (m < N) {
      std::copy(src, src + 4 * m, tail);
      src = tail;
    }
    hn::Vec<decltype(df)> x, y, z, w;
    hn::LoadInterleaved4(df, src, x, y, z, w);
    const auto finite = hn::And(hn::And(hn::IsFinite(x), hn::IsFinite(y)), hn::And(hn::IsFinite(z), hn::IsFinite(w)));
    auto flag = [&](auto mask, uint32_t bit) {
      return hn::IfThenElseZero(hn::RebindMask(di, mask), hn::Set(di, static_cast<int32_t>(bit)));
    };
    const auto negW = hn::Neg(w);
    auto f = hn::Or(hn::Or(flag(hn::Lt(x, negW), kOutLeft), flag(hn::Gt(x, w), kOutRight)),
                    hn::Or(flag(hn::Lt(y, negW), kOutBottom), flag(hn::Gt(y, w), kOutTop)));
    f = hn::Or(f, hn::Or(flag(hn::Lt(z, zeroF), kOutNear), flag(hn::Gt(z, w), kOutFar)));
    // Guard band in double, as guardDistances.
    const auto xd = hn::PromoteTo(dd, x), yd = hn::PromoteTo(dd, y), wd = hn::PromoteTo(dd, w);
    const auto d0 = hn::Sub(hn::Mul(hn::Set(dd, guard.xhi), wd), xd);
    const auto d1 = hn::Sub(xd, hn::Mul(hn::Set(dd, guard.xlo), wd));
    const auto d2 = hn::Sub(hn::Mul(hn::Set(dd, guard.yhi), wd), yd);
    const auto d3 = hn::Sub(yd, hn::Mul(hn::Set(dd, guard.ylo), wd));
    const auto outside = hn::Or(hn::Or(hn::Lt(d0, zeroD), hn::Lt(d1, zeroD)), hn::Or(hn::Lt(d2, zeroD), hn::Lt(d3, zeroD)));
    uint8_t bits[8] = {};
    hn::StoreMaskBits(dd, outside, bits);
    const auto guardOut = hn::Or(hn::LoadMaskBits(di, bits), hn::RebindMask(di, hn::Not(hn::Gt(w, zeroF))));
    const auto bad = hn::RebindMask(di, hn::Not(finite));
    f = hn::IfThenElse(bad, hn::Set(di, static_cast<int32_t>(kNonFinite)),
                       hn::Or(f, hn::IfThenElseZero(guardOut, hn::Set(di, static_cast<int32_t>(kOutGuard)))));
    // Snapped position, z / w and 1 / w, where neither flag is set (elsewhere 0, and nothing out
    // of int32's range is converted).
    const auto keep = hn::Not(hn::Or(bad, guardOut));
    hn::StoreMaskBits(di, keep, bits);
    const auto keepD = hn::LoadMaskBits(dd, bits);
    const auto px = hn::IfThenElseZero(keepD, hn::Mul(hn::Add(hn::Mul(hn::Div(xd, wd), half), half), width));
    const auto py = hn::IfThenElseZero(keepD, hn::Mul(hn::Sub(half, hn::Mul(hn::Div(yd, wd), half)), height));
    const auto qx = hn::Sub(hn::DemoteTo(di, hn::Round(hn::Sub(hn::Mul(px, subpixel), halfSubpixel))), hn::Set(di, vp.sampleX));
    const auto qy = hn::Sub(hn::DemoteTo(di, hn::Round(hn::Sub(hn::Mul(py, subpixel), halfSubpixel))), hn::Set(di, vp.sampleY));
    const auto keepF = hn::RebindMask(df, keep);
    hn::StoreU(hn::IfThenElseZero(keep, qx), di, sx);
    hn::StoreU(hn::IfThenElseZero(keep, qy), di, sy);
    hn::StoreU(hn::IfThenElseZero(keepF, DemoteIeee(df, hn::Div(hn::PromoteTo(dd, z), wd))), df, sz);
    hn::StoreU(hn::IfThenElseZero(keepF, DemoteIeee(df, hn::Div(hn::Set(dd, 1.0), wd))), df, siw);
    hn::StoreU(f, di, flags);
    nonFinite += hn::CountTrue(di, bad);
    for (size_t l = 0; l < m; ++l)
      out[i0 + l] = ScreenVert{sx[l], sy[l], sz[l], siw[l], static_cast<uint32_t>(flags[l])};
  }
  return nonFinite;
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::raster {

HWY_EXPORT(SetupLanesImpl);
HWY_EXPORT(ProjectVerticesImpl);

uint64_t projectVertices(const float* clip, size_t n, const Viewport& vp, const GuardPlanes& guard, ScreenVert* out,
                         int64_t simd) {
  auto* fn = HWY_DISPATCH_TABLE(ProjectVerticesImpl)[simdDispatchIndex(simd)];
  return (fn ? fn : HWY_DISPATCH_TABLE(ProjectVerticesImpl)[0])(clip, n, vp, guard, out);
}

uint32_t setupLanes(const SetupGroupIn& in, int n, CullMode cull, const Viewport& vp, SetupTri* tris,
                    SetupAttr* attrs, uint64_t verdicts[4], int64_t simd) {
  auto* fn = HWY_DISPATCH_TABLE(SetupLanesImpl)[simdDispatchIndex(simd)];
  return (fn ? fn : HWY_DISPATCH_TABLE(SetupLanesImpl)[0])(in, n, cull, vp, tris, attrs, verdicts);
}

}  // namespace penumbra::raster
#endif
