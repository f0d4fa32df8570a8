#include "stochastic/bounds.h"

#include <algorithm>
#include <cmath>

namespace penumbra::stochastic {

namespace {

// Snapping moves a vertex by at most 1/512 pixel per axis; float rounding of the clip coordinates
// (the lerp, the lens shear) adds ~1e-4 pixel on screen and ~1e-3 at the guard band's edge.
constexpr double kMarginPixels = 1.0 / 64.0;
constexpr double kRelTol = 1e-6;  // float clip coordinates carry ~6e-8 relative error per operation

struct P4 {
  double x, y, z, w;
};

double lerp(float a, float b, double t) { return double{a} + (double{b} - double{a}) * t; }

P4 vertexAt(const glm::vec4& a, const glm::vec4& b, double t, double u, double v, const ThinLens& lens) {
  P4 p{lerp(a.x, b.x, t), lerp(a.y, b.y, t), lerp(a.z, b.z, t), lerp(a.w, b.w, t)};
  if (lens.active()) {
    const double d = p.w - double{lens.focusW};
    p.x += u * double{lens.kx} * d;
    p.y += v * double{lens.ky} * d;
  }
  return p;
}

}  // namespace

PixelRect footprint(const glm::vec4 c0[3], const glm::vec4 c1[3], const Domain& d, const ThinLens& lens, bool motion,
                    int width, int height) {
  P4 pts[24];
  int n = 0;
  const int nt = motion ? 2 : 1, nl = lens.active() ? 2 : 1;
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < nt; ++a)
      for (int b = 0; b < nl; ++b)
        for (int c = 0; c < nl; ++c) {
          const double t = motion ? double{a ? d.t1 : d.t0} : 0.0;
          pts[n++] = vertexAt(c0[i], motion ? c1[i] : c0[i], t, double{b ? d.u1 : d.u0}, double{c ? d.v1 : d.v0}, lens);
        }
  const PixelRect whole{0, 0, width - 1, height - 1};
  double lox = HUGE_VAL, hix = -HUGE_VAL, loy = HUGE_VAL, hiy = -HUGE_VAL;
  bool any = false, unbounded = false;
  double wmin = HUGE_VAL;  // over the projected points (the near plane's crossings included)
  auto add = [&](const P4& p) {
    if (!(p.w > 0.0)) {
      unbounded = true;
      return;
    }
    const double sx = (p.x / p.w * 0.5 + 0.5) * width, sy = (0.5 - p.y / p.w * 0.5) * height;
    if (!std::isfinite(sx) || !std::isfinite(sy)) {
      unbounded = true;
      return;
    }
    lox = std::min(lox, sx), hix = std::max(hix, sx), loy = std::min(loy, sy), hiy = std::max(hiy, sy);
    wmin = std::min(wmin, p.w);
    any = true;
  };
  // Near-plane clipping of the hull: the points in front, and where each segment from a point in
  // front to one behind crosses z = 0 (a superset of the clipped hull's vertices).
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(pts[i].x) || !std::isfinite(pts[i].y) || !std::isfinite(pts[i].z) || !std::isfinite(pts[i].w))
      return whole;  // non-finite input: the per-sample test drops it; bound nothing away
    if (pts[i].z < 0.0) continue;
    add(pts[i]);
    for (int j = 0; j < n; ++j) {
      if (!(pts[j].z < 0.0)) continue;
      const double s = pts[i].z / (pts[i].z - pts[j].z);
      add({pts[i].x + s * (pts[j].x - pts[i].x), pts[i].y + s * (pts[j].y - pts[i].y), 0.0,
           pts[i].w + s * (pts[j].w - pts[i].w)});
    }
  }
  if (unbounded) return whole;
  if (!any) return {};
  // The exact test computes the vertices in float: its rounding grows with the magnitudes of the
  // trajectory's ends (not with the position at the sample's time) over the smallest w in reach.
  double magnitude = 0.0;
  for (int i = 0; i < n; ++i)
    magnitude = std::max(magnitude, std::abs(pts[i].x) + std::abs(pts[i].y) + std::abs(pts[i].w));
  for (int i = 0; i < 3; ++i) {
    const glm::vec4& a = c0[i];
    const glm::vec4& b = c1[i];
    magnitude = std::max(magnitude, double{std::abs(a.x)} + double{std::abs(a.y)} + double{std::abs(a.w)} +
                                        double{std::abs(b.x)} + double{std::abs(b.y)} + double{std::abs(b.w)});
  }
  const double margin = kMarginPixels + kRelTol * magnitude / std::max(wmin, 1e-30) * std::max(width, height);
  if (!std::isfinite(margin) || margin > 4.0 * std::max(width, height)) return whole;
  // Pixel i is sampled at i + 0.5.
  auto lo = [&](double s, int size) {
    return static_cast<int>(std::clamp(std::ceil(s - 0.5 - margin), 0.0, static_cast<double>(size)));
  };
  auto hi = [&](double s, int size) {
    return static_cast<int>(std::clamp(std::floor(s - 0.5 + margin), -1.0, static_cast<double>(size - 1)));
  };
  return {lo(lox, width), lo(loy, height), hi(hix, width), hi(hiy, height)};
}

namespace {

// Linear functions of s on [0, 1], given by their values at the two ends, plus a tolerance: the
// hull of the set of s where at least one is >= -tol. Returns false when that set is empty.
struct Lines {
  double a[12], b[12], tol[12];
  int n = 0;
  void add(double va, double vb, double tolerance) {
    a[n] = va, b[n] = vb, tol[n] = tolerance;
    ++n;
  }
  bool hull(double& s0, double& s1) const {
    double e0 = 0.0, e1 = 1.0;  // where every line is < -tol: (e0, e1), closed at an end left alone
    bool lo = true, hi = true;  // the excluded set reaches s = 0 / s = 1
    for (int i = 0; i < n; ++i) {
      const double ga = a[i] + tol[i], gb = b[i] + tol[i];
      if (ga >= 0.0 && gb >= 0.0) {
        s0 = 0.0, s1 = 1.0;  // this line alone allows everything
        return true;
      }
      if (ga < 0.0 && gb < 0.0) continue;
      const double r = ga / (ga - gb);  // crossing
      if (ga < 0.0) {
        e1 = std::min(e1, r);  // excluded below r
        hi = false;
      } else {
        e0 = std::max(e0, r);  // excluded above r
        lo = false;
      }
    }
    if (e0 >= e1 && !(lo && hi)) {
      s0 = 0.0, s1 = 1.0;
      return true;
    }
    if (lo && hi) return false;
    constexpr double kPad = 1e-9;
    if (lo) {
      s0 = std::max(0.0, e1 - kPad), s1 = 1.0;
    } else if (hi) {
      s0 = 0.0, s1 = std::min(1.0, e0 + kPad);
    } else {
      s0 = 0.0, s1 = 1.0;
    }
    return true;
  }
};

// Side k of the rectangle as a homogeneous half-plane: a point is on the rectangle's side when
// sx * x + sy * y + sw * w >= 0.
struct Side {
  double sx, sy, sw;
};

double sideValue(const Side& s, const P4& p) { return s.sx * p.x + s.sy * p.y + s.sw * p.w; }
double sideScale(const Side& s, const P4& p) {
  return std::abs(s.sx * p.x) + std::abs(s.sy * p.y) + std::abs(s.sw * p.w) + std::abs(p.w);
}

}  // namespace

bool dualSpaceDomain(const glm::vec4 c0[3], const glm::vec4 c1[3], const ThinLens& lens, bool motion,
                     const PixelRect& r, int width, int height, Domain& d) {
  // NDC of the extreme pixel centres, widened by the margin.
  const double x0 = (r.x0 + 0.5 - kMarginPixels) / width * 2.0 - 1.0;
  const double x1 = (r.x1 + 0.5 + kMarginPixels) / width * 2.0 - 1.0;
  const double yTop = 1.0 - (r.y0 + 0.5 - kMarginPixels) / height * 2.0;
  const double yBottom = 1.0 - (r.y1 + 0.5 + kMarginPixels) / height * 2.0;
  const Side sides[4] = {{1, 0, -x0}, {-1, 0, x1}, {0, 1, -yBottom}, {0, -1, yTop}};
  const bool defocus = lens.active();
  if (motion) {
    // Time: per side, each vertex at each lens corner (u for the x sides, v for the y sides).
    double t0 = double{d.t0}, t1 = double{d.t1};
    for (int k = 0; k < 5; ++k) {
      Lines lines;
      for (int i = 0; i < 3; ++i)
        for (int corner = 0; corner < (defocus ? 2 : 1); ++corner) {
          const double u = double{corner ? d.u1 : d.u0}, v = double{corner ? d.v1 : d.v0};
          const P4 pa = vertexAt(c0[i], c1[i], double{d.t0}, u, v, lens), pb = vertexAt(c0[i], c1[i], double{d.t1}, u, v, lens);
          if (k < 4) {
            const Side& s = sides[k];
            lines.add(sideValue(s, pa), sideValue(s, pb), kRelTol * std::max(sideScale(s, pa), sideScale(s, pb)));
          } else {  // in front of the near plane: z >= 0
            lines.add(pa.z, pb.z, kRelTol * std::max(std::abs(pa.z) + std::abs(pa.w), std::abs(pb.z) + std::abs(pb.w)));
          }
        }
      double s0, s1;
      if (!lines.hull(s0, s1)) return false;
      const double span = double{d.t1} - double{d.t0};
      t0 = std::max(t0, double{d.t0} + s0 * span);
      t1 = std::min(t1, double{d.t0} + s1 * span);
      if (t0 > t1) return false;
    }
    d.t0 = static_cast<float>(std::nextafter(static_cast<float>(t0), -1.0f));
    d.t1 = static_cast<float>(std::nextafter(static_cast<float>(t1), 2.0f));
    d.t0 = std::max(d.t0, 0.0f);
  }
  if (defocus) {
    // Lens: for the x sides u over [u0, u1] with each vertex at both ends of the time range; y, v.
    for (int axis = 0; axis < 2; ++axis) {
      const float lo = axis == 0 ? d.u0 : d.v0, hi = axis == 0 ? d.u1 : d.v1;
      double a0 = double{lo}, a1 = double{hi};
      for (int k = axis * 2; k < axis * 2 + 2; ++k) {
        Lines lines;
        const Side& s = sides[k];
        for (int i = 0; i < 3; ++i)
          for (int e = 0; e < (motion ? 2 : 1); ++e) {
            const double t = double{e ? d.t1 : d.t0};
            const double l = double{lo}, h = double{hi};
            const P4 pa = vertexAt(c0[i], motion ? c1[i] : c0[i], t, axis == 0 ? l : 0.0, axis == 1 ? l : 0.0, lens);
            const P4 pb = vertexAt(c0[i], motion ? c1[i] : c0[i], t, axis == 0 ? h : 0.0, axis == 1 ? h : 0.0, lens);
            lines.add(sideValue(s, pa), sideValue(s, pb), kRelTol * std::max(sideScale(s, pa), sideScale(s, pb)));
          }
        double s0, s1;
        if (!lines.hull(s0, s1)) return false;
        const double span = double{hi} - double{lo};
        a0 = std::max(a0, double{lo} + s0 * span);
        a1 = std::min(a1, double{lo} + s1 * span);
        if (a0 > a1) return false;
      }
      const float f0 = std::nextafter(static_cast<float>(a0), -2.0f), f1 = std::nextafter(static_cast<float>(a1), 2.0f);
      if (axis == 0) {
        d.u0 = f0, d.u1 = f1;
      } else {
        d.v0 = f0, d.v1 = f1;
      }
    }
  }
  return true;
}

}  // namespace penumbra::stochastic
