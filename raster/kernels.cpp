// Image kernels (see kernels.h for conventions and the determinism contract). Every parallel loop
// gives each output row (or column) to one task, and each output value is computed by the same
// sequence of operations whichever task computes it.
#include "raster/kernels.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace penumbra::raster {
namespace {

// Rows per task when a row is cheap; TBB splits further as needed.
constexpr int kRowGrain = 4;
// Columns per task for the column-strip passes: 64 floats = 256 bytes, four cache lines per row.
constexpr int kColumnGrain = 64;

int clampi(int v, int lo, int hi) { return std::min(std::max(v, lo), hi); }

template <class F>
void forRows(int height, int grain, F&& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, grain), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) f(y);
  });
}

// Double accumulators per pixel type.
struct Acc4 {
  double r = 0, g = 0, b = 0, a = 0;
};
template <class T>
struct Accum;
template <>
struct Accum<float> {
  using Type = double;
  static void madd(double& acc, double w, float v) { acc += w * static_cast<double>(v); }
  static float out(double acc) { return static_cast<float>(acc); }
};
template <>
struct Accum<Float4> {
  using Type = Acc4;
  static void madd(Acc4& acc, double w, const Float4& v) {
    acc.r += w * static_cast<double>(v.r);
    acc.g += w * static_cast<double>(v.g);
    acc.b += w * static_cast<double>(v.b);
    acc.a += w * static_cast<double>(v.a);
  }
  static Float4 out(const Acc4& acc) {
    return {static_cast<float>(acc.r), static_cast<float>(acc.g), static_cast<float>(acc.b),
            static_cast<float>(acc.a)};
  }
};

// Copies row y of src into buf with r clamped pixels on each side: buf[i] = src(clamp(i - r), y).
template <class T>
void clampedRow(const Image<T>& src, int y, int r, std::vector<T>& buf) {
  const int w = src.width();
  buf.resize(static_cast<size_t>(w + 2 * r));
  const T* s = src.row(y);
  for (int i = 0; i < w + 2 * r; ++i) buf[static_cast<size_t>(i)] = s[clampi(i - r, 0, w - 1)];
}

// dst(x, y) = sum_{k=0}^{2r} w[k] src(clamp(x + k - r), y), k ascending.
template <class T>
void convolveRows(const Image<T>& src, Image<T>& dst, const std::vector<double>& w, int r) {
  const int width = src.width();
  tbb::parallel_for(tbb::blocked_range<int>(0, src.height(), 1), [&](const tbb::blocked_range<int>& range) {
    std::vector<T> buf;
    for (int y = range.begin(); y < range.end(); ++y) {
      clampedRow(src, y, r, buf);
      T* d = dst.row(y);
      for (int x = 0; x < width; ++x) {
        typename Accum<T>::Type acc{};
        for (int k = 0; k <= 2 * r; ++k)
          Accum<T>::madd(acc, w[static_cast<size_t>(k)], buf[static_cast<size_t>(x + k)]);
        d[x] = Accum<T>::out(acc);
      }
    }
  });
}

// dst(x, y) = sum_{k=0}^{2r} w[k] src(x, clamp(y + k - r)), k ascending (same order per pixel as
// convolveRows, accumulated a whole row at a time).
template <class T>
void convolveColumns(const Image<T>& src, Image<T>& dst, const std::vector<double>& w, int r) {
  const int width = src.width(), height = src.height();
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 1), [&](const tbb::blocked_range<int>& range) {
    std::vector<typename Accum<T>::Type> acc(static_cast<size_t>(width));
    for (int y = range.begin(); y < range.end(); ++y) {
      std::fill(acc.begin(), acc.end(), typename Accum<T>::Type{});
      for (int k = 0; k <= 2 * r; ++k) {
        const T* s = src.row(clampi(y + k - r, 0, height - 1));
        const double wk = w[static_cast<size_t>(k)];
        for (int x = 0; x < width; ++x) Accum<T>::madd(acc[static_cast<size_t>(x)], wk, s[x]);
      }
      T* d = dst.row(y);
      for (int x = 0; x < width; ++x) d[x] = Accum<T>::out(acc[static_cast<size_t>(x)]);
    }
  });
}

template <class T>
void copyImage(const Image<T>& src, Image<T>& dst) {
  if (&src != &dst) dst = src;
}

void checkSigma(float sigma) {
  if (!(sigma >= 0.0f && sigma <= kMaxBlurSigma))
    throw std::invalid_argument("gaussianBlur: sigma " + std::to_string(sigma) + " outside [0, " +
                                std::to_string(kMaxBlurSigma) + "]");
}

// Normalized Gaussian taps for k in [-r, r], r = ceil(3 sigma), sigma > 0.
std::vector<double> gaussianWeights(float sigma, int& r) {
  const double s = static_cast<double>(sigma);
  r = static_cast<int>(std::ceil(3.0 * s));
  std::vector<double> w(static_cast<size_t>(2 * r + 1));
  double sum = 0.0;
  for (int k = -r; k <= r; ++k) {
    const double v = std::exp(-static_cast<double>(k * k) / (2.0 * s * s));
    w[static_cast<size_t>(k + r)] = v;
    sum += v;
  }
  for (double& v : w) v /= sum;
  return w;
}

template <class T>
void gaussianBlurImpl(const Image<T>& src, Image<T>& dst, float sigma) {
  checkSigma(sigma);
  if (sigma == 0.0f || src.empty()) {
    if (src.empty()) dst.resize(src.width(), src.height());
    else copyImage(src, dst);
    return;
  }
  int r = 0;
  const std::vector<double> w = gaussianWeights(sigma, r);
  Image<T> tmp(src.width(), src.height());
  convolveRows(src, tmp, w, r);
  dst.resize(src.width(), src.height());  // after the first pass: src may be dst
  convolveColumns(tmp, dst, w, r);
}

// Next level's size: ceil halving.
int half(int n) { return (n + 1) / 2; }

}  // namespace

// --- Blurs -------------------------------------------------------------------------------------

void boxBlur(const ImageFloat& src, ImageFloat& dst, int radius) {
  if (radius < 0 || radius > kMaxBlurRadius)
    throw std::invalid_argument("boxBlur: radius " + std::to_string(radius) + " outside [0, " +
                                std::to_string(kMaxBlurRadius) + "]");
  const int width = src.width(), height = src.height();
  if (radius == 0 || src.empty()) {
    if (src.empty()) dst.resize(width, height);
    else copyImage(src, dst);
    return;
  }
  const int r = radius;
  const double n = static_cast<double>(2 * r + 1);

  // Horizontal: running sum over buf[x .. x+2r] (buf = the clamped row), add the entering pixel,
  // then remove the leaving one.
  ImageFloat tmp(width, height);
  tbb::parallel_for(tbb::blocked_range<int>(0, height, kRowGrain), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> buf;
    for (int y = range.begin(); y < range.end(); ++y) {
      clampedRow(src, y, r, buf);
      float* d = tmp.row(y);
      double s = 0.0;
      for (int k = 0; k <= 2 * r; ++k) s += static_cast<double>(buf[static_cast<size_t>(k)]);
      d[0] = static_cast<float>(s / n);
      for (int x = 1; x < width; ++x) {
        s += static_cast<double>(buf[static_cast<size_t>(x + 2 * r)]);
        s -= static_cast<double>(buf[static_cast<size_t>(x - 1)]);
        d[x] = static_cast<float>(s / n);
      }
    }
  });

  // Vertical: strips of columns, one running sum per column down the rows. A column's sequence of
  // operations does not depend on which strip holds it.
  dst.resize(width, height);
  tbb::parallel_for(tbb::blocked_range<int>(0, width, kColumnGrain), [&](const tbb::blocked_range<int>& range) {
    const int x0 = range.begin(), cols = range.end() - range.begin();
    std::vector<double> s(static_cast<size_t>(cols), 0.0);
    for (int k = -r; k <= r; ++k) {
      const float* t = tmp.row(clampi(k, 0, height - 1)) + x0;
      for (int i = 0; i < cols; ++i) s[static_cast<size_t>(i)] += static_cast<double>(t[i]);
    }
    for (int y = 0; y < height; ++y) {
      if (y > 0) {
        const float* in = tmp.row(clampi(y + r, 0, height - 1)) + x0;
        const float* out = tmp.row(clampi(y - 1 - r, 0, height - 1)) + x0;
        for (int i = 0; i < cols; ++i) {
          s[static_cast<size_t>(i)] += static_cast<double>(in[i]);
          s[static_cast<size_t>(i)] -= static_cast<double>(out[i]);
        }
      }
      float* d = dst.row(y) + x0;
      for (int i = 0; i < cols; ++i) d[i] = static_cast<float>(s[static_cast<size_t>(i)] / n);
    }
  });
}

void gaussianBlur(const ImageFloat& src, ImageFloat& dst, float sigma) { gaussianBlurImpl(src, dst, sigma); }
void gaussianBlur(const ImageFloat4& src, ImageFloat4& dst, float sigma) { gaussianBlurImpl(src, dst, sigma); }

// --- Summed-area tables --------------------------------------------------------------------------

namespace {

// Fills sums ((w+1) x (h+1), zeroed) from src: horizontal prefixes with rows in parallel, then
// vertical prefixes with strips of columns in parallel. Each entry's sequence of additions is fixed.
template <class Sum, class Pixel>
void buildSums(const Image<Pixel>& src, std::vector<Sum>& sums) {
  const int w = src.width(), h = src.height();
  const size_t stride = static_cast<size_t>(w + 1);
  sums.assign(stride * static_cast<size_t>(h + 1), Sum{0});
  if (w == 0 || h == 0) return;
  forRows(h, kRowGrain, [&](int y) {
    const Pixel* s = src.row(y);
    Sum* d = sums.data() + static_cast<size_t>(y + 1) * stride;
    Sum acc{0};
    for (int x = 0; x < w; ++x) {
      acc += static_cast<Sum>(s[x]);
      d[x + 1] = acc;
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(1, w + 1, kColumnGrain), [&](const tbb::blocked_range<int>& range) {
    for (int y = 2; y <= h; ++y) {
      const Sum* above = sums.data() + static_cast<size_t>(y - 1) * stride;
      Sum* d = sums.data() + static_cast<size_t>(y) * stride;
      for (int x = range.begin(); x < range.end(); ++x) d[x] += above[x];
    }
  });
}

// The finest k with (b >> k) - (a >> k) <= 1, for 0 <= a <= b. With d = b - a >= 2 and
// 2^(L-1) <= d < 2^L: below L - 1 the span is at least d >> k >= 2, at L at most 1. So L - 1 or L.
int spanLevel(int a, int b) {
  const auto d = static_cast<unsigned>(b - a);
  if (d <= 1) return 0;
  const int k = std::bit_width(d) - 1;
  return (b >> k) - (a >> k) <= 1 ? k : k + 1;
}

// Clamps [x0, x1) x [y0, y1) to [0, w] x [0, h]; false if empty.
bool clampRect(int w, int h, int& x0, int& y0, int& x1, int& y1) {
  x0 = clampi(x0, 0, w);
  x1 = clampi(x1, 0, w);
  y0 = clampi(y0, 0, h);
  y1 = clampi(y1, 0, h);
  return x0 < x1 && y0 < y1;
}

}  // namespace

double SummedAreaTable::rectSum(int x0, int y0, int x1, int y1) const {
  if (!clampRect(width, height, x0, y0, x1, y1)) return 0.0;
  return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
}

SummedAreaTable buildSat(const ImageFloat& src) {
  SummedAreaTable t;
  t.width = src.width();
  t.height = src.height();
  buildSums(src, t.sums);
  return t;
}

uint64_t SummedAreaTableU64::rectSum(int x0, int y0, int x1, int y1) const {
  if (!clampRect(width, height, x0, y0, x1, y1)) return 0;
  return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);  // modulo 2^64, see kernels.h
}

SummedAreaTableU64 buildSatU64(const Image<uint32_t>& src) {
  SummedAreaTableU64 t;
  t.width = src.width();
  t.height = src.height();
  buildSums(src, t.sums);
  return t;
}

Image<uint32_t> quantize(const ImageFloat& src, float lo, float hi, int bits) {
  if (bits < 1 || bits > 24)
    throw std::invalid_argument("quantize: bits " + std::to_string(bits) + " outside [1, 24]");
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
    throw std::invalid_argument("quantize: range [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                "] is not finite and increasing");
  const double maxQ = static_cast<double>((1u << bits) - 1u);
  const double dlo = static_cast<double>(lo);
  const double scale = maxQ / (static_cast<double>(hi) - dlo);
  Image<uint32_t> out(src.width(), src.height());
  forRows(src.height(), kRowGrain, [&](int y) {
    const float* s = src.row(y);
    uint32_t* d = out.row(y);
    for (int x = 0; x < src.width(); ++x) {
      const double q = (static_cast<double>(s[x]) - dlo) * scale;
      // !(q > 0) also sends NaN to 0.
      d[x] = !(q > 0.0) ? 0u : q >= maxQ ? static_cast<uint32_t>(maxQ) : static_cast<uint32_t>(std::floor(q + 0.5));
    }
  });
  return out;
}

// --- Min/max pyramid and mip chain: one ceil-halving reduction -----------------------------------

namespace {

// Fills dst (already ceil-halved) from src: each texel is combine(children, n) over its existing
// children (1 to 4), always in the order top-left, top-right, bottom-left, bottom-right.
template <class Combine>
void reduceLevel(const ImageFloat& src, ImageFloat& dst, Combine combine) {
  const int sw = src.width(), sh = src.height();
  forRows(dst.height(), kRowGrain, [&](int y) {
    const float* r0 = src.row(2 * y);
    const float* r1 = 2 * y + 1 < sh ? src.row(2 * y + 1) : nullptr;
    float* d = dst.row(y);
    for (int x = 0; x < dst.width(); ++x) {
      const int c = 2 * x;
      const bool right = c + 1 < sw;
      float children[4];
      int n = 0;
      children[n++] = r0[c];
      if (right) children[n++] = r0[c + 1];
      if (r1) {
        children[n++] = r1[c];
        if (right) children[n++] = r1[c + 1];
      }
      d[x] = combine(children, n);
    }
  });
}

}  // namespace

MinMaxPyramid buildMinMaxPyramid(const ImageFloat& depth) {
  MinMaxPyramid p;
  if (depth.empty()) return p;
  // Every level sized and first written by the tasks (Image::resizeParallel): a 1024^2 map's
  // pyramid is 11 MB of fresh memory, whose page faults one thread would take alone.
  p.mins.emplace_back().resizeParallel(depth.width(), depth.height());
  p.maxs.emplace_back().resizeParallel(depth.width(), depth.height());
  forRows(depth.paddedRows(), kRowGrain, [&](int y) {  // padding included: a copy of the image
    std::copy(depth.row(y), depth.row(y) + depth.stride(), p.mins[0].row(y));
    std::copy(depth.row(y), depth.row(y) + depth.stride(), p.maxs[0].row(y));
  });
  while (p.mins.back().width() > 1 || p.mins.back().height() > 1) {
    const int w = half(p.mins.back().width()), h = half(p.mins.back().height());
    ImageFloat mn, mx;
    mn.resizeParallel(w, h);
    mx.resizeParallel(w, h);
    reduceLevel(p.mins.back(), mn, [](const float* v, int n) { return *std::min_element(v, v + n); });
    reduceLevel(p.maxs.back(), mx, [](const float* v, int n) { return *std::max_element(v, v + n); });
    p.mins.push_back(std::move(mn));
    p.maxs.push_back(std::move(mx));
  }
  return p;
}

void queryMinMax(const MinMaxPyramid& pyramid, int x0, int y0, int x1, int y1, float& mn, float& mx) {
  int covered[4];
  queryMinMax(pyramid, x0, y0, x1, y1, mn, mx, covered);
}

void queryMinMax(const MinMaxPyramid& pyramid, int x0, int y0, int x1, int y1, float& mn, float& mx, int covered[4]) {
  covered[0] = covered[1] = covered[2] = covered[3] = 0;
  mn = std::numeric_limits<float>::infinity();
  mx = -std::numeric_limits<float>::infinity();
  if (pyramid.mins.empty()) return;
  const ImageFloat& base = pyramid.mins.front();
  if (!clampRect(base.width(), base.height(), x0, y0, x1, y1)) return;
  // Texel i of level k covers pixels [i << k, (i + 1) << k), so the rectangle's last pixel x1 - 1
  // lies in texel (x1 - 1) >> k: the finest level where both spans are at most 2 texels (spans
  // only shrink with k, so the larger of the axes' levels; the top level is 1x1).
  const int k = std::max(spanLevel(x0, x1 - 1), spanLevel(y0, y1 - 1));
  covered[0] = (x0 >> k) << k, covered[1] = (y0 >> k) << k;
  covered[2] = std::min((((x1 - 1) >> k) + 1) << k, base.width());
  covered[3] = std::min((((y1 - 1) >> k) + 1) << k, base.height());
  const ImageFloat& mins = pyramid.mins[static_cast<size_t>(k)];
  const ImageFloat& maxs = pyramid.maxs[static_cast<size_t>(k)];
  for (int ty = y0 >> k; ty <= (y1 - 1) >> k; ++ty)
    for (int tx = x0 >> k; tx <= (x1 - 1) >> k; ++tx) {
      mn = std::min(mn, mins.row(ty)[tx]);
      mx = std::max(mx, maxs.row(ty)[tx]);
    }
}

// --- Min/max stack ------------------------------------------------------------------------------

MinMaxStack buildMinMaxStack(const MinMaxPyramid& pyramid, int base) {
  MinMaxStack st;
  st.base = base;
  if (base < 0 || base >= pyramid.levels()) return st;
  st.width = pyramid.mins[0].width(), st.height = pyramid.mins[0].height();
  st.mins.push_back(pyramid.mins[static_cast<size_t>(base)]);
  st.maxs.push_back(pyramid.maxs[static_cast<size_t>(base)]);
  const int w = st.mins[0].width(), h = st.mins[0].height();
  // Level k + 1 from level k: the window at (i, j) is the four windows of level k at (i, j),
  // (i + s, j), (i, j + s), (i + s, j + s), s = 2^k, those past the edge left out.
  for (int s = 1; s < std::max(w, h); s *= 2) {
    const ImageFloat &pmn = st.mins.back(), &pmx = st.maxs.back();
    ImageFloat mn(w, h), mx(w, h);
    forRows(h, kRowGrain, [&](int y) {
      const bool down = y + s < h;
      for (int x = 0; x < w; ++x) {
        const bool right = x + s < w;
        float a = pmn.at(x, y), b = pmx.at(x, y);
        if (right) a = std::min(a, pmn.at(x + s, y)), b = std::max(b, pmx.at(x + s, y));
        if (down) a = std::min(a, pmn.at(x, y + s)), b = std::max(b, pmx.at(x, y + s));
        if (right && down) a = std::min(a, pmn.at(x + s, y + s)), b = std::max(b, pmx.at(x + s, y + s));
        mn.at(x, y) = a, mx.at(x, y) = b;
      }
    });
    st.mins.push_back(std::move(mn));
    st.maxs.push_back(std::move(mx));
  }
  return st;
}

void queryMinMax(const MinMaxStack& stack, int x0, int y0, int x1, int y1, float& mn, float& mx, int* windows) {
  mn = std::numeric_limits<float>::infinity();
  mx = -std::numeric_limits<float>::infinity();
  if (windows) *windows = 0;
  if (stack.mins.empty()) return;
  const int b = stack.base, w = stack.mins[0].width(), h = stack.mins[0].height();
  if (!clampRect(stack.width, stack.height, x0, y0, x1, y1)) return;
  // The grid texels touched, then the largest window that fits in both sides.
  const int i0 = x0 >> b, i1 = std::min(((x1 - 1) >> b) + 1, w);
  const int j0 = y0 >> b, j1 = std::min(((y1 - 1) >> b) + 1, h);
  const int side = std::min(i1 - i0, j1 - j0);
  int k = 0;
  while (k + 1 < stack.levels() && (2 << k) <= side) ++k;
  const int s = 1 << k;
  const ImageFloat &mins = stack.mins[static_cast<size_t>(k)], &maxs = stack.maxs[static_cast<size_t>(k)];
  // Windows at i0, i0 + s, ... and the last one flush with i1 (they overlap, which min/max allows).
  for (int j = j0;; j = std::min(j + s, j1 - s)) {
    for (int i = i0;; i = std::min(i + s, i1 - s)) {
      mn = std::min(mn, mins.at(i, j));
      mx = std::max(mx, maxs.at(i, j));
      if (windows) ++*windows;
      if (i + s >= i1) break;
    }
    if (j + s >= j1) break;
  }
}

// --- Mip chain -----------------------------------------------------------------------------------

std::vector<ImageFloat> mipChain(const ImageFloat& src) {
  std::vector<ImageFloat> mips;
  if (src.empty()) return mips;
  mips.push_back(src);
  while (mips.back().width() > 1 || mips.back().height() > 1) {
    const ImageFloat& prev = mips.back();
    const int sw = prev.width(), sh = prev.height();
    ImageFloat next(half(sw), half(sh));
    reduceLevel(prev, next, [](const float* v, int n) {
      double sum = 0.0;  // in double, children in their fixed order
      for (int i = 0; i < n; ++i) sum += static_cast<double>(v[i]);
      return static_cast<float>(sum / n);
    });
    mips.push_back(std::move(next));
  }
  return mips;
}

}  // namespace penumbra::raster
