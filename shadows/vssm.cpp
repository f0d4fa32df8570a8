#include "shadows/vssm.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "shadows/prefiltered.h"
#include "shadows/sampling.h"

namespace penumbra::shadows {

namespace {

constexpr int kMaxSub = 8;

// What a kernel gives (as essm.cpp): sum of A s, of A (1 - s) z_occ and of A (1 - s).
struct KernelResult {
  double area = 0, lit = 0, occDepth = 0, occWeight = 0;
};

struct Counts {
  size_t kernels = 0, lit = 0, blocked = 0;
};

// The shared part: the map, its pyramid and the double table of (z, z^2).
class VarianceSat {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params, const char* name) {
    bias_ = biasParams(params);
    usePlane_ = params.choice("receiver_plane") == "on";
    minVariance_ = params.number("min_variance");
    bleed_ = params.number("bleed_reduction");
    floatSat_ = params.choice("sat") == "float";
    hsm_ = params.choice("search") == "hsm";
    preparePrefilterMap(ctx, params, m_);
    const auto t0 = Clock::now();
    const int w = m_.z.width(), h = m_.z.height();
    raster::Planes<float> planes(w, h, 2);
    ctx.raster.run([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const raster::Float4 t = m_.map.texels.at(x, y);
            float* p = planes.pixel(x, y);
            p[0] = t.r, p[1] = t.g;
          }
      });
      if (floatSat_)
        float_ = raster::buildSatFloat(planes);
      else
        double_ = raster::buildSatDouble(planes);
    });
    ctx.times.msFilter += msSince(t0);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "%s: map %d^2, %s SAT of (z, z^2), Chebyshev (min variance %g, bleed reduction %g)", name,
                  w, floatSat_ ? "float" : "double", minVariance_, bleed_);
    ctx.notes.push_back(buf);
  }

  ReceiverKernel receiver(const ShadowContext& ctx, const Receiver& r) const {
    ReceiverKernel k = receiverKernel(m_, ctx, r, bias_, usePlane_);
    if (hsm_) shrinkSearchBox(m_, ctx, k);
    return k;
  }
  const PrefilterMap& map() const { return m_; }

  // The box split into n x n sub-kernels; with `bounds`, the min/max pyramid decides the wholly
  // lit and wholly blocked ones first.
  KernelResult kernel(const ReceiverKernel& k, double x0, double y0, double x1, double y1, int n, bool bounds,
                      Counts& counts) const {
    double sums[kMaxSub * kMaxSub * 2], area[kMaxSub * kMaxSub];
    if (floatSat_)
      float_.gridSums(x0, y0, x1, y1, n, sums, area);
    else
      double_.gridSums(x0, y0, x1, y1, n, sums, area);
    KernelResult r;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double a = area[j * n + i];
        if (!(a > 0.0)) continue;
        ++counts.kernels;
        const double sx0 = x0 + (x1 - x0) * i / n, sx1 = x0 + (x1 - x0) * (i + 1) / n;
        const double sy0 = y0 + (y1 - y0) * j / n, sy1 = y0 + (y1 - y0) * (j + 1) / n;
        const double mean = sums[(j * n + i) * 2] / a, meanSq = sums[(j * n + i) * 2 + 1] / a;
        const double zc = k.zrAt(0.5 * (sx0 + sx1), 0.5 * (sy0 + sy1));
        double s = -1.0;
        if (bounds) {
          const PlaneBounds pb = planeBounds(m_.pyramid, k, sx0, sy0, sx1, sy1);
          if (pb.mn >= pb.hi)
            s = 1.0, ++counts.lit;
          else if (pb.mx < pb.lo)
            s = 0.0, ++counts.blocked;
        }
        double zOcc = mean;
        if (s < 0.0) {
          s = reduceLightBleeding(chebyshevUpperBound(mean, meanSq, zc, minVariance_), bleed_);
          if (s < 1.0) zOcc = std::clamp((mean - s * zc) / (1.0 - s), 0.0, zc);
        }
        r.area += a;
        r.lit += a * s;
        r.occWeight += a * (1.0 - s);
        r.occDepth += a * (1.0 - s) * zOcc;
      }
    return r;
  }

 private:
  PrefilterMap m_;
  BiasParams bias_;
  bool usePlane_ = true, floatSat_ = false, hsm_ = true;
  double minVariance_ = 1e-5, bleed_ = 0;
  raster::MultiSat<double> double_;
  raster::MultiSat<float> float_;
};

std::vector<ParamSpec> varianceParams(int defaultSubdivision) {
  std::vector<ParamSpec> p = prefilterParams(defaultSubdivision);
  for (ParamSpec& c : chebyshevParams(1e-6)) p.push_back(std::move(c));
  p.push_back({.name = "sat",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1,
               .choices = {"double", "float"},
               .help = "summed-area table precision"});
  p.push_back(searchParam());
  return p;
}

float finish(const KernelResult& f) {
  const double v = f.area > 0.0 ? f.lit / f.area : 1.0;
  return v < 0x1p-24 ? 0.0f : static_cast<float>(std::min(v, 1.0));
}

class Vssm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    n_ = params.integer("subdivision");
    bounds_ = params.choice("minmax") == "on";
    sat_.prepare(ctx, params, "vssm");
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    counts_.clear();
    forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
      Counts& counts = counts_.local();
      const ReceiverKernel k = sat_.receiver(ctx, r);
      const KernelResult b =
          sat_.kernel(k, k.cx - k.sx, k.cy - k.sy, k.cx + k.sx, k.cy + k.sy, n_, bounds_, counts);
      if (!(b.occWeight > 1e-7 * b.area)) return 1.0f;
      const glm::dvec2 p = penumbraHalf(sat_.map(), ctx, k, b.occDepth / b.occWeight);
      return finish(sat_.kernel(k, k.cx - p.x, k.cy - p.y, k.cx + p.x, k.cy + p.y, n_, bounds_, counts));
    });
    ctx.times.msEvaluate += msSince(t0);
    Counts t;
    for (const Counts& c : counts_) t.kernels += c.kernels, t.lit += c.lit, t.blocked += c.blocked;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "vssm: %zu sub-kernels: %zu wholly lit and %zu wholly blocked by the min/max pyramid, %zu "
                  "by Chebyshev",
                  t.kernels, t.lit, t.blocked, t.kernels - t.lit - t.blocked);
    ctx.notes.push_back(buf);
  }

 private:
  VarianceSat sat_;
  int n_ = 4;
  bool bounds_ = true;
  tbb::enumerable_thread_specific<Counts> counts_;
};

class Savsm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const int n = params.integer("blocker_samples");
    taps_.clear();
    for (int i = 0; i < n; ++i)
      taps_.push_back(hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n)));
    sat_.prepare(ctx, params, "savsm");
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver& r) {
      const ReceiverKernel k = sat_.receiver(ctx, r);
      const PrefilterMap& m = sat_.map();
      // Blocker search by taps (Lauritzen's), shifted per pixel as PCSS's.
      const double ox = unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0x5a75u));
      const double oy = unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0x5a76u));
      double sum = 0;
      int count = 0;
      for (const glm::vec2& t : taps_) {
        const double u = std::fmod(static_cast<double>(t.x) + ox, 1.0),
                     v = std::fmod(static_cast<double>(t.y) + oy, 1.0);
        const double tx = k.cx + (2.0 * u - 1.0) * k.sx, ty = k.cy + (2.0 * v - 1.0) * k.sy;
        const auto z = static_cast<double>(m.zAt(tx, ty));
        if (z < k.zrAt(tx, ty)) sum += z, ++count;
      }
      if (count == 0) return 1.0f;
      const glm::dvec2 p = penumbraHalf(m, ctx, k, sum / count);
      Counts c;
      return finish(sat_.kernel(k, k.cx - p.x, k.cy - p.y, k.cx + p.x, k.cy + p.y, 1, false, c));
    });
    ctx.times.msEvaluate += msSince(t0);
  }

 private:
  VarianceSat sat_;
  std::vector<glm::vec2> taps_;
};

uint64_t satBytes(const ParamSet& ps, uint64_t) {
  const uint64_t n = static_cast<uint64_t>(ps.integer("map_size"));
  return n * n * 52;  // moments 16, z 4, pyramid ~5.3, planes 8, table 16
}

}  // namespace

TechniqueInfo vssmTechnique() {
  std::vector<ParamSpec> p = varianceParams(4);
  p.push_back(minMaxParam());
  return {
      .name = "vssm",
      .summary =
          "variance soft shadow mapping: (z, z^2) summed-area table, Chebyshev blocker search and filter, "
          "kernel subdivision with min/max bounds",
      .params = std::move(p),
      .benchSettings = {"", "subdivision=1", "subdivision=8", "minmax=off", "search=near"},
      .isReference = false,
      .make = [] { return std::make_unique<Vssm>(); },
      .peakBytes = satBytes};
}

TechniqueInfo savsmTechnique() {
  std::vector<ParamSpec> p = varianceParams(1);
  std::erase_if(p, [](const ParamSpec& s) { return s.name == "subdivision"; });  // one box, by design
  p.push_back({.name = "blocker_samples",
               .kind = ParamKind::Int,
               .defaultValue = 32,
               .minValue = 1,
               .maxValue = 1024,
               .choices = {},
               .help = "depth taps of the blocker search"});
  return {
      .name = "savsm",
      .summary =
          "summed-area variance shadow maps: tap blocker search, one Chebyshev bound over the penumbra box",
      .params = std::move(p),
      .benchSettings = {"", "sat=float", "bleed_reduction=0"},
      .isReference = false,
      .make = [] { return std::make_unique<Savsm>(); },
      .peakBytes = satBytes};
}

}  // namespace penumbra::shadows
