#include "shadows/backproj.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "shadows/sampling.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

// Light samples and occluder rectangles live on a kBins x kBins lattice of the light: sample i at
// bin (qx, qy) stands for the point ((qx + 0.5) / kBins, (qy + 0.5) / kBins) of the light's uv.
constexpr int kBins = 1024;

// The first bin whose sample position is >= u (u in [0, 1]): samples in [u0, u1) are the bins in
// [binAt(u0), binAt(u1)).
inline int binAt(float u) {
  return std::clamp(static_cast<int>(std::ceil(u * static_cast<float>(kBins) - 0.5f)), 0, kBins);
}

// K = 64 W samples, jittered in the cells of a gx x gy grid (gx gy = K), as bitmasks: geX[t] holds
// the samples whose x bin is >= t (t in [0, kBins]), W words each; so are those in bins [a, b)
// geX[a] & ~geX[b].
struct LightBits {
  int words = 1;
  std::vector<uint16_t> qx, qy;
  std::vector<uint64_t> geX, geY;

  explicit LightBits(int samples) : words(samples / 64) {
    const int gx = 1 << ((std::countr_zero(static_cast<unsigned>(samples)) + 1) / 2), gy = samples / gx;
    for (int i = 0; i < samples; ++i) {
      const auto u = static_cast<uint32_t>(i);
      const float jx = unitFloat(hash3(u, 0xba5eu, static_cast<uint32_t>(samples)));
      const float jy = unitFloat(hash3(u, 0xba5fu, static_cast<uint32_t>(samples)));
      const float x = (static_cast<float>(i % gx) + jx) / static_cast<float>(gx);
      const float y = (static_cast<float>(i / gx) + jy) / static_cast<float>(gy);
      qx.push_back(static_cast<uint16_t>(std::min(kBins - 1, static_cast<int>(x * kBins))));
      qy.push_back(static_cast<uint16_t>(std::min(kBins - 1, static_cast<int>(y * kBins))));
    }
    geX = suffixMasks(qx);
    geY = suffixMasks(qy);
  }

 private:
  std::vector<uint64_t> suffixMasks(const std::vector<uint16_t>& q) const {
    const auto w = static_cast<size_t>(words);
    std::vector<uint64_t> ge((kBins + 1) * w, 0);
    for (int t = kBins - 1; t >= 0; --t)
      for (size_t k = 0; k < w; ++k)
        ge[static_cast<size_t>(t) * w + k] = ge[static_cast<size_t>(t + 1) * w + k];
    for (size_t i = 0; i < q.size(); ++i)
      for (int t = 0; t <= q[i]; ++t) ge[static_cast<size_t>(t) * w + i / 64] |= uint64_t{1} << (i % 64);
    return ge;
  }
};

// Bins [a, b) of the lattice after the pixel's toroidal shift s (sample bin q is at (q + s) mod
// kBins): as at most two intervals of unshifted bins, OR'ed into out.
template <int W>
inline void orShifted(const uint64_t* ge, int a, int b, int s, uint64_t* out) {
  auto orRange = [&](int lo, int hi) {
    const uint64_t *l = ge + static_cast<ptrdiff_t>(lo) * W, *h = ge + static_cast<ptrdiff_t>(hi) * W;
    for (int k = 0; k < W; ++k) out[k] |= l[k] & ~h[k];
  };
  a -= s, b -= s;
  if (a >= 0)
    orRange(a, b);
  else if (b <= 0)
    orRange(a + kBins, b + kBins);
  else
    orRange(0, b), orRange(a + kBins, kBins);
}

struct Counts {
  uint64_t searched = 0, texels = 0, patches = 0, lit = 0, blocked = 0, capped = 0, lone = 0;
};

enum class Occlusion { Bitmask, Area };

// The structure bounding the search areas' depths: min/max pyramid (HSM), stack (MSSM), or the
// pyramid's finest levels and a stack on level kYsmBase (YSM).
enum class Bounds { Hsm, Mssm, Ysm };
constexpr int kYsmBase = 2;

// A vertex of the microquad grid: a blocker texel's centre projected onto the light, in its uv.
struct Corner {
  double u = 0, v = 0;
  bool blocker = false;
};

// The area of triangle abc inside the unit square (Sutherland-Hodgman against its four sides).
inline double clippedArea(const Corner& a, const Corner& b, const Corner& c) {
  std::array<std::array<double, 2>, 8> poly{}, next{};
  poly[0] = {a.u, a.v}, poly[1] = {b.u, b.v}, poly[2] = {c.u, c.v};
  int n = 3;
  for (int side = 0; side < 4 && n > 0; ++side) {
    const int axis = side / 2;
    const double bound = side % 2;  // sides u >= 0, u <= 1, v >= 0, v <= 1
    auto inside = [&](const std::array<double, 2>& p) { return side % 2 ? p[axis] <= bound : p[axis] >= bound; };
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const auto& p = poly[static_cast<size_t>(k)];
      const auto& r = poly[static_cast<size_t>((k + 1) % n)];
      if (inside(p)) next[static_cast<size_t>(m++)] = p;
      if (inside(p) != inside(r)) {
        const double t = (bound - p[axis]) / (r[axis] - p[axis]);
        next[static_cast<size_t>(m++)] = {p[0] + t * (r[0] - p[0]), p[1] + t * (r[1] - p[1])};
      }
    }
    poly = next, n = m;
  }
  double twice = 0;
  for (int k = 0; k < n; ++k) {
    const auto& p = poly[static_cast<size_t>(k)];
    const auto& r = poly[static_cast<size_t>((k + 1) % n)];
    twice += p[0] * r[1] - r[0] * p[1];
  }
  return 0.5 * std::abs(twice);
}

// Twice the signed area of the triangle abc (counter-clockwise positive).
inline double cross(const Corner& a, const Corner& b, double u, double v) {
  return (b.u - a.u) * (v - a.v) - (b.v - a.v) * (u - a.u);
}


class Backproj final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const auto t0 = Clock::now();
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    occlusion_ = params.choice("occlusion") == "area" ? Occlusion::Area : Occlusion::Bitmask;
    samples_ = std::stoi(params.choice("samples"));
    cap_ = params.integer("search_cap");
    minMax_ = params.choice("minmax") == "on";
    gapFill_ = params.choice("gap_fill") == "on";
    quads_ = params.choice("micro") != "patches";
    outline_ = params.choice("micro") == "quads_outline";
    search_ = params.choice("search") == "mssm" ? Bounds::Mssm
              : params.choice("search") == "ysm" ? Bounds::Ysm
                                                 : Bounds::Hsm;
    // The map must hold every occluder a receiver's search area reaches, not only what lies in
    // front of the receivers (widenedView).
    const WidenedView wide = widenedView(ctx, size);
    map_.view = wide.view;
    renderDepthMap(ctx, map_);
    ctx.times.msMaps += msSince(t0);
    const auto t1 = Clock::now();
    ctx.raster.run([&] {
      pyramid_ = raster::buildMinMaxPyramid(map_.depth.image());
      stack_ = search_ == Bounds::Hsm ? raster::MinMaxStack{}
                                      : raster::buildMinMaxStack(pyramid_, search_ == Bounds::Ysm ? kYsmBase : 0);
    });
    if (occlusion_ == Occlusion::Bitmask) bits_ = LightBits(samples_);
    ctx.times.msFilter += msSince(t1);
    ctx.notes.push_back("backproj: 1 depth map " + std::to_string(map_.view.width) + "x" + std::to_string(map_.view.height) + wide.note +
                        (quads_ ? (outline_ ? ", microquads and outline micropatches, " : ", microquads, ") : ", micropatches, ") +
                        (occlusion_ == Occlusion::Area
                             ? std::string("area accumulation")
                             : "bitmask of " + std::to_string(samples_) + " light samples") +
                        ", search cap " + std::to_string(cap_) + " texels, search areas bounded by " +
                        (search_ == Bounds::Hsm   ? std::string("the min/max pyramid (HSM)")
                         : search_ == Bounds::Mssm ? "the min/max stack (MSSM, " + std::to_string(stack_.levels()) + " levels)"
                                                   : "the pyramid and, past " + std::to_string(2 << kYsmBase) +
                                                         " texels, the stack on its level " + std::to_string(kYsmBase) +
                                                         " (YSM)"));
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    tbb::enumerable_thread_specific<Counts> counts;
    if (occlusion_ == Occlusion::Area) {
      forEachReceiver(ctx, visibility,
                      [&](int, int, const Receiver& r) { return receiver<0>(ctx, r, 0, 0, counts.local()); });
    } else {
      forEachReceiver(
          ctx, visibility,
          [&](int x, int y, const Receiver& r) {
            const auto sx =
                static_cast<int>(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xbac1u) % kBins);
            const auto sy =
                static_cast<int>(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xbac2u) % kBins);
            Counts& c = counts.local();
            switch (bits_.words) {
              case 1:
                return receiver<1>(ctx, r, sx, sy, c);
              case 2:
                return receiver<2>(ctx, r, sx, sy, c);
              case 4:
                return receiver<4>(ctx, r, sx, sy, c);
              case 8:
                return receiver<8>(ctx, r, sx, sy, c);
              default:
                return receiver<16>(ctx, r, sx, sy, c);
            }
          },
          SelfShadow::Handled);
    }
    ctx.times.msEvaluate += msSince(t0);
    Counts sum;
    counts.combine_each([&](const Counts& c) {
      sum.searched += c.searched, sum.texels += c.texels, sum.patches += c.patches;
      sum.lit += c.lit, sum.blocked += c.blocked, sum.capped += c.capped, sum.lone += c.lone;
    });
    const double n = static_cast<double>(std::max<uint64_t>(sum.searched, 1));
    char line[400];
    std::snprintf(
        line, sizeof line,
        "backproj: %llu receivers searched, %.1f texels and %.1f %s each; %llu lit and %llu "
        "blocked by the min/max test without micro-occluders; %llu over the search cap (coarser level)",
        static_cast<unsigned long long>(sum.searched), static_cast<double>(sum.texels) / n,
        static_cast<double>(sum.patches) / n, quads_ ? "microtriangles (2 per quad)" : "micropatches",
        static_cast<unsigned long long>(sum.lit), static_cast<unsigned long long>(sum.blocked),
        static_cast<unsigned long long>(sum.capped));
    ctx.notes.push_back(line);
    if (quads_) {
      std::snprintf(line, sizeof line,
                    "backproj: %llu blocker texels in no microquad or microtriangle (lines and points one texel "
                    "wide) taken as micropatches",
                    static_cast<unsigned long long>(sum.lone));
      ctx.notes.push_back(line);
    }
  }

 private:
  // V of one receiver; W = 0: area accumulation, else a bitmask of W words, shifted by (sx, sy).
  template <int W>
  float receiver(const ShadowContext& ctx, const Receiver& r, int sx, int sy, Counts& c) const {
    std::array<uint64_t, (W > 0 ? W : 1)> mask{};
    if constexpr (W > 0) {
      if (!horizonBits<W>(ctx.in.light, r, sx, sy, mask.data())) return 0.0f;
    }
    const LightView& view = map_.view;
    const glm::vec3 v = lookupPoint(view, r, bias_);
    if (v.z <= view.znear) return visible<W>(mask.data());
    const ReceiverPlane plane(view, v, r.normal, bias_);
    const float dr = v.z, tpx = v.x / v.z, tpy = v.y / v.z;
    const glm::vec2 halfLight(0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height);
    // 1. The search area, shrunk twice by the nearest depth the pyramid finds in it.
    glm::vec2 half = halfLight * std::max(1.0f / view.znear - 1.0f / dr, 0.0f);
    for (int pass = 0; pass < 2; ++pass) {
      float mn, mx;
      bounds(map_.column(tpx - half.x), map_.row(tpy + half.y),
                          map_.column(tpx + half.x) + 1, map_.row(tpy - half.y) + 1, mn, mx);
      if (!(mx > 0.0f)) return visible<W>(mask.data());  // nothing drawn there
      half = halfLight * std::max(mx / view.znear - 1.0f / dr, 0.0f);
    }
    const int c0 = map_.column(tpx - half.x), c1 = map_.column(tpx + half.x) + 1;
    const int r0 = map_.row(tpy + half.y), r1 = map_.row(tpy - half.y) + 1;
    const BlockerPlane blocker{plane.tapPlane()};
    if (minMax_) {  // as testBox (shadow_map.h), with this plane
      float mn, mx;
      bounds(c0, r0, c1, r1, mn, mx);
      const float t00 = blocker.threshold(tpx - half.x, tpy - half.y),
                  t01 = blocker.threshold(tpx - half.x, tpy + half.y);
      const float t10 = blocker.threshold(tpx + half.x, tpy - half.y),
                  t11 = blocker.threshold(tpx + half.x, tpy + half.y);
      if (mx <= std::min(std::min(t00, t01), std::min(t10, t11)) * (1.0f - 1e-5f))
        return ++c.lit, visible<W>(mask.data());
      if (mn > std::max(std::max(t00, t01), std::max(t10, t11)) * (1.0f + 1e-5f)) return ++c.blocked, 0.0f;
    }
    ++c.searched;
    // 2. The level at which the area is at most search_cap texels wide; its texels are visited and
    // mixed ones refined (visit).
    int level = 0;
    while (std::max(c1 - c0, r1 - r0) > (cap_ << level) && level + 1 < pyramid_.levels()) ++level;
    if (level > 0) ++c.capped;
    thread_local std::vector<uint64_t> level0;
    level0.clear();
    Search<W> q{.plane = blocker,
                .c = c,
                .mask = mask,
                .tx = tpx,
                .ty = tpy,
                .bx0 = tpx - half.x,
                .bx1 = tpx + half.x,
                .by0 = tpy - half.y,
                .by1 = tpy + half.y,
                .drNear = dr * view.znear,
                .dr = dr,
                .invW = 1.0f / ctx.in.light.width,
                .invH = 1.0f / ctx.in.light.height,
                .sx = sx,
                .sy = sy,
                .level0 = &level0};
    for (int j = r0 >> level; j <= (r1 - 1) >> level; ++j)
      for (int i = c0 >> level; i <= (c1 - 1) >> level; ++i)
        if (visit<W>(q, level, i, j)) return 0.0f;
    if (quads_) {  // the level-0 blockers' quads, once the set of them is known (microquads)
      std::sort(level0.begin(), level0.end());
      for (const uint64_t key : level0)
        if (microquads<W>(q, static_cast<int>(key & 0xffffffffu), static_cast<int>(key >> 32))) return 0.0f;
    }
    if constexpr (W == 0) return std::max(0.0f, 1.0f - q.area);
    return visible<W>(q.mask.data());
  }

  // Depth bounds of the map texels [x0, x1) x [y0, y1): the pyramid's (HSM: at most 2 x 2 aligned
  // texels, loose), the stack's (MSSM: exact), or the pyramid's for areas up to 2^(kYsmBase + 1)
  // texels wide and the stack on level kYsmBase's for larger ones (YSM: exact to 2^kYsmBase texels).
  void bounds(int x0, int y0, int x1, int y1, float& mn, float& mx) const {
    if (search_ == Bounds::Hsm || (search_ == Bounds::Ysm && std::max(x1 - x0, y1 - y0) <= (2 << kYsmBase)))
      raster::queryMinMax(pyramid_, x0, y0, x1, y1, mn, mx);
    else
      raster::queryMinMax(stack_, x0, y0, x1, y1, mn, mx);
  }

  // One receiver's search: its plane, position and search box (tangent units), what it has found.
  template <int W>
  struct Search {
    const BlockerPlane& plane;
    Counts& c;
    std::array<uint64_t, (W > 0 ? W : 1)> mask;
    float tx, ty, bx0, bx1, by0, by1, drNear, dr, invW, invH;
    int sx, sy;
    std::vector<uint64_t>* level0;  // micro=quads: the level-0 blocker texels visited, as keys
    float area = 0.0f;
  };

  // Texel (i, j) of pyramid level `level`: skipped when no texel under it is a blocker (its nearest
  // depth is behind the receiver plane at all four corners), one patch when every texel is (at the
  // harmonic mean of its depth bounds), refined into its children otherwise; at level 0, a blocker
  // by PCF's test at its centre. True once the light is wholly covered.
  template <int W>
  bool visit(Search<W>& q, int level, int i, int j) const {
    ++q.c.texels;
    const auto l = static_cast<size_t>(level);
    const float sMax = pyramid_.maxs[l].at(i, j), sMin = pyramid_.mins[l].at(i, j);
    const TexelBox box = texelBox(level, i, j);
    const float txLeft = box.txLeft, txRight = box.txRight, tyTop = box.tyTop, tyBottom = box.tyBottom;
    float s = sMax;
    if (level == 0) {
      if (!(s > q.plane.threshold(0.5f * (txLeft + txRight), 0.5f * (tyTop + tyBottom)))) return false;
      if (quads_) return q.level0->push_back(texelKey(i, j)), false;
    } else {
      const float t00 = q.plane.threshold(txLeft, tyTop), t10 = q.plane.threshold(txRight, tyTop);
      const float t01 = q.plane.threshold(txLeft, tyBottom), t11 = q.plane.threshold(txRight, tyBottom);
      if (!(sMax > std::min(std::min(t00, t10), std::min(t01, t11)))) return false;  // no blocker under it
      if (!(sMin > std::max(std::max(t00, t10), std::max(t01, t11)))) {              // mixed: its children
        const int n = level - 1, cw = pyramid_.maxs[l - 1].width(), ch = pyramid_.maxs[l - 1].height();
        for (int cj = 2 * j; cj < std::min(2 * j + 2, ch); ++cj)
          for (int ci = 2 * i; ci < std::min(2 * i + 2, cw); ++ci)
            if (visit<W>(q, n, ci, cj)) return true;
        return false;
      }
      // Bitmask: the farthest; the nearest, sMax, bounds the rectangle too (below). Area
      // accumulation, which counts overlaps, takes one patch at the harmonic mean (the mean of the
      // stored near / depth).
      s = W == 0 ? 0.5f * (sMin + sMax) : sMin;
    }
    return patch<W>(q, level, i, j, s, level == 0 || W == 0 ? s : sMax);
  }

  // Texel (i, j) of `level` in tangent units: its left, right, top and bottom edges.
  struct TexelBox {
    float txLeft, txRight, tyTop, tyBottom;
  };
  TexelBox texelBox(int level, int i, int j) const {
    const LightView& view = map_.view;
    const int colLeft = i << level, colRight = std::min((i + 1) << level, view.width);
    const int rowTop = j << level, rowBottom = std::min((j + 1) << level, view.height);
    const float dtx = (view.tanHi.x - view.tanLo.x) / static_cast<float>(view.width);
    const float dty = (view.tanHi.y - view.tanLo.y) / static_cast<float>(view.height);
    return {view.tanLo.x + static_cast<float>(colLeft) * dtx, view.tanLo.x + static_cast<float>(colRight) * dtx,
            view.tanHi.y - static_cast<float>(rowTop) * dty, view.tanHi.y - static_cast<float>(rowBottom) * dty};
  }

  // The micropatch of texel (i, j) of `level`, a blocker at stored depth s (near / z); sNear >= s
  // the nearest of a coarse texel's blockers, whose square's projection the patch covers as well.
  template <int W>
  bool patch(Search<W>& q, int level, int i, int j, float s, float sNear) const {
    const LightView& view = map_.view;
    auto [txLeft, txRight, tyTop, tyBottom] = texelBox(level, i, j);
    const int colLeft = i << level, colRight = std::min((i + 1) << level, view.width);
    const int rowTop = j << level, rowBottom = std::min((j + 1) << level, view.height);
    // The map's edge texels stand for what lies beyond it, as a clamped lookup reads them (every
    // technique here does): they reach to the search area's edge. Right for a surface that leaves
    // the map (a wall beside the light); an occluder that covers the whole map grows with it.
    if (colLeft == 0) txLeft = std::min(txLeft, q.bx0);
    if (colRight == view.width) txRight = std::max(txRight, q.bx1);
    if (rowTop == 0) tyTop = std::max(tyTop, q.by1);
    if (rowBottom == view.height) tyBottom = std::min(tyBottom, q.by0);
    const float denom = q.dr * s - view.znear;  // d_r (1 - z / d_r) s
    if (!(denom > 0.0f)) return false;
    // 3. The micropatch's rectangle on the light, in the light's uv: at level 0 the texel's square
    // at its depth; with the bitmask, a coarse texel of blockers at depths [z_near, z_far] covers
    // the bounding rectangle of its square's projections at both (its texels' patches lie between
    // them: their union is covered, a little more where the depth varies; no crack opens inside).
    const float f = q.drNear / denom;  // d_r z / (d_r - z)
    const float g = sNear == s ? f : q.drNear / (q.dr * sNear - view.znear);
    auto lo = [&](float t, float tp, float inv) { return std::min(f * (t - tp), g * (t - tp)) * inv + 0.5f; };
    auto hi = [&](float t, float tp, float inv) { return std::max(f * (t - tp), g * (t - tp)) * inv + 0.5f; };
    float u0 = lo(txLeft, q.tx, q.invW), u1 = hi(txRight, q.tx, q.invW);
    float v0 = lo(tyBottom, q.ty, q.invH), v1 = hi(tyTop, q.ty, q.invH);
    if (gapFill_) {
      // Gap filling (Guennebaud et al. 2006): where a neighbouring texel is a blocker at another
      // depth, the two patches' shared edge projects to two places on the light; the patch reaches
      // to its neighbour's projection of that edge, so no light passes between them (a surface
      // seen at a grazing angle is a staircase of patches otherwise).
      auto edge = [&](int ni, int nj, float t, float tp, float inv) {
        const float sn = blockerAt(q, level, ni, nj);
        const float dn = q.dr * sn - view.znear;
        return dn > 0.0f ? q.drNear / dn * (t - tp) * inv + 0.5f : NAN;
      };
      const float eL = edge(i - 1, j, txLeft, q.tx, q.invW), eR = edge(i + 1, j, txRight, q.tx, q.invW);
      const float eT = edge(i, j - 1, tyTop, q.ty, q.invH), eB = edge(i, j + 1, tyBottom, q.ty, q.invH);
      if (eL < u0) u0 = eL;  // false for NaN: no blocker there
      if (eR > u1) u1 = eR;
      if (eB < v0) v0 = eB;
      if (eT > v1) v1 = eT;
    }
    if (u1 <= 0.0f || u0 >= 1.0f || v1 <= 0.0f || v0 >= 1.0f) return false;
    ++q.c.patches;
    const float cu0 = std::max(u0, 0.0f), cu1 = std::min(u1, 1.0f);
    const float cv0 = std::max(v0, 0.0f), cv1 = std::min(v1, 1.0f);
    if constexpr (W == 0) {
      q.area += (cu1 - cu0) * (cv1 - cv0);
      return q.area >= 1.0f;
    } else {
      std::array<uint64_t, W> xs{}, ys{};
      orShifted<W>(bits_.geX.data(), binAt(cu0), binAt(cu1), q.sx, xs.data());
      orShifted<W>(bits_.geY.data(), binAt(cv0), binAt(cv1), q.sy, ys.data());
      uint64_t all = ~uint64_t{0};
      for (size_t k = 0; k < static_cast<size_t>(W); ++k) q.mask[k] |= xs[k] & ys[k], all &= q.mask[k];
      return all == ~uint64_t{0};
    }
  }

  // The stored value of texel (i, j) of `level` as a gap-filling neighbour: its own (level 0) or
  // its farthest (a coarse texel wholly of blockers; else its nearest), or 0 when it is outside the
  // map or no blocker at its centre.
  template <int W>
  float blockerAt(const Search<W>& q, int level, int i, int j) const {
    const auto l = static_cast<size_t>(level);
    const raster::ImageFloat& mx = pyramid_.maxs[l];
    if (i < 0 || j < 0 || i >= mx.width() || j >= mx.height()) return 0.0f;
    const glm::vec2 t = centre(level, i, j);
    const float sMax = mx.at(i, j), threshold = q.plane.threshold(t.x, t.y);
    if (!(sMax > threshold)) return 0.0f;
    const float sMin = pyramid_.mins[l].at(i, j);
    return sMin > threshold ? sMin : sMax;  // the farthest blocker depth it has, as far as known
  }

  // The centre of texel (i, j) of pyramid level `level`, in tangent units (the last texel of a
  // level may be cut by the map's edge).
  glm::vec2 centre(int level, int i, int j) const {
    const LightView& view = map_.view;
    const float cx = 0.5f * static_cast<float>((i << level) + std::min((i + 1) << level, view.width));
    const float cy = 0.5f * static_cast<float>((j << level) + std::min((j + 1) << level, view.height));
    return {view.tanLo.x + cx * (view.tanHi.x - view.tanLo.x) / static_cast<float>(view.width),
            view.tanHi.y - cy * (view.tanHi.y - view.tanLo.y) / static_cast<float>(view.height)};
  }

  // Microquads (Schwarz & Stamminger 2008) around the level-0 blocker texel (i, j): the four quads
  // between its centre and its neighbours' centres, each corner at its texel's depth and projected
  // onto the light; a quad whose four corners are blockers is two triangles, one with three is the
  // triangle of those (a microtriangle: an occluder's outline or a depth discontinuity). Quads
  // share their edges, so no crack opens at any depth difference (gap filling is built in); the
  // outline lies half a texel inside the micropatches'. micro=quads_outline: a texel with a
  // non-blocker among its eight neighbours adds its micropatch, which puts the outline back where
  // micropatches have it. A blocker texel in no quad or triangle (a line or point one texel wide,
  // which quads would drop) is taken as its micropatch. Each quad with a visited level-0 blocker
  // corner is emitted once, by the first such corner in row order (a quad whose blockers are all
  // inside coarse texels taken whole is left to their rectangles, which gap filling joins; area
  // accumulation sums outline patches over their quads). Beyond the map's edge a corner stands at
  // the search area's edge with the edge texel's depth (as patch()). True once the light is wholly
  // covered.
  template <int W>
  bool microquads(Search<W>& q, int i, int j) const {
    std::array<Corner, 9> c;  // (di, dj) in [-1, 1]^2 at 3 (dj + 1) + di + 1
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) c[static_cast<size_t>(3 * (dj + 1) + di + 1)] = corner(q, i + di, j + dj);
    bool used = false;
    for (int qj = 0; qj < 2; ++qj)
      for (int qi = 0; qi < 2; ++qi) {
        const int k = 3 * qj + qi;
        const Corner* around[4] = {&c[static_cast<size_t>(k)], &c[static_cast<size_t>(k + 1)],
                                   &c[static_cast<size_t>(k + 4)], &c[static_cast<size_t>(k + 3)]};
        const Corner* tri[4];
        int n = 0;
        for (const Corner* x : around)
          if (x->blocker) tri[n++] = x;
        if (n < 3) continue;
        used = true;
        // Once per quad: from its first corner in row order that is a visited blocker (this texel
        // is at 4, the quad's corners at k, k + 1, k + 3, k + 4).
        bool first = true;
        for (int e : {k, k + 1, k + 3})
          if (e < 4 && c[static_cast<size_t>(e)].blocker)
            first &= !std::binary_search(q.level0->begin(), q.level0->end(),
                                         texelKey(i + e % 3 - 1, j + e / 3 - 1));
        if (!first) continue;
        if (triangle<W>(q, *tri[0], *tri[1], *tri[2])) return true;
        if (n == 4 && triangle<W>(q, *tri[0], *tri[2], *tri[3])) return true;
      }
    bool outline = false;
    if (outline_)
      for (const Corner& x : c) outline |= !x.blocker;
    if (used && !outline) return false;
    if (!used) ++q.c.lone;
    const float s = pyramid_.maxs[0].at(i, j);
    return patch<W>(q, 0, i, j, s, s);
  }

  // The sort key of map texel (i, j): row-major order (texels outside the map are never keys).
  static uint64_t texelKey(int i, int j) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(j)) << 32) | static_cast<uint32_t>(i);
  }

  // Texel (i, j) of the map as a microquad corner: its centre projected from the receiver onto the
  // light, where it is a blocker (blockerAt). Outside the map: the nearest edge texel's depth, at
  // the search area's edge if that is farther out.
  template <int W>
  Corner corner(const Search<W>& q, int i, int j) const {
    const LightView& view = map_.view;
    Corner r;
    const int ci = std::clamp(i, 0, view.width - 1), cj = std::clamp(j, 0, view.height - 1);
    const float s = blockerAt(q, 0, ci, cj);
    const float denom = q.dr * s - view.znear;
    if (!(s > 0.0f) || !(denom > 0.0f)) return r;
    const auto dtx = static_cast<double>(view.tanHi.x - view.tanLo.x) / view.width;
    const auto dty = static_cast<double>(view.tanHi.y - view.tanLo.y) / view.height;
    double tx = static_cast<double>(view.tanLo.x) + (i + 0.5) * dtx;
    double ty = static_cast<double>(view.tanHi.y) - (j + 0.5) * dty;
    if (i < 0) tx = std::min(tx, static_cast<double>(q.bx0));
    if (i >= view.width) tx = std::max(tx, static_cast<double>(q.bx1));
    if (j < 0) ty = std::max(ty, static_cast<double>(q.by1));
    if (j >= view.height) ty = std::min(ty, static_cast<double>(q.by0));
    const double f = static_cast<double>(q.drNear) / static_cast<double>(denom);
    r.u = f * (tx - static_cast<double>(q.tx)) * static_cast<double>(q.invW) + 0.5;
    r.v = f * (ty - static_cast<double>(q.ty)) * static_cast<double>(q.invH) + 0.5;
    r.blocker = std::isfinite(r.u) && std::isfinite(r.v);
    return r;
  }

  // Marks the light samples inside triangle abc (uv of the light), exactly: the samples of its
  // bounding rectangle (the bin tables) not yet marked, each tested against its three edges in
  // double. Area accumulation adds its area inside the light. True once the light is covered.
  template <int W>
  bool triangle(Search<W>& q, const Corner& a, const Corner& b, const Corner& c) const {
    const double twice = cross(a, b, c.u, c.v);
    if (!(std::abs(twice) > 0.0)) return false;
    const double u0 = std::min({a.u, b.u, c.u}), u1 = std::max({a.u, b.u, c.u});
    const double v0 = std::min({a.v, b.v, c.v}), v1 = std::max({a.v, b.v, c.v});
    if (u1 <= 0.0 || u0 >= 1.0 || v1 <= 0.0 || v0 >= 1.0) return false;
    ++q.c.patches;
    if constexpr (W == 0) {
      q.area += static_cast<float>(clippedArea(a, b, c));
      return q.area >= 1.0f;
    } else {
      std::array<uint64_t, W> xs{}, ys{};
      orShifted<W>(bits_.geX.data(), binAt(static_cast<float>(std::max(u0, 0.0))),
                   binAt(static_cast<float>(std::min(u1, 1.0))), q.sx, xs.data());
      orShifted<W>(bits_.geY.data(), binAt(static_cast<float>(std::max(v0, 0.0))),
                   binAt(static_cast<float>(std::min(v1, 1.0))), q.sy, ys.data());
      const double sign = twice > 0.0 ? 1.0 : -1.0;
      uint64_t all = ~uint64_t{0};
      for (size_t k = 0; k < static_cast<size_t>(W); ++k) {
        uint64_t candidates = xs[k] & ys[k] & ~q.mask[k];
        while (candidates != 0) {
          const int bit = std::countr_zero(candidates);
          candidates &= candidates - 1;
          const size_t s = k * 64 + static_cast<size_t>(bit);
          const double u = (static_cast<double>((bits_.qx[s] + q.sx) % kBins) + 0.5) / kBins;
          const double v = (static_cast<double>((bits_.qy[s] + q.sy) % kBins) + 0.5) / kBins;
          if (sign * cross(a, b, u, v) >= 0.0 && sign * cross(b, c, u, v) >= 0.0 && sign * cross(c, a, u, v) >= 0.0)
            q.mask[k] |= uint64_t{1} << bit;
        }
        all &= q.mask[k];
      }
      return all == ~uint64_t{0};
    }
  }

  // The unmarked fraction of the bitmask (W = 0: 1, area accumulation's start).
  template <int W>
  static float visible(const uint64_t* mask) {
    if constexpr (W == 0) {
      return 1.0f;
    } else {
      int set = 0;
      for (int k = 0; k < W; ++k) set += std::popcount(mask[k]);
      return static_cast<float>(64 * W - set) / static_cast<float>(64 * W);
    }
  }

  // Marks the samples below r's tangent plane (dot(n, y - x) <= 0); false when that is all of them.
  template <int W>
  bool horizonBits(const RectLight& light, const Receiver& r, int sx, int sy, uint64_t* mask) const {
    const glm::vec3 p = toLightSpace(light, r.position);
    const glm::vec3 n(glm::dot(r.normal, light.right), glm::dot(r.normal, light.up),
                      glm::dot(r.normal, light.normal()));
    const float k = glm::dot(n, p);
    const float hw = 0.5f * light.width, hh = 0.5f * light.height;
    int above = 0;
    for (float cx : {-hw, hw})
      for (float cy : {-hh, hh}) above += n.x * cx + n.y * cy > k ? 1 : 0;
    if (above == 4) return true;
    if (above == 0) return false;
    for (int i = 0; i < 64 * W; ++i) {
      const auto ui = static_cast<size_t>(i);
      const float u = (static_cast<float>((bits_.qx[ui] + sx) % kBins) + 0.5f) / kBins;
      const float w = (static_cast<float>((bits_.qy[ui] + sy) % kBins) + 0.5f) / kBins;
      if (!(n.x * (u - 0.5f) * light.width + n.y * (w - 0.5f) * light.height > k))
        mask[i / 64] |= uint64_t{1} << (i % 64);
    }
    return true;
  }

  ShadowMap map_;
  BiasParams bias_;
  raster::MinMaxPyramid pyramid_;
  raster::MinMaxStack stack_;
  Bounds search_ = Bounds::Hsm;
  LightBits bits_{64};
  Occlusion occlusion_ = Occlusion::Bitmask;
  int samples_ = 256, cap_ = 32;
  bool minMax_ = true, gapFill_ = true, quads_ = false, outline_ = false;
};

}  // namespace

TechniqueInfo backprojTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512);
  p.push_back(choiceParam("occlusion", 0, {"bitmask", "area"},
                          "light occlusion from the micropatches: a bitmask of light samples (overlaps count once) "
                          "or summed clipped areas (overlaps count twice)"));
  p.push_back(choiceParam("samples", 2, {"64", "128", "256", "512", "1024"}, "light samples of the bitmask"));
  p.push_back({.name = "search_cap", .kind = ParamKind::Int, .defaultValue = 32, .minValue = 2, .maxValue = 8192,
               .choices = {}, .help = "widest search area in texels; wider ones are searched at a coarser level"});
  p.push_back(choiceParam("gap_fill", 1, {"off", "on"},
                          "extend each micropatch to its blocking neighbours' projections (closes the cracks between "
                          "patches at different depths; joins distinct occluders that touch in the map)"));
  p.push_back(choiceParam("micro", 0, {"patches", "quads", "quads_outline"},
                          "micro-occluders: each blocker texel's square at its depth (micropatches); quads between "
                          "neighbouring blocker texels' centres, triangles where one of four is not (microquads: "
                          "no cracks, the outline half a texel in); or microquads with the outline texels' "
                          "patches (the outline where micropatches put it). gap_fill applies to patches only"));
  p.push_back(choiceParam("search", 2, {"hsm", "mssm", "ysm"},
                          "depth bounds of the search areas: min/max pyramid (HSM, cheap, loose), min/max stack "
                          "(MSSM, exact, a full-size image per level), or both (YSM: the pyramid up to 8 texels, "
                          "the stack on 4x4 texels beyond)"));
  p.push_back(choiceParam("minmax", 1, {"off", "on"},
                          "settle receivers whose search area is uniformly lit (same V) or blocked (V = 0, where the "
                          "micropatches may leave cracks) by the min/max pyramid"));
  return {.name = "backproj",
          .summary =
              "backprojection soft shadow mapping: micropatches from one depth map projected onto the light, "
              "occlusion bitmask",
          .params = std::move(p),
          .benchSettings = {"samples=64", "", "samples=1024", "occlusion=area", "gap_fill=off", "micro=quads", "micro=quads_outline,gap_fill=off", "search=hsm", "search=mssm",
                            "search_cap=16", "search_cap=64"},
          .isReference = false,
          .make = [] { return std::make_unique<Backproj>(); },
          // The widened map (up to 2 map_size per side): depth, its render target and the min/max
          // pyramid, 16 bytes per texel; the stack, 8 bytes per texel and level (MSSM: one level
          // per doubling of the side; YSM: on a grid 4x4 times smaller); microquads' texel list; the
          // bitmask's tables.
          .peakBytes = [](const ParamSet& params, uint64_t) -> uint64_t {
            const auto side = 2 * static_cast<uint64_t>(params.integer("map_size"));
            const auto words = static_cast<uint64_t>(std::stoi(params.choice("samples")) / 64);
            const std::string search = params.choice("search");
            const uint64_t grid = search == "ysm" ? side >> kYsmBase : side;
            const uint64_t stack = search == "hsm" ? 0 : grid * grid * 8 * (std::bit_width(grid) + 1);
            // Microquads: a search's list of level-0 blocker texels (8 bytes each), at worst the map.
            const uint64_t quads = params.choice("micro") == "patches" ? 0 : side * side * 8;
            return side * side * 16 + stack + quads + 2 * (kBins + 1) * words * 8;
          }};
}

}  // namespace penumbra::shadows
