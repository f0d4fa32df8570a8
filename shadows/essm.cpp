#include "shadows/essm.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <glm/ext/matrix_double2x2.hpp>

#include "shadows/prefiltered.h"

namespace penumbra::shadows {

namespace {

// essm.h: the stored exp(c (z - z_max)) must stay a normal float, above FLT_MIN = 1.2e-38 = e^-87.3.
constexpr double kMaxRange = 80.0;
constexpr int kChannels = 4;  // e, e z, z, o (0 where no caster covers the texel)

// Sums of one (sub-)kernel: its area and the area-weighted sums of the three channels.
struct BoxSums {
  double area = 0, e = 0, ez = 0, z = 0, o = 0;
  double errE = 0;  // bound on the error of e (the table's quantization or rounding)
};

// u / sinh(u) = e^-u f(u) with f(u) = 2u / (1 - e^-2u), u >= 0: the caller folds e^-u into its one
// exp, so no term overflows (f(u) <= 1 + 2u; f(0) = 1).
double sinhcRest(double u) {
  return u > 0.0 ? 2.0 * u / -std::expm1(-2.0 * u) : 1.0;
}

// The receiver factor's cap, e^700 (receivers nearer than every caster): no overflow.
const double kMaxFactor = std::exp(700.0);

// What a kernel gives: sum of A s, of A (E[z] - k E[e z]) (the blockers' depth times their
// weight) and of A (1 - s) (their weight), over its (sub-)kernels.
struct KernelResult {
  double area = 0, lit = 0, occDepth = 0, occWeight = 0;
  void add(const KernelResult& o) {
    area += o.area, lit += o.lit, occDepth += o.occDepth, occWeight += o.occWeight;
  }
};

struct Counts {
  size_t kernels = 0, pcf = 0, precision = 0, split = 0, contact = 0, receivers = 0, shrunk = 0;
};

constexpr int kMaxSub = 8;  // the subdivision parameter's range

class Essm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    usePlane_ = params.choice("receiver_plane") == "on";
    n_ = params.integer("subdivision");
    adaptive_ = params.choice("split") == "adaptive";
    subdivide_ = params.choice("fallback") == "on";
    fallback_ = params.integer("fallback_taps");
    minMaxTest_ = params.choice("minmax_test") == "on";
    hsm_ = params.choice("search") == "hsm";
    precisionTolerance_ = params.number("precision_tolerance");
    eps_ = params.number("nonplanar_epsilon");
    leakTolerance_ = params.number("leak_tolerance");
    ellipse_ = params.choice("kernel") == "ellipse";
    rowHeight_ = params.number("rect_height");
    satName_ = params.choice("sat");
    sat_ = satName_ == "tiled"     ? Sat::Tiled
           : satName_ == "integer" ? Sat::Integer
           : satName_ == "double"  ? Sat::Double
                                   : Sat::Float;
    const int bits = params.integer("bits");
    preparePrefilterMap(ctx, params, m_, {.moments = false, .pyramid = hsm_});

    const auto t0 = Clock::now();
    const double range = std::max(static_cast<double>(m_.zMax) - static_cast<double>(m_.zMin), 1e-6);
    const double fixed = params.number("exponent");
    // c (z_max - z_min) <= 80: every stored value is in [e^-80, 1], normal floats (essm.h).
    c_ = std::min(fixed > 0.0 ? fixed : params.number("exponent_range") / range, kMaxRange / range);
    behindTolerance_ = std::log1p(eps_) / c_;
    leakDepth_ = leakTolerance_ > 0.0 ? -std::log(leakTolerance_) / c_ : 0.0;
    const int w = m_.z.width(), h = m_.z.height();
    // The channels of one texel: e, e z, z, o; all 0 where no caster covers it.
    const auto texel = [this](float zf, float* p) {
      if (PrefilterMap::empty(zf)) {
        p[0] = p[1] = p[2] = p[3] = 0.0f;
        return;
      }
      const auto z = static_cast<double>(zf);
      const double e = std::exp(c_ * (z - static_cast<double>(m_.zMax)));
      p[0] = static_cast<float>(e), p[1] = static_cast<float>(e * z), p[2] = zf, p[3] = 1.0f;
    };
    ctx.raster.run([&] {
      if (minMaxTest_) {
        raster::ImageFloat occupiedZ(w, h);
        tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
          for (int y = r.begin(); y < r.end(); ++y)
            for (int x = 0; x < w; ++x) {
              const float zf = m_.z.at(x, y);
              occupiedZ.at(x, y) = PrefilterMap::empty(zf) ? 0.0f : zf;
            }
        });
        occupied_ = raster::buildMinMaxPyramid(occupiedZ);
      }
      if (sat_ == Sat::Tiled) {
        // Straight from the depths, tile by tile: texels no receiver's kernel reaches are never
        // computed (nor the whole map's channels stored).
        const int T = raster::stgTileSize(bits);
        const int tx = (w + T - 1) / T, ty = (h + T - 1) / T;
        tiled_ = raster::buildTiledSat(
            w, h, kChannels, bits,
            [&](int x0, int y0, int tw, int th, float* out) {
              for (int y = 0; y < th; ++y)
                for (int x = 0; x < tw; ++x) texel(m_.z.at(x0 + x, y0 + y), out + (y * tw + x) * kChannels);
            },
            tilesReached(ctx, m_, bias_, T, tx, ty, hsm_));
        return;
      }
      raster::Planes<float> planes(w, h, kChannels);
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y)
          for (int x = 0; x < w; ++x) texel(m_.z.at(x, y), planes.pixel(x, y));
      });
      if (sat_ == Sat::Integer) {
        // The paper's normalization (section 6.2): each channel's range over the map to [0, 1].
        // Empty texels hold 0 in every channel, so every range starts at 0.
        const auto zHi = static_cast<double>(m_.zMax);
        lo_ = {0.0, 0.0, 0.0, 0.0};
        const std::vector<double> hi = {1.0, zHi, zHi, 1.0};
        const double maxQ = static_cast<double>((1u << bits) - 1u);
        for (int k = 0; k < kChannels; ++k)
          step_[static_cast<size_t>(k)] = (hi[static_cast<size_t>(k)] - lo_[static_cast<size_t>(k)]) / maxQ;
        integer_ = raster::buildSatInteger(raster::quantizePlanes(planes, lo_, hi, bits));
      } else if (sat_ == Sat::Double) {
        double_ = raster::buildSatDouble(planes);
      } else {
        float_ = raster::buildSatFloat(planes);
      }
    });
    ctx.times.msFilter += msSince(t0);

    char buf[240];
    std::snprintf(
        buf, sizeof buf,
        "essm: map %d^2, z in [%.4f, %.4f], c = %.1f, %s SAT of (e, e z, z), %s kernel, subdivision %dx%d "
        "(eps %g)",
        w, static_cast<double>(m_.zMin), static_cast<double>(m_.zMax), c_, satName_.c_str(),
        ellipse_ ? "ellipse" : "box", n_, n_, eps_);
    ctx.notes.push_back(buf);
    if (sat_ == Sat::Tiled)
      ctx.notes.push_back("essm: SAT tile grid " + std::to_string(tiled_.tile) + "^2 tiles, mu " +
                          std::to_string(bits) + " bits: " +
                          tileNote(tiled_.tilesBuilt,
                                   static_cast<size_t>(tiled_.tilesX) * static_cast<size_t>(tiled_.tilesY)));
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    counts_.clear();
    const ReceiverImage& rec = *ctx.in.receivers;
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      Counts& counts = counts_.local();
      ++counts.receivers;
      ReceiverKernel k = receiverKernel(m_, ctx, r, bias_, usePlane_);
      if (hsm_) counts.shrunk += shrinkSearchBox(m_, ctx, k) ? 1 : 0;
      // 1. Blocker search over the box kernel w_avg.
      const KernelResult b = kernel(k, k.cx - k.sx, k.cy - k.sy, k.cx + k.sx, k.cy + k.sy, n_, n_, counts);
      if (!(b.occWeight > 1e-7 * b.area)) return 1.0f;  // no blocker
      const double zOcc = std::clamp(b.occDepth / b.occWeight, 0.0, k.zr);
      // 2. Penumbra kernel, 3. filter.
      const glm::dvec2 p = penumbraHalf(m_, ctx, k, zOcc);
      if (k.zr - zOcc < leakDepth_) {
        // Contact: blockers this near read exp(-c (z_r - z)) >= the tolerance, the ESM tail's light
        // leak; PCF over the n x n sub-kernels instead (Penumbra's addition).
        ++counts.contact;
        KernelResult f;
        for (int j = 0; j < n_; ++j)
          for (int i = 0; i < n_; ++i) {
            const double x0 = k.cx - p.x + 2.0 * p.x * i / n_, x1 = k.cx - p.x + 2.0 * p.x * (i + 1) / n_;
            const double y0 = k.cy - p.y + 2.0 * p.y * j / n_, y1 = k.cy - p.y + 2.0 * p.y * (j + 1) / n_;
            f.add(pcf(k, x0, y0, x1, y1));
          }
        return f.area > 0.0 ? static_cast<float>(f.lit / f.area) : 1.0f;
      }
      const KernelResult f = ellipse_
                                 ? ellipseKernel(k, p, footprint(rec, x, y, k), counts)
                                 : kernel(k, k.cx - p.x, k.cy - p.y, k.cx + p.x, k.cy + p.y, n_, n_, counts);
      const double v = f.area > 0.0 ? f.lit / f.area : 1.0;
      return v < 0x1p-24 ? 0.0f : static_cast<float>(std::min(v, 1.0));
    });
    ctx.times.msEvaluate += msSince(t0);
    Counts total;
    for (const Counts& c : counts_)
      total.kernels += c.kernels, total.pcf += c.pcf, total.precision += c.precision, total.split += c.split,
          total.contact += c.contact, total.receivers += c.receivers, total.shrunk += c.shrunk;
    const auto pct = [&](size_t n) {
      return total.kernels ? 100.0 * static_cast<double>(n) / static_cast<double>(total.kernels) : 0.0;
    };
    char buf[320];
    std::snprintf(
        buf, sizeof buf,
        "essm: %zu (sub-)kernels, %zu (%.2f%%) split %dx%d (%s), %zu (%.2f%%) by %dx%d PCF: %zu (%.2f%%) not "
        "planar, %zu (%.2f%%) beyond the table's precision",
        total.kernels, total.split, pct(total.split), n_, n_, adaptive_ ? "where not planar" : "always",
        total.pcf, pct(total.pcf), fallback_, fallback_, total.pcf - total.precision,
        pct(total.pcf - total.precision), total.precision, pct(total.precision));
    ctx.notes.push_back(buf);
    std::snprintf(buf, sizeof buf,
                  "essm: %zu of %zu receivers (%.2f%%) filtered by PCF: their blockers within %.4f of them "
                  "(exp(-c d) above %g)",
                  total.contact, total.receivers,
                  total.receivers ? 100.0 * static_cast<double>(total.contact) / static_cast<double>(total.receivers)
                                  : 0.0,
                  leakDepth_, leakTolerance_);
    ctx.notes.push_back(buf);
    if (hsm_) {
      std::snprintf(buf, sizeof buf,
                    "essm: %zu of %zu receivers (%.2f%%) searched a smaller box than the near plane's: the "
                    "nearest depth in it (min/max pyramid) bounds their blockers",
                    total.shrunk, total.receivers,
                    total.receivers
                        ? 100.0 * static_cast<double>(total.shrunk) / static_cast<double>(total.receivers)
                        : 0.0);
      ctx.notes.push_back(buf);
    }
  }

 private:
  // The sums of the nx x ny equal parts of a box, row-major.
  void subSums(double x0, double y0, double x1, double y1, int nx, int ny, BoxSums* out) const {
    double o[kMaxSub * kMaxSub * kChannels], area[kMaxSub * kMaxSub], err[kMaxSub * kMaxSub] = {};
    const int parts = nx * ny;
    double whole[kChannels] = {};
    if (sat_ == Sat::Double) double_.roundingBound(x1, y1, whole);
    if (sat_ == Sat::Float) float_.roundingBound(x1, y1, whole);
    if (nx == ny) {
      if (sat_ == Sat::Tiled) {
        double bound[kMaxSub * kMaxSub * kChannels];
        tiled_.gridSums(x0, y0, x1, y1, nx, o, area, bound);
        for (int i = 0; i < parts; ++i) err[i] = bound[i * kChannels];
      } else if (sat_ == Sat::Integer)
        integer_.gridSums(x0, y0, x1, y1, nx, o, area);
      else if (sat_ == Sat::Double)
        double_.gridSums(x0, y0, x1, y1, nx, o, area);
      else
        float_.gridSums(x0, y0, x1, y1, nx, o, area);
    } else {
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const double sx0 = x0 + (x1 - x0) * i / nx, sx1 = x0 + (x1 - x0) * (i + 1) / nx;
          const double sy0 = y0 + (y1 - y0) * j / ny, sy1 = y0 + (y1 - y0) * (j + 1) / ny;
          double* d = o + (j * nx + i) * kChannels;
          double& a = area[j * nx + i];
          double bound[kChannels];
          if (sat_ == Sat::Tiled)
            a = tiled_.boxSum(sx0, sy0, sx1, sy1, d, bound), err[j * nx + i] = bound[0];
          else if (sat_ == Sat::Integer)
            a = integer_.boxSum(sx0, sy0, sx1, sy1, d);
          else if (sat_ == Sat::Double)
            a = double_.boxSum(sx0, sy0, sx1, sy1, d);
          else
            a = float_.boxSum(sx0, sy0, sx1, sy1, d);
        }
    }
    for (int i = 0; i < parts; ++i) {
      double* d = o + i * kChannels;
      if (sat_ == Sat::Integer)  // fixed point back to values (the step per channel; ranges start at 0)
        for (int c = 0; c < kChannels; ++c) d[c] *= step_[static_cast<size_t>(c)];
      const double e = sat_ == Sat::Tiled     ? err[i]
                       : sat_ == Sat::Integer ? 0.5 * step_[0] * area[i]
                                              : whole[0];
      out[i] = {area[i], d[0], d[1], d[2], d[3], e};
    }
  }

  // One sub-kernel by the ESM test. Texels no caster covers count as lit. With the receiver plane,
  // the test is against the plane's depth z_c at the sub-kernel's centre, normalized by what the
  // plane itself would give: texels on the plane z_c + g . (x - centre) have the box mean of
  // exp(c g . (x - centre)) = prod sinh(u) / u, u = c |g_axis| half-extent, so a tilted receiver
  // reads exactly 1 on its own surface. `planar` is false when the unclamped value exceeds 1 + eps
  // (section 5.2) or, with the min/max test, when a covered texel lies more than ln(1 + eps) / c
  // behind the receiver's plane anywhere in the box.
  KernelResult esm(const ReceiverKernel& k, const BoxSums& s, double x0, double y0, double x1, double y1,
                   bool& planar, bool& precisionMiss) const {
    KernelResult r;
    planar = true;
    precisionMiss = false;
    if (!(s.area > 0.0)) return r;
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double zc = k.zrAt(cx, cy);
    // Against the unbiased plane (zc + biasZ): the receiver's own surface reads 1, not
    // exp(c biasZ), which would brighten every partly blocked kernel by that factor.
    double logK = c_ * (static_cast<double>(m_.zMax) - zc - k.biasZ), rest = 1.0;
    if (k.usePlane) {
      // Divided by sinh(ux) / ux and sinh(uy) / uy: e^-(ux + uy) in the exponent, the rest after.
      const double gx = 0.5 * (k.zrAt(cx + 1.0, cy) - k.zrAt(cx - 1.0, cy));
      const double gy = 0.5 * (k.zrAt(cx, cy + 1.0) - k.zrAt(cx, cy - 1.0));
      const double ux = c_ * std::abs(gx) * 0.5 * (x1 - x0), uy = c_ * std::abs(gy) * 0.5 * (y1 - y0);
      logK -= ux + uy;
      rest = sinhcRest(ux) * sinhcRest(uy);
    }
    const double kf = std::min(std::exp(std::min(logK, 700.0)) * rest, kMaxFactor);
    const double raw = (kf * s.e + (s.area - s.o)) / s.area;  // unclamped
    planar = raw <= 1.0 + eps_ && std::isfinite(raw);
    // The table cannot resolve this receiver's neighbourhood: its error bound, scaled as the test
    // scales e, exceeds the tolerance (values far below a tile's range, or the float/double
    // table's accumulated total). PCF instead.
    if (planar && kf * s.errE > precisionTolerance_ * s.area) {
      planar = false;
      precisionMiss = true;
    }
    if (planar && minMaxTest_) {
      // Over the texels the pyramid's bounds cover (a little more than the box): the plane's
      // largest depth there is at a corner (1/d is linear in the map, so d is monotone along lines).
      const PlaneBounds pb = planeBounds(occupied_, k, x0, y0, x1, y1);
      planar = pb.mx <= pb.hi + k.biasZ + behindTolerance_;
    }
    const double lit = std::min(raw, 1.0);
    r.area = s.area;
    r.lit = lit * s.area;
    r.occWeight = (1.0 - lit) * s.area;
    // Blockers lie in front of the receiver: their mean depth is in [0, z_c].
    r.occDepth = std::clamp(s.z - kf * s.ez, 0.0, r.occWeight * std::max(zc, 0.0));
    return r;
  }

  // g x g PCF inside a sub-kernel (the paper's g = 2): taps at the centres of a g x g grid.
  KernelResult pcf(const ReceiverKernel& k, double x0, double y0, double x1, double y1) const {
    KernelResult r;
    r.area = std::max(0.0, std::min(x1, static_cast<double>(m_.z.width())) - std::max(x0, 0.0)) *
             std::max(0.0, std::min(y1, static_cast<double>(m_.z.height())) - std::max(y0, 0.0));
    if (!(r.area > 0.0)) return r;
    const int g = fallback_;
    int lit = 0;
    double blocked = 0;
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) {
        const double tx = x0 + (x1 - x0) * (i + 0.5) / g, ty = y0 + (y1 - y0) * (j + 0.5) / g;
        const auto z = static_cast<double>(m_.zAt(tx, ty));
        if (z >= k.zrAt(tx, ty))
          ++lit;
        else
          blocked += z;
      }
    const double a = r.area / (g * g);
    r.lit = a * lit;
    r.occDepth = a * blocked;
    r.occWeight = a * (g * g - lit);
    return r;
  }

  // A rectangular kernel as nx x ny sub-kernels (section 5.2), each by the ESM test or, where not
  // planar, by PCF.
  KernelResult kernel(const ReceiverKernel& k, double x0, double y0, double x1, double y1, int nx, int ny,
                      Counts& counts) const {
    if (adaptive_ && nx * ny > 1) {
      // Section 5.2 as the paper orders it: the whole kernel first, split only where not planar.
      BoxSums whole;
      subSums(x0, y0, x1, y1, 1, 1, &whole);
      bool planar = true, precisionMiss = false;
      const KernelResult r = esm(k, whole, x0, y0, x1, y1, planar, precisionMiss);
      ++counts.kernels;
      if (planar) return r;
      ++counts.split;
    }
    BoxSums parts[kMaxSub * kMaxSub];
    subSums(x0, y0, x1, y1, nx, ny, parts);
    KernelResult r;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double sx0 = x0 + (x1 - x0) * i / nx, sx1 = x0 + (x1 - x0) * (i + 1) / nx;
        const double sy0 = y0 + (y1 - y0) * j / ny, sy1 = y0 + (y1 - y0) * (j + 1) / ny;
        bool planar = true, precisionMiss = false;
        ++counts.kernels;
        KernelResult part = esm(k, parts[j * nx + i], sx0, sy0, sx1, sy1, planar, precisionMiss);
        if (precisionMiss) ++counts.precision;
        if (!planar && subdivide_) {
          part = pcf(k, sx0, sy0, sx1, sy1);
          ++counts.pcf;
        }
        r.add(part);
      }
    return r;
  }

  // The pixel's footprint in the map: texels per pixel along the image's x and y (from the
  // neighbouring receivers on the same surface; zero where there is none).
  glm::mat2 footprint(const ReceiverImage& rec, int x, int y, const ReceiverKernel& k) const {
    glm::mat2 j(0.0f);
    const auto axis = [&](int dx, int dy) -> glm::vec2 {
      for (int s : {1, -1}) {
        const int nx = x + s * dx, ny = y + s * dy;
        if (nx < 0 || ny < 0 || nx >= rec.width() || ny >= rec.height()) continue;
        const Receiver& o = rec.at(nx, ny);
        if (!o.valid || glm::dot(o.normal, rec.at(x, y).normal) < 0.9f) continue;
        const glm::vec3 v = m_.map.view.toView(o.position);
        if (!(v.z > 0.0f)) continue;
        const glm::vec2 d =
            (m_.map.view.toMap(v) - glm::vec2(static_cast<float>(k.cx), static_cast<float>(k.cy))) *
            static_cast<float>(s);
        if (glm::length(d) < 64.0f) return d;
      }
      return glm::vec2(0.0f);
    };
    j[0] = axis(1, 0);
    j[1] = axis(0, 1);
    return j;
  }

  // Section 5.1, Level0: the penumbra box's Gaussian (variance p^2 / 3 per axis) convolved with the
  // pixel footprint's (a pixel's box, variance 1/12 per image axis), the ellipse x^T S^-1 x <= 3,
  // cut into rows of height <= H texels, each row the rectangle of its centre line's chord.
  KernelResult ellipseKernel(const ReceiverKernel& k, glm::dvec2 p, const glm::mat2& jf,
                             Counts& counts) const {
    const glm::dmat2 j(jf);
    const double sxx = p.x * p.x / 3.0 + (j[0].x * j[0].x + j[1].x * j[1].x) / 12.0;
    const double syy = p.y * p.y / 3.0 + (j[0].y * j[0].y + j[1].y * j[1].y) / 12.0;
    const double sxy = (j[0].x * j[0].y + j[1].x * j[1].y) / 12.0;
    const double det = sxx * syy - sxy * sxy;
    const double hy = std::sqrt(3.0 * syy);
    if (!(det > 0.0) || !(hy > 0.0))
      return kernel(k, k.cx - p.x, k.cy - p.y, k.cx + p.x, k.cy + p.y, n_, n_, counts);
    const double a00 = syy / det, a01 = -sxy / det, a11 = sxx / det;  // S^-1
    const int rows = std::max(1, static_cast<int>(std::ceil(2.0 * hy / rowHeight_)));
    KernelResult r;
    for (int i = 0; i < rows; ++i) {
      const double y0 = -hy + 2.0 * hy * i / rows, y1 = -hy + 2.0 * hy * (i + 1) / rows, yc = 0.5 * (y0 + y1);
      const double disc = a01 * a01 * yc * yc - a00 * (a11 * yc * yc - 3.0);
      if (!(disc > 0.0)) continue;
      const double xa = (-a01 * yc - std::sqrt(disc)) / a00, xb = (-a01 * yc + std::sqrt(disc)) / a00;
      r.add(kernel(k, k.cx + xa, k.cy + y0, k.cx + xb, k.cy + y1, n_, 1, counts));
    }
    return r;
  }

  PrefilterMap m_;
  BiasParams bias_;
  bool usePlane_ = true, ellipse_ = false, subdivide_ = true, minMaxTest_ = true, adaptive_ = false,
       hsm_ = true;
  int n_ = 3, fallback_ = 2;
  double behindTolerance_ = 0, precisionTolerance_ = 0.01, leakTolerance_ = 0.05, leakDepth_ = 0;
  raster::MinMaxPyramid occupied_;
  double eps_ = 0.02, rowHeight_ = 5, c_ = 1;
  enum class Sat { Tiled, Integer, Double, Float } sat_ = Sat::Tiled;
  std::string satName_;
  raster::TiledSat tiled_;
  raster::MultiSat<uint64_t> integer_;
  raster::MultiSat<double> double_;
  raster::MultiSat<float> float_;
  std::vector<double> lo_ = std::vector<double>(kChannels, 0.0), step_ = std::vector<double>(kChannels, 1.0);
  tbb::enumerable_thread_specific<Counts> counts_;
};

}  // namespace

TechniqueInfo essmTechnique() {
  std::vector<ParamSpec> p = prefilterParams(3);
  p.push_back(
      {.name = "exponent_range",
       .kind = ParamKind::Float,
       .defaultValue = kMaxRange,
       .minValue = 1,
       .maxValue = kMaxRange,
       .choices = {},
       .help = "R of c = R / (z_max - z_min): the ESM test's steepness over the map's depth range (<= 80: "
               "exp(-R) stays a normal float)"});
  p.push_back({.name = "exponent",
               .kind = ParamKind::Float,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1e4,
               .choices = {},
               .help = "c itself (0: from exponent_range), lowered to 80 / (z_max - z_min) if above"});
  p.push_back({.name = "sat",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 3,
               .choices = {"tiled", "integer", "double", "float"},
               .help = "summed-area table: the tile grid (mu-bit integers per tile), one exact integer "
                       "table, double, float"});
  p.push_back(
      {.name = "bits",
       .kind = ParamKind::Int,
       .defaultValue = 20,
       .minValue = 8,
       .maxValue = 24,
       .choices = {},
       .help = "mu: fixed-point bits of the integer tables (tiles of 2^floor((32 - mu) / 2) texels)"});
  p.push_back({.name = "leak_tolerance",
               .kind = ParamKind::Float,
               .defaultValue = 0.05,
               .minValue = 0,
               .maxValue = 1,
               .choices = {},
               .help = "receivers whose average blocker reads exp(-c (z_r - z_occ)) above this take PCF over "
                       "the penumbra kernel (0: never)"});
  p.push_back({.name = "split",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1,
               .choices = {"always", "adaptive"},
               .help = "split a kernel into its n x n sub-kernels only where the whole is not planar (the "
                       "paper's order), or always"});
  p.push_back({.name = "nonplanar_epsilon",
               .kind = ParamKind::Float,
               .defaultValue = 0.02,
               .minValue = 0,
               .maxValue = 10,
               .choices = {},
               .help = "eps: an ESM value above 1 + eps marks a non-planar kernel"});
  p.push_back({.name = "fallback",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1,
               .choices = {"on", "off"},
               .help = "non-planar sub-kernels by PCF (off: the clamped ESM value)"});
  p.push_back({.name = "fallback_taps",
               .kind = ParamKind::Int,
               .defaultValue = 2,
               .minValue = 1,
               .maxValue = 8,
               .choices = {},
               .help = "g: the fallback PCF's g x g taps per sub-kernel (the paper's 2)"});
  p.push_back(searchParam());
  p.push_back({.name = "minmax_test",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1,
               .choices = {"on", "off"},
               .help = "also mark a sub-kernel not planar when the min/max pyramid finds a texel behind the "
                       "receiver's plane"});
  p.push_back(
      {.name = "precision_tolerance",
       .kind = ParamKind::Float,
       .defaultValue = 0.01,
       .minValue = 0,
       .maxValue = 1e6,
       .choices = {},
       .help =
           "largest error of V a sub-kernel's table lookup may carry (its stated bound); beyond it, PCF"});
  p.push_back(
      {.name = "kernel",
       .kind = ParamKind::Choice,
       .defaultValue = 0,
       .minValue = 0,
       .maxValue = 1,
       .choices = {"box", "ellipse"},
       .help =
           "penumbra kernel: the light's rectangle, or the ellipse with the pixel footprint (Level0 rows)"});
  p.push_back({.name = "rect_height",
               .kind = ParamKind::Float,
               .defaultValue = 5,
               .minValue = 1,
               .maxValue = 64,
               .choices = {},
               .help = "H: row height of the ellipse's rectangles, texels"});
  return {.name = "essm",
          .summary =
              "exponential soft shadow mapping: ESM and ESM-Z summed-area tables, constant-time blocker "
              "search and filter, micro-subdivision",
          .params = std::move(p),
          .benchSettings = {"", "sat=integer", "kernel=ellipse", "subdivision=1", "search=near"},
          .isReference = false,
          .make = [] { return std::make_unique<Essm>(); },
          .peakBytes =
              [](const ParamSet& ps, uint64_t) {
                const uint64_t n = static_cast<uint64_t>(ps.integer("map_size"));
                // z (4), the occupied depths and their pyramid (~9.3), then the tile grid (at most
                // 17: 4 channels of 4 bytes, (T + 1)^2 / T^2 of them), or the whole map's channels
                // (16) and its table (integer: 16 quantized + 32; double 32; float 16).
                const std::string sat = ps.choice("sat");
                const uint64_t perTexel = sat == "tiled"     ? 31
                                          : sat == "integer" ? 78
                                          : sat == "double"  ? 62
                                                             : 46;
                return n * n * perTexel;
              }};
}

}  // namespace penumbra::shadows
