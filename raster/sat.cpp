// Multi-channel summed-area tables, the SAT tile grid and four-channel mip chains (see sat.h).
#include "raster/sat.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace penumbra::raster {
namespace {

// The columns (or rows) of a box side [a0, a1) clamped to [0, size]: at most three segments, the
// first partial texel, the whole texels between, the last partial texel, as entry indices
// e[0] <= e[1] <= e[2] <= e[3] and weights w[0..2] (the covered fraction of a texel; 1 between).
struct Axis {
  int e[4];
  double w[3];
};
bool axisSegments(double a0, double a1, int size, Axis& ax) {
  a0 = std::max(a0, 0.0);
  a1 = std::min(a1, static_cast<double>(size));
  if (!(a0 < a1)) return false;  // also NaN
  // 0 <= a0 < a1 <= size: truncation is the floor (std::floor is a library call without SSE4.1).
  const int i0 = static_cast<int>(a0), i1 = static_cast<int>(a1);
  if (i1 == i0) {
    ax = {{i0, i0 + 1, i0 + 1, i0 + 1}, {a1 - a0, 0.0, 0.0}};
  } else {
    ax = {{i0, i0 + 1, i1, std::min(i1 + 1, size)},
          {static_cast<double>(i0 + 1) - a0, 1.0, a1 - static_cast<double>(i1)}};
  }
  return true;
}

// The ceiling of x in [0, 2^31) (std::ceil is a library call without SSE4.1).
int ceilOf(double x) {
  const int i = static_cast<int>(x);
  return static_cast<double>(i) < x ? i + 1 : i;
}

// Differences of table entries in the table's arithmetic (exact modulo 2^64 for integers).
template <class Sum>
double rectDiff(const Sum* e11, const Sum* e01, const Sum* e10, const Sum* e00, int c) {
  const auto d = static_cast<Sum>(e11[c] - e01[c] - e10[c] + e00[c]);
  // A rectangle's true sum is below 2^63 (sat.h: bits <= 24, up to 2^39 texels): through int64
  // the value is the same, and the conversion one instruction (uint64 needs a branchy sequence
  // before AVX-512).
  if constexpr (std::is_same_v<Sum, uint64_t>)
    return static_cast<double>(static_cast<int64_t>(d));
  else
    return static_cast<double>(d);
}

// The box query on any table: entry(x, y) points at S(x, y)'s channels. C > 0 fixes the channel
// count at compile time (the loops unroll; the result is the same), C = 0 takes `channels`.
template <class Sum, int C, class Entry>
double boxQuery(double x0, double y0, double x1, double y1, int width, int height, int channels, Entry entry,
                double* out) {
  const int ch = C > 0 ? C : channels;
  std::fill(out, out + ch, 0.0);
  Axis ax, ay;
  if (!axisSegments(x0, x1, width, ax) || !axisSegments(y0, y1, height, ay)) return 0.0;
  const Sum* e[4][4];
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) e[j][i] = entry(ax.e[i], ay.e[j]);
  for (int b = 0; b < 3; ++b) {
    if (ay.e[b + 1] == ay.e[b]) continue;
    for (int a = 0; a < 3; ++a) {
      if (ax.e[a + 1] == ax.e[a]) continue;
      const double wt = ax.w[a] * ay.w[b];
      for (int c = 0; c < ch; ++c)
        out[c] += wt * rectDiff<Sum>(e[b + 1][a + 1], e[b + 1][a], e[b][a + 1], e[b][a], c);
    }
  }
  const double area = (std::min(x1, static_cast<double>(width)) - std::max(x0, 0.0)) *
                      (std::min(y1, static_cast<double>(height)) - std::max(y0, 0.0));
  return area;
}
template <class Sum, class Entry>
double boxQuery(double x0, double y0, double x1, double y1, int width, int height, int channels, Entry entry,
                double* out) {
  switch (channels) {
    case 1:
      return boxQuery<Sum, 1>(x0, y0, x1, y1, width, height, channels, entry, out);
    case 2:
      return boxQuery<Sum, 2>(x0, y0, x1, y1, width, height, channels, entry, out);
    case 4:
      return boxQuery<Sum, 4>(x0, y0, x1, y1, width, height, channels, entry, out);
    default:
      return boxQuery<Sum, 0>(x0, y0, x1, y1, width, height, channels, entry, out);
  }
}

// Horizontal prefixes with rows in parallel, then vertical prefixes with strips of columns.
template <class Sum, class Pixel>
MultiSat<Sum> buildMulti(const Planes<Pixel>& src) {
  if (src.channels < 1 || src.channels > kMaxSatChannels)
    throw std::invalid_argument("summed-area table: " + std::to_string(src.channels) +
                                " channels outside [1, " + std::to_string(kMaxSatChannels) + "]");
  MultiSat<Sum> t;
  t.width = src.width, t.height = src.height, t.channels = src.channels;
  const int w = src.width, h = src.height, ch = src.channels;
  const size_t rowLen = static_cast<size_t>(w + 1) * static_cast<size_t>(ch);
  t.sums.assign(rowLen * static_cast<size_t>(h + 1), Sum{0});
  if (w == 0 || h == 0) return t;
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& r) {
    Sum acc[kMaxSatChannels];
    for (int y = r.begin(); y < r.end(); ++y) {
      std::fill(acc, acc + ch, Sum{0});
      Sum* d = t.sums.data() + static_cast<size_t>(y + 1) * rowLen;
      for (int x = 0; x < w; ++x) {
        const Pixel* s = src.pixel(x, y);
        for (int c = 0; c < ch; ++c) {
          acc[c] = static_cast<Sum>(acc[c] + static_cast<Sum>(s[c]));
          d[static_cast<size_t>(x + 1) * ch + c] = acc[c];
        }
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rowLen, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (int y = 2; y <= h; ++y) {
      const Sum* above = t.sums.data() + static_cast<size_t>(y - 1) * rowLen;
      Sum* d = t.sums.data() + static_cast<size_t>(y) * rowLen;
      for (size_t i = r.begin(); i < r.end(); ++i) d[i] = static_cast<Sum>(d[i] + above[i]);
    }
  });
  return t;
}

constexpr int kMaxGrid = 8;  // gridSums' n

// The n + 1 lines splitting [a0, a1) into n equal parts (unclamped).
void gridLines(double a0, double a1, int n, double* g) {
  for (int k = 0; k <= n; ++k) g[k] = a0 + (a1 - a0) * (static_cast<double>(k) / n);
}

// Ceil halving (kernels.h).
int half(int n) {
  return (n + 1) / 2;
}

}  // namespace

template <class Sum>
double MultiSat<Sum>::boxSum(double x0, double y0, double x1, double y1, double* out) const {
  return boxQuery<Sum>(
      x0, y0, x1, y1, width, height, channels, [&](int x, int y) { return entry(x, y); }, out);
}

template <class Sum>
void MultiSat<Sum>::gridSums(double x0, double y0, double x1, double y1, int n, double* out,
                             double* area) const {
  constexpr int kMaxN = kMaxGrid;
  if (n < 1 || n > kMaxN) throw std::invalid_argument("gridSums: n " + std::to_string(n) + " outside [1, 8]");
  const int ch = channels;
  std::fill(out, out + n * n * ch, 0.0);
  std::fill(area, area + n * n, 0.0);
  const double cx0 = std::max(x0, 0.0), cy0 = std::max(y0, 0.0);
  if (!(cx0 < std::min(x1, static_cast<double>(width)) && cy0 < std::min(y1, static_cast<double>(height))))
    return;
  // Grid point k of an axis, clamped to [base, size]; R(gx, gy) = the integral over
  // [bx, gx) x [by, gy), bilinear in the exact integer rectangles from the base corner.
  // Coordinates here are >= 0: truncation is the floor.
  const int bx = static_cast<int>(cx0), by = static_cast<int>(cy0);
  double gx[kMaxN + 1], gy[kMaxN + 1];
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    gx[k] = std::clamp(x0 + (x1 - x0) * t, static_cast<double>(bx), static_cast<double>(width));
    gy[k] = std::clamp(y0 + (y1 - y0) * t, static_cast<double>(by), static_cast<double>(height));
  }
  const Sum* base = entry(bx, by);
  double r[(kMaxN + 1) * (kMaxN + 1) * kMaxSatChannels];
  for (int j = 0; j <= n; ++j) {
    int iy = static_cast<int>(gy[j]);
    if (iy >= height) iy = height - 1;
    const double fy = gy[j] - iy;
    for (int i = 0; i <= n; ++i) {
      int ix = static_cast<int>(gx[i]);
      if (ix >= width) ix = width - 1;
      const double fx = gx[i] - ix;
      const Sum* e00 = entry(ix, iy);
      const Sum* e10 = entry(ix + 1, iy);
      const Sum* e01 = entry(ix, iy + 1);
      const Sum* e11 = entry(ix + 1, iy + 1);
      const Sum* l0 = entry(bx, iy);
      const Sum* l1 = entry(bx, iy + 1);
      const Sum* t0 = entry(ix, by);
      const Sum* t1 = entry(ix + 1, by);
      double* d = r + (j * (n + 1) + i) * ch;
      for (int c = 0; c < ch; ++c) {
        const double i00 = rectDiff<Sum>(e00, t0, l0, base, c), i10 = rectDiff<Sum>(e10, t1, l0, base, c);
        const double i01 = rectDiff<Sum>(e01, t0, l1, base, c), i11 = rectDiff<Sum>(e11, t1, l1, base, c);
        d[c] = (1.0 - fy) * ((1.0 - fx) * i00 + fx * i10) + fy * ((1.0 - fx) * i01 + fx * i11);
      }
    }
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      area[j * n + i] = (gx[i + 1] - gx[i]) * (gy[j + 1] - gy[j]);
      const double* a = r + (j * (n + 1) + i) * ch;
      const double* b = r + (j * (n + 1) + i + 1) * ch;
      const double* c0 = r + ((j + 1) * (n + 1) + i) * ch;
      const double* d0 = r + ((j + 1) * (n + 1) + i + 1) * ch;
      for (int c = 0; c < ch; ++c) out[(j * n + i) * ch + c] = d0[c] - c0[c] - b[c] + a[c];
    }
}

template <class Sum>
void MultiSat<Sum>::roundingBound(double x1, double y1, double* bound) const {
  constexpr double u = std::is_same_v<Sum, float> ? 0x1p-24 : std::is_same_v<Sum, double> ? 0x1p-53 : 0.0;
  const int ix = std::clamp(static_cast<int>(std::ceil(x1)), 0, width);
  const int iy = std::clamp(static_cast<int>(std::ceil(y1)), 0, height);
  const Sum* e = entry(ix, iy);
  const double scale = 4.0 * static_cast<double>(width + height) * u;
  for (int c = 0; c < channels; ++c) bound[c] = scale * std::abs(static_cast<double>(e[c]));
}

template struct MultiSat<float>;
template struct MultiSat<double>;
template struct MultiSat<uint64_t>;

MultiSat<float> buildSatFloat(const Planes<float>& src) {
  return buildMulti<float>(src);
}
MultiSat<double> buildSatDouble(const Planes<float>& src) {
  return buildMulti<double>(src);
}
MultiSat<uint64_t> buildSatInteger(const Planes<uint32_t>& src) {
  return buildMulti<uint64_t>(src);
}

Planes<uint32_t> quantizePlanes(const Planes<float>& src, const std::vector<double>& lo,
                                const std::vector<double>& hi, int bits) {
  if (bits < 1 || bits > 24)
    throw std::invalid_argument("quantizePlanes: bits " + std::to_string(bits) + " outside [1, 24]");
  const int ch = src.channels;
  if (static_cast<int>(lo.size()) != ch || static_cast<int>(hi.size()) != ch)
    throw std::invalid_argument("quantizePlanes: one range per channel");
  const double maxQ = static_cast<double>((1u << bits) - 1u);
  Planes<uint32_t> out(src.width, src.height, ch);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, src.data.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
          const size_t c = i % static_cast<size_t>(ch);
          const double range = hi[c] - lo[c];
          const double q = range > 0.0 ? (static_cast<double>(src.data[i]) - lo[c]) / range * maxQ : 0.0;
          out.data[i] = !(q > 0.0)  ? 0u
                        : q >= maxQ ? static_cast<uint32_t>(maxQ)
                                    : static_cast<uint32_t>(std::floor(q + 0.5));
        }
      });
  return out;
}

// --- SAT tile grid -------------------------------------------------------------------------------

int stgTileSize(int bits) {
  if (bits < 1 || bits > 24)
    throw std::invalid_argument("stgTileSize: bits " + std::to_string(bits) + " outside [1, 24]");
  return 1 << ((32 - bits) / 2);
}

TiledSat buildTiledSat(const Planes<float>& src, int bits, const std::vector<uint8_t>& tileNeeded) {
  const size_t ch = static_cast<size_t>(std::max(src.channels, 0));
  return buildTiledSat(
      src.width, src.height, src.channels, bits,
      [&](int x0, int y0, int w, int h, float* out) {
        for (int y = 0; y < h; ++y)
          std::copy_n(src.pixel(x0, y0 + y), static_cast<size_t>(w) * ch,
                      out + static_cast<size_t>(y * w) * ch);
      },
      tileNeeded);
}

TiledSat buildTiledSat(int width, int height, int channels, int bits, const TileFill& fill,
                       const std::vector<uint8_t>& tileNeeded) {
  TiledSat t;
  t.width = width, t.height = height, t.channels = channels, t.bits = bits;
  t.tile = stgTileSize(bits);
  if (channels < 1 || channels > kMaxSatChannels)
    throw std::invalid_argument("buildTiledSat: " + std::to_string(channels) + " channels");
  const int T = t.tile, ch = t.channels;
  t.tilesX = (t.width + T - 1) / T, t.tilesY = (t.height + T - 1) / T;
  const size_t tiles = static_cast<size_t>(t.tilesX) * static_cast<size_t>(t.tilesY);
  if (!tileNeeded.empty() && tileNeeded.size() != tiles)
    throw std::invalid_argument("buildTiledSat: tile mask size");
  t.built.assign(tiles, 0);
  t.offset.assign(tiles, ~0u);
  t.lo.assign(tiles * ch, 0.0);
  t.step.assign(tiles * ch, 0.0);
  const size_t entrySize = static_cast<size_t>(T + 1) * static_cast<size_t>(T + 1) * static_cast<size_t>(ch);
  for (size_t i = 0; i < tiles; ++i)
    if (tileNeeded.empty() || tileNeeded[i]) {
      t.built[i] = 1;
      t.offset[i] = static_cast<uint32_t>(t.tilesBuilt++);
    }
  t.sums.assign(t.tilesBuilt * entrySize, 0u);
  const double maxQ = static_cast<double>((1u << bits) - 1u);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles, 1), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<float> texels(static_cast<size_t>(T) * static_cast<size_t>(T) * static_cast<size_t>(ch));
    for (size_t ti = r.begin(); ti < r.end(); ++ti) {
      if (!t.built[ti]) continue;
      const int tx = static_cast<int>(ti % static_cast<size_t>(t.tilesX)),
                ty = static_cast<int>(ti / static_cast<size_t>(t.tilesX));
      const int x0 = tx * T, y0 = ty * T, tw = std::min(T, t.width - x0), th = std::min(T, t.height - y0);
      fill(x0, y0, tw, th, texels.data());
      const auto pixel = [&](int x, int y) {
        return texels.data() + (static_cast<size_t>(y) * static_cast<size_t>(tw) + static_cast<size_t>(x)) *
                                   static_cast<size_t>(ch);
      };
      double lo[kMaxSatChannels], hi[kMaxSatChannels];
      std::fill(lo, lo + ch, std::numeric_limits<double>::infinity());
      std::fill(hi, hi + ch, -std::numeric_limits<double>::infinity());
      for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x) {
          const float* p = pixel(x, y);
          for (int c = 0; c < ch; ++c) {
            const double v = static_cast<double>(p[c]);
            if (v < lo[c]) lo[c] = v;
            if (v > hi[c]) hi[c] = v;
          }
        }
      double* tlo = t.lo.data() + ti * ch;
      double* tstep = t.step.data() + ti * ch;
      for (int c = 0; c < ch; ++c) {
        if (!(lo[c] <= hi[c])) lo[c] = hi[c] = 0.0;  // NaN only: a tile of NaN reads 0
        tlo[c] = lo[c];
        tstep[c] = (hi[c] - lo[c]) / maxQ;
      }
      uint32_t* s = t.sums.data() + t.offset[ti] * entrySize;
      const size_t stride = static_cast<size_t>(T + 1) * ch;
      for (int y = 0; y < th; ++y) {
        uint32_t* row = s + static_cast<size_t>(y + 1) * stride;
        const uint32_t* above = s + static_cast<size_t>(y) * stride;
        uint32_t acc[kMaxSatChannels] = {};
        for (int x = 0; x < tw; ++x) {
          const float* p = pixel(x, y);
          for (int c = 0; c < ch; ++c) {
            const double q = tstep[c] > 0.0 ? (static_cast<double>(p[c]) - tlo[c]) / tstep[c] : 0.0;
            acc[c] += !(q > 0.0)  ? 0u
                      : q >= maxQ ? static_cast<uint32_t>(maxQ)
                                  : static_cast<uint32_t>(std::floor(q + 0.5));
            row[static_cast<size_t>(x + 1) * ch + c] = acc[c] + above[static_cast<size_t>(x + 1) * ch + c];
          }
        }
      }
    }
  });
  return t;
}

double TiledSat::boxSum(double x0, double y0, double x1, double y1, double* out, double* bound) const {
  std::fill(out, out + channels, 0.0);
  if (bound) std::fill(bound, bound + channels, 0.0);
  const double cx0 = std::max(x0, 0.0), cy0 = std::max(y0, 0.0);
  const double cx1 = std::min(x1, static_cast<double>(width)),
               cy1 = std::min(y1, static_cast<double>(height));
  if (!(cx0 < cx1 && cy0 < cy1)) return 0.0;
  const int T = tile;
  const int tx0 = static_cast<int>(cx0) / T, ty0 = static_cast<int>(cy0) / T;
  const int tx1 = (ceilOf(cx1) - 1) / T, ty1 = (ceilOf(cy1) - 1) / T;
  const size_t entrySize =
      static_cast<size_t>(T + 1) * static_cast<size_t>(T + 1) * static_cast<size_t>(channels);
  const size_t stride = static_cast<size_t>(T + 1) * static_cast<size_t>(channels);
  double part[kMaxSatChannels];
  for (int ty = ty0; ty <= ty1; ++ty)
    for (int tx = tx0; tx <= tx1; ++tx) {
      const size_t ti = static_cast<size_t>(ty) * static_cast<size_t>(tilesX) + static_cast<size_t>(tx);
      const double ox = static_cast<double>(tx * T), oy = static_cast<double>(ty * T);
      const int tw = std::min(T, width - tx * T), th = std::min(T, height - ty * T);
      if (!built[ti]) {
        std::fill(out, out + channels, std::numeric_limits<double>::quiet_NaN());
        return 0.0;
      }
      const uint32_t* s = sums.data() + offset[ti] * entrySize;
      const double a = boxQuery<uint32_t>(
          cx0 - ox, cy0 - oy, cx1 - ox, cy1 - oy, tw, th, channels,
          [&](int x, int y) {
            return s + static_cast<size_t>(y) * stride + static_cast<size_t>(x) * channels;
          },
          part);
      const double* tlo = lo.data() + ti * channels;
      const double* tstep = step.data() + ti * channels;
      for (int c = 0; c < channels; ++c) out[c] += tlo[c] * a + tstep[c] * part[c];
      if (bound)
        for (int c = 0; c < channels; ++c) bound[c] += 0.5 * tstep[c] * a;
    }
  return (cx1 - cx0) * (cy1 - cy0);
}

namespace {
// TiledSat::gridSums with the channel count fixed at compile time (C > 0; 0: t.channels).
template <int C>
void tiledGridSums(const TiledSat& t, double x0, double y0, double x1, double y1, int n, double* out,
                   double* area, double* bound) {
  if (n < 1 || n > kMaxGrid)
    throw std::invalid_argument("gridSums: n " + std::to_string(n) + " outside [1, 8]");
  const int ch = C > 0 ? C : t.channels, parts = n * n;
  std::fill(out, out + parts * ch, 0.0);
  std::fill(area, area + parts, 0.0);
  if (bound) std::fill(bound, bound + parts * ch, 0.0);
  const double cx0 = std::max(x0, 0.0), cy0 = std::max(y0, 0.0);
  const double cx1 = std::min(x1, static_cast<double>(t.width)),
               cy1 = std::min(y1, static_cast<double>(t.height));
  if (!(cx0 < cx1 && cy0 < cy1)) return;
  double gx[kMaxGrid + 1], gy[kMaxGrid + 1];
  gridLines(x0, x1, n, gx);
  gridLines(y0, y1, n, gy);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double w = std::clamp(gx[i + 1], 0.0, static_cast<double>(t.width)) -
                       std::clamp(gx[i], 0.0, static_cast<double>(t.width));
      const double h = std::clamp(gy[j + 1], 0.0, static_cast<double>(t.height)) -
                       std::clamp(gy[j], 0.0, static_cast<double>(t.height));
      area[j * n + i] = std::max(w, 0.0) * std::max(h, 0.0);
    }
  const int T = t.tile;
  const int tx0 = static_cast<int>(cx0) / T, ty0 = static_cast<int>(cy0) / T;
  const int tx1 = (ceilOf(cx1) - 1) / T, ty1 = (ceilOf(cy1) - 1) / T;
  const size_t entrySize = static_cast<size_t>(T + 1) * static_cast<size_t>(T + 1) * static_cast<size_t>(ch);
  const size_t stride = static_cast<size_t>(T + 1) * static_cast<size_t>(ch);
  // The sub-boxes a span [o, o + size) of one axis meets: [first, last], a superset (the lines
  // are clamped to the tile below, so a sub-box outside it gets area 0 there).
  const auto span = [n](const double* g, double o, int size, int& first, int& last) {
    first = 0, last = n - 1;
    while (first < n - 1 && g[first + 1] <= o) ++first;
    while (last > first && g[last] >= o + size) --last;
  };
  // R(x, y) = the tile's integral over [0, x) x [0, y), x in [0, tw], y in [0, th]: bilinear in
  // its entries (exact for piecewise-constant texels), which are below 2^32 and exact in double.
  // At integer coordinates one entry (the first row and column hold 0).
  double r[(kMaxGrid + 1) * (kMaxGrid + 1) * (C > 0 ? C : kMaxSatChannels)];
  double lx[kMaxGrid + 1], ly[kMaxGrid + 1];
  for (int ty = ty0; ty <= ty1; ++ty)
    for (int tx = tx0; tx <= tx1; ++tx) {
      const size_t ti = static_cast<size_t>(ty) * static_cast<size_t>(t.tilesX) + static_cast<size_t>(tx);
      if (!t.built[ti]) {
        std::fill(out, out + parts * ch, std::numeric_limits<double>::quiet_NaN());
        return;
      }
      const double ox = static_cast<double>(tx * T), oy = static_cast<double>(ty * T);
      const int tw = std::min(T, t.width - tx * T), th = std::min(T, t.height - ty * T);
      int i0, i1, j0, j1;
      span(gx, ox, tw, i0, i1);
      span(gy, oy, th, j0, j1);
      const int mx = i1 - i0 + 1, my = j1 - j0 + 1;
      for (int k = 0; k <= mx; ++k) lx[k] = std::clamp(gx[i0 + k] - ox, 0.0, static_cast<double>(tw));
      for (int k = 0; k <= my; ++k) ly[k] = std::clamp(gy[j0 + k] - oy, 0.0, static_cast<double>(th));
      const uint32_t* s = t.sums.data() + t.offset[ti] * entrySize;
      const auto entry = [&](int x, int y) {
        return s + static_cast<size_t>(y) * stride + static_cast<size_t>(x) * static_cast<size_t>(ch);
      };
      const auto value = [](uint32_t v) { return static_cast<double>(static_cast<int64_t>(v)); };
      for (int l = 0; l <= my; ++l) {
        const int iy = static_cast<int>(ly[l]);  // >= 0: truncation is the floor
        const double fy = ly[l] - iy;            // 0 at y = th
        for (int k = 0; k <= mx; ++k) {
          double* d = r + (l * (mx + 1) + k) * ch;
          if (lx[k] == 0.0 || ly[l] == 0.0) {  // the tile's first column or row: R = 0
            std::fill(d, d + ch, 0.0);
            continue;
          }
          const int ix = static_cast<int>(lx[k]);
          const double fx = lx[k] - ix;
          const uint32_t* e00 = entry(ix, iy);
          if (fx == 0.0 && fy == 0.0) {
            for (int c = 0; c < ch; ++c) d[c] = value(e00[c]);
          } else if (fx == 0.0) {
            const uint32_t* e01 = entry(ix, iy + 1);
            for (int c = 0; c < ch; ++c) d[c] = (1.0 - fy) * value(e00[c]) + fy * value(e01[c]);
          } else if (fy == 0.0) {
            const uint32_t* e10 = entry(ix + 1, iy);
            for (int c = 0; c < ch; ++c) d[c] = (1.0 - fx) * value(e00[c]) + fx * value(e10[c]);
          } else {
            const uint32_t *e10 = entry(ix + 1, iy), *e01 = entry(ix, iy + 1), *e11 = entry(ix + 1, iy + 1);
            for (int c = 0; c < ch; ++c)
              d[c] = (1.0 - fy) * ((1.0 - fx) * value(e00[c]) + fx * value(e10[c])) +
                     fy * ((1.0 - fx) * value(e01[c]) + fx * value(e11[c]));
          }
        }
      }
      const double* tlo = t.lo.data() + ti * ch;
      const double* tstep = t.step.data() + ti * ch;
      for (int j = 0; j < my; ++j)
        for (int i = 0; i < mx; ++i) {
          const double a = (lx[i + 1] - lx[i]) * (ly[j + 1] - ly[j]);
          if (!(a > 0.0)) continue;
          const int p = (j0 + j) * n + i0 + i;
          double* o = out + p * ch;
          const double* ra = r + (j * (mx + 1) + i) * ch;
          const double* rb = r + (j * (mx + 1) + i + 1) * ch;
          const double* rc = r + ((j + 1) * (mx + 1) + i) * ch;
          const double* rd = r + ((j + 1) * (mx + 1) + i + 1) * ch;
          for (int c = 0; c < ch; ++c) o[c] += tlo[c] * a + tstep[c] * (rd[c] - rc[c] - rb[c] + ra[c]);
          if (bound)
            for (int c = 0; c < ch; ++c) bound[p * ch + c] += 0.5 * tstep[c] * a;
        }
    }
}

}  // namespace

void TiledSat::gridSums(double x0, double y0, double x1, double y1, int n, double* out, double* area,
                        double* bound) const {
  if (channels == 4)
    tiledGridSums<4>(*this, x0, y0, x1, y1, n, out, area, bound);
  else
    tiledGridSums<0>(*this, x0, y0, x1, y1, n, out, area, bound);
}

// --- Four-channel mips ---------------------------------------------------------------------------

std::vector<ImageFloat4> mipChain4(const ImageFloat4& src) {
  std::vector<ImageFloat4> mips;
  if (src.empty()) return mips;
  mips.push_back(src);
  while (mips.back().width() > 1 || mips.back().height() > 1) {
    const ImageFloat4& prev = mips.back();
    const int sw = prev.width(), sh = prev.height();
    ImageFloat4 next(half(sw), half(sh));
    tbb::parallel_for(tbb::blocked_range<int>(0, next.height(), 4), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y)
        for (int x = 0; x < next.width(); ++x) {
          double acc[4] = {0, 0, 0, 0};
          int n = 0;
          for (int dy = 0; dy < 2; ++dy)  // children in the fixed order TL, TR, BL, BR
            for (int dx = 0; dx < 2; ++dx) {
              const int cx = 2 * x + dx, cy = 2 * y + dy;
              if (cx >= sw || cy >= sh) continue;
              const Float4& c = prev.at(cx, cy);
              acc[0] += static_cast<double>(c.r), acc[1] += static_cast<double>(c.g);
              acc[2] += static_cast<double>(c.b), acc[3] += static_cast<double>(c.a), ++n;
            }
          next.at(x, y) = {static_cast<float>(acc[0] / n), static_cast<float>(acc[1] / n),
                           static_cast<float>(acc[2] / n), static_cast<float>(acc[3] / n)};
        }
    });
    mips.push_back(std::move(next));
  }
  return mips;
}

namespace {
std::array<double, 4> bilinear4(const ImageFloat4& img, double u, double v) {
  const auto axis = [](double p, int size, int& i0, int& i1, double& f) {
    double q = p - 0.5;
    if (!(q >= 0.0)) q = 0.0;
    if (q > static_cast<double>(size - 1)) q = static_cast<double>(size - 1);
    const double fl = std::floor(q);
    i0 = static_cast<int>(fl);
    i1 = std::min(i0 + 1, size - 1);
    f = q - fl;
  };
  int x0, x1, y0, y1;
  double fx, fy;
  axis(u, img.width(), x0, x1, fx);
  axis(v, img.height(), y0, y1, fy);
  const Float4 a = img.at(x0, y0), b = img.at(x1, y0), c = img.at(x0, y1), d = img.at(x1, y1);
  const auto mix = [&](double pa, double pb, double pc, double pd) {
    return (1.0 - fy) * ((1.0 - fx) * pa + fx * pb) + fy * ((1.0 - fx) * pc + fx * pd);
  };
  const auto d64 = [](float f) { return static_cast<double>(f); };
  return {mix(d64(a.r), d64(b.r), d64(c.r), d64(d.r)), mix(d64(a.g), d64(b.g), d64(c.g), d64(d.g)),
          mix(d64(a.b), d64(b.b), d64(c.b), d64(d.b)), mix(d64(a.a), d64(b.a), d64(c.a), d64(d.a))};
}
}  // namespace

std::array<double, 4> sampleTrilinear(const std::vector<ImageFloat4>& mips, double x, double y,
                                      double level) {
  if (mips.empty()) return {0, 0, 0, 0};
  const double top = static_cast<double>(mips.size() - 1);
  if (!(level > 0.0)) level = 0.0;
  if (level > top) level = top;
  const int k = static_cast<int>(std::floor(level));
  const double f = level - k;
  const double s0 = std::ldexp(1.0, -k);
  const std::array<double, 4> a = bilinear4(mips[static_cast<size_t>(k)], x * s0, y * s0);
  if (f == 0.0 || k + 1 >= static_cast<int>(mips.size())) return a;
  const std::array<double, 4> b = bilinear4(mips[static_cast<size_t>(k + 1)], x * s0 * 0.5, y * s0 * 0.5);
  return {(1 - f) * a[0] + f * b[0], (1 - f) * a[1] + f * b[1], (1 - f) * a[2] + f * b[2],
          (1 - f) * a[3] + f * b[3]};
}

}  // namespace penumbra::raster
