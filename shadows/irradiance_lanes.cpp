// irradianceFactors (area_light.h): Lambert's polygon formula for up to 16 receivers at a time, one
// per float lane, compiled once per Highway target.
//
// Exactness, lane by lane against irradianceFactor: the lanes repeat its float operations in its
// order (glm's dot is (x * x' + y * y') + z * z', its cross x.y * y.z - y.y * x.z and so on; no
// FMA, -ffp-contract=off); Sqrt and Div are IEEE on every target; std::min(pi, v) is
// (pi < v) ? pi : v. The scalar code skips an edge whose cross product is zero or NaN; a lane adds
// +0 instead, which leaves the sum alone except that -0 + +0 is +0, and the result takes |sum|.
// Lanes whose rectangle dips below the tangent plane (the scalar code clips it to 3 or 5 corners)
// are recomputed by irradianceFactor.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shadows/irradiance_lanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "raster/simd.h"
#include "shadows/area_light.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::shadows {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using DF = hn::CappedTag<float, 16>;
using VF = hn::Vec<DF>;

struct V3 {
  VF x, y, z;
};

HWY_INLINE V3 operator+(const V3& a, const V3& b) { return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)}; }
HWY_INLINE V3 operator-(const V3& a, const V3& b) { return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)}; }
HWY_INLINE V3 scaled(const V3& a, VF s) { return {hn::Mul(a.x, s), hn::Mul(a.y, s), hn::Mul(a.z, s)}; }
HWY_INLINE VF dot(const V3& a, const V3& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
HWY_INLINE V3 cross(const V3& a, const V3& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(b.y, a.z)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(b.z, a.x)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(b.x, a.y))};
}
HWY_INLINE V3 broadcast(DF df, glm::vec3 v) { return {hn::Set(df, v.x), hn::Set(df, v.y), hn::Set(df, v.z)}; }

// lambertAtan2, lane by lane (area_light.cpp), for y > 0.
HWY_INLINE VF atan2Lanes(DF df, VF y, VF x) {
  using namespace lambert;
  const VF one = hn::Set(df, 1.0f);
  const VF ax = hn::Abs(x);
  const auto steep = hn::Lt(ax, y);
  const VF t = hn::Div(hn::IfThenElse(steep, ax, y), hn::IfThenElse(steep, y, ax));
  const auto reduced = hn::Lt(hn::Set(df, kTanPi8), t);
  const VF u = hn::IfThenElse(reduced, hn::Div(hn::Sub(t, one), hn::Add(t, one)), t);
  const VF z = hn::Mul(u, u);
  VF p = hn::Sub(hn::Mul(hn::Set(df, kP0), z), hn::Set(df, kP1));
  p = hn::Add(hn::Mul(p, z), hn::Set(df, kP2));
  p = hn::Sub(hn::Mul(p, z), hn::Set(df, kP3));
  p = hn::Add(hn::Mul(hn::Mul(p, z), u), u);
  VF r = hn::IfThenElse(reduced, hn::Add(hn::Set(df, kPi4), p), p);
  r = hn::IfThenElse(steep, hn::Sub(hn::Set(df, kPi2), r), r);
  return hn::IfThenElse(hn::Lt(x, hn::Zero(df)), hn::Sub(hn::Set(df, kPi), r), r);
}

}  // namespace

void IrradianceFactorsImpl(const RectLight& light, const SurfacePoints& pts, int n, float* out) {
  const DF df;
  const int lanes = static_cast<int>(hn::Lanes(df));
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f), pi = hn::Set(df, lambert::kPi);
  const V3 center = broadcast(df, light.center), ln = broadcast(df, light.normal());
  const V3 hw = broadcast(df, 0.5f * light.width * light.right), hh = broadcast(df, 0.5f * light.height * light.up);
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const V3 x{hn::LoadU(df, pts.px + i), hn::LoadU(df, pts.py + i), hn::LoadU(df, pts.pz + i)};
    const V3 nrm{hn::LoadU(df, pts.nx + i), hn::LoadU(df, pts.ny + i), hn::LoadU(df, pts.nz + i)};
    const auto behind = hn::Le(dot(x - center, ln), zero);
    const V3 c = center - x;
    const V3 quad[4] = {c - hw - hh, c + hw - hh, c + hw + hh, c - hw + hh};
    auto above = hn::Ge(dot(nrm, quad[0]), zero);
    for (int k = 1; k < 4; ++k) above = hn::And(above, hn::Ge(dot(nrm, quad[k]), zero));
    V3 u[4];
    for (int k = 0; k < 4; ++k) u[k] = scaled(quad[k], hn::Div(one, hn::Sqrt(dot(quad[k], quad[k]))));
    VF sum = zero;
    for (int k = 0; k < 4; ++k) {
      const V3& a = u[k];
      const V3& b = u[(k + 1) & 3];
      const V3 cr = cross(a, b);
      const VF s = hn::Sqrt(dot(cr, cr));
      const VF term = hn::Mul(atan2Lanes(df, s, dot(a, b)), hn::Div(dot(nrm, cr), s));
      sum = hn::Add(sum, hn::IfThenElseZero(hn::Lt(zero, s), term));
    }
    VF r = hn::Abs(hn::Mul(half, sum));
    r = hn::IfThenElse(hn::Lt(pi, r), pi, r);
    hn::StoreU(hn::IfThenZeroElse(behind, r), df, out + i);
    const auto clipped = hn::AndNot(behind, hn::Not(above));
    if (hn::AllFalse(df, clipped)) continue;
    const hn::RebindToSigned<DF> di;
    HWY_ALIGN int32_t flags[16];
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, clipped)), di, flags);
    for (int j = 0; j < lanes; ++j)
      if (flags[j] != 0) {
        const int k = i + j;
        out[k] = irradianceFactor(light, {pts.px[k], pts.py[k], pts.pz[k]}, {pts.nx[k], pts.ny[k], pts.nz[k]});
      }
  }
  for (; i < n; ++i)
    out[i] = irradianceFactor(light, {pts.px[i], pts.py[i], pts.pz[i]}, {pts.nx[i], pts.ny[i], pts.nz[i]});
}

}  // namespace HWY_NAMESPACE
}  // namespace penumbra::shadows
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::shadows {

HWY_EXPORT(IrradianceFactorsImpl);

void irradianceFactors(const RectLight& light, const SurfacePoints& points, int n, float* out, int64_t simd) {
  auto* fn = HWY_DISPATCH_TABLE(IrradianceFactorsImpl)[raster::simdDispatchIndex(simd)];
  (fn ? fn : HWY_DISPATCH_TABLE(IrradianceFactorsImpl)[0])(light, points, n, out);
}

}  // namespace penumbra::shadows
#endif
