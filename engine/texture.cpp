#include "engine/texture.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

namespace penumbra::engine {
namespace {

using raster::ImageRgba8;
using raster::Rgba8;

const std::array<float, 256>& srgbTable() {
  // Built once on first use (thread-safe static initialization), immutable afterwards.
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[static_cast<size_t>(i)] =
          static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

uint8_t alphaToByte(float a) {
  if (!(a > 0.0f)) return 0;  // also NaN
  if (a >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(a * 255.0f));
}

// One source texel's share of a destination texel along one axis.
struct Tap {
  int index;
  float weight;
};

// Destination texel i of a dst-texel axis covers source interval [i * src / dst, (i + 1) * src / dst);
// each source texel j it overlaps gets weight |[j, j + 1) ∩ interval| / |interval|.
std::vector<std::vector<Tap>> boxFootprints(int src, int dst) {
  std::vector<std::vector<Tap>> taps(static_cast<size_t>(dst));
  const double scale = static_cast<double>(src) / dst;
  for (int i = 0; i < dst; ++i) {
    const double lo = i * scale, hi = (i + 1) * scale;
    const int j0 = static_cast<int>(std::floor(lo));
    const int j1 = std::min(src, static_cast<int>(std::ceil(hi)));
    for (int j = j0; j < j1; ++j) {
      const double overlap = std::min(hi, j + 1.0) - std::max(lo, static_cast<double>(j));
      if (overlap > 0.0) taps[static_cast<size_t>(i)].push_back({j, static_cast<float>(overlap / scale)});
    }
  }
  return taps;
}

glm::vec4 decode(const Rgba8& t) {
  const std::array<float, 256>& lut = srgbTable();
  return {lut[t.r], lut[t.g], lut[t.b], static_cast<float>(t.a) * (1.0f / 255.0f)};
}

ImageRgba8 downsample(const ImageRgba8& src) {
  const int sw = src.width(), sh = src.height();
  const int dw = std::max(1, sw / 2), dh = std::max(1, sh / 2);
  // Decode the source once: linear color, alpha as stored.
  std::vector<glm::vec4> lin(static_cast<size_t>(sw) * static_cast<size_t>(sh));
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x) lin[static_cast<size_t>(y) * static_cast<size_t>(sw) + static_cast<size_t>(x)] = decode(src.row(y)[x]);
  const std::vector<std::vector<Tap>> tx = boxFootprints(sw, dw), ty = boxFootprints(sh, dh);
  ImageRgba8 dst(dw, dh);
  // Each task owns whole destination rows and sums taps in a fixed order: deterministic.
  tbb::parallel_for(0, dh, [&](int y) {
    Rgba8* out = dst.row(y);
    for (int x = 0; x < dw; ++x) {
      glm::vec4 sum(0.0f);
      for (const Tap& ry : ty[static_cast<size_t>(y)]) {
        const glm::vec4* srcRow = lin.data() + static_cast<size_t>(ry.index) * static_cast<size_t>(sw);
        glm::vec4 rowSum(0.0f);
        for (const Tap& rx : tx[static_cast<size_t>(x)]) rowSum += srcRow[rx.index] * rx.weight;
        sum += rowSum * ry.weight;
      }
      out[x] = Rgba8{linearToSrgb(sum.x), linearToSrgb(sum.y), linearToSrgb(sum.z), alphaToByte(sum.w)};
    }
  });
  return dst;
}

// Bilinear lookup in one level with repeat wrapping.
glm::vec4 bilinear(const ImageRgba8& img, glm::vec2 uv) {
  const int w = img.width(), h = img.height();
  if (w <= 0 || h <= 0) return glm::vec4(1.0f);
  // Texel centers sit at half-integers: shift by 0.5 so that x0 is the texel left of the sample.
  const double x = static_cast<double>(uv.x) * w - 0.5, y = static_cast<double>(uv.y) * h - 0.5;
  const double xf = std::floor(x), yf = std::floor(y);
  const float fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf);
  auto wrap = [](double i, int n) {
    // i is a whole number. Below 2^30 in magnitude, with n below 2^23, i / n in double is within
    // 2^-23 of the true quotient, which is a whole number or at least 1 / n from one: the floor
    // below is exact, and the formula is the remainder in integers.
    if (std::abs(i) < 1073741824.0 && n < (1 << 23)) {
      const int r = static_cast<int>(i) % n;
      return r < 0 ? r + n : r;
    }
    const double m = i - n * std::floor(i / n);  // in [0, n], n only through rounding
    const int k = static_cast<int>(m);
    return k >= n ? 0 : k;
  };
  const int x0 = wrap(xf, w), y0 = wrap(yf, h);
  const int x1 = x0 + 1 == w ? 0 : x0 + 1, y1 = y0 + 1 == h ? 0 : y0 + 1;
  const glm::vec4 t00 = decode(img.row(y0)[x0]), t10 = decode(img.row(y0)[x1]);
  const glm::vec4 t01 = decode(img.row(y1)[x0]), t11 = decode(img.row(y1)[x1]);
  const glm::vec4 top = t00 + (t10 - t00) * fx;
  const glm::vec4 bottom = t01 + (t11 - t01) * fx;
  return top + (bottom - top) * fy;
}

}  // namespace

float srgbToLinear(uint8_t v) { return srgbTable()[v]; }

namespace {

// Code k is chosen when the encoded value c satisfies c * 255 >= k - 0.5, i.e. when linear is at
// least the decoded value of (k - 0.5) / 255: threshold[k] (threshold[0] = -1 takes everything else).
// Every float below 2^-13 gives 0 (threshold[1] is 1.5e-4); from there to 1 the floats are cut into
// buckets of 128 per octave (their top 7 mantissa bits, 0.8% apart), and bucket[i] holds the code of
// its smallest float. The thresholds are at least 0.9% apart, so a bucket holds at most one of them
// and a value's code is its bucket's or the next: a table lookup and at most two comparisons replace
// a binary search over 255 thresholds (three per pixel in the shading pass), with the same result
// (tests/engine/texture_test.cpp compares with the binary search on every 13th float in [0, 1] and
// on every float within 4096 ulps of a threshold).
constexpr uint32_t kLowestBucketBits = (127u - 13u) << 23;  // 2^-13
constexpr int kBucketShift = 23 - 7;
constexpr size_t kBuckets = size_t{13} << 7;  // octaves 2^-13 ... 2^-1

struct SrgbEncodeTables {
  std::array<float, 257> threshold{};  // [256]: +inf, so that no code passes 255
  std::array<uint8_t, kBuckets> bucket{};
};

const SrgbEncodeTables& srgbEncodeTables() {
  static const SrgbEncodeTables tables = [] {
    SrgbEncodeTables t;
    t.threshold[0] = -1.0f;
    for (int k = 1; k < 256; ++k) {
      const double c = (k - 0.5) / 255.0;
      t.threshold[static_cast<size_t>(k)] =
          static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    t.threshold[256] = INFINITY;
    for (size_t i = 0; i < kBuckets; ++i) {
      const float lowest = std::bit_cast<float>(kLowestBucketBits + (static_cast<uint32_t>(i) << kBucketShift));
      size_t k = 0;
      while (lowest >= t.threshold[k + 1]) ++k;
      t.bucket[i] = static_cast<uint8_t>(k);
    }
    return t;
  }();
  return tables;
}

}  // namespace

uint8_t linearToSrgb(float linear) {
  const SrgbEncodeTables& t = srgbEncodeTables();
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  const uint32_t bits = std::bit_cast<uint32_t>(linear);
  if (bits < kLowestBucketBits) return 0;
  size_t k = t.bucket[(bits - kLowestBucketBits) >> kBucketShift];
  while (linear >= t.threshold[k + 1]) ++k;
  return static_cast<uint8_t>(k);
}

void buildMips(Texture& texture) {
  if (texture.mips.empty()) return;
  texture.mips.resize(1);
  if (texture.mips[0].empty()) return;
  while (texture.mips.back().width() > 1 || texture.mips.back().height() > 1)
    texture.mips.push_back(downsample(texture.mips.back()));
}

glm::vec4 sampleBilinear(const Texture& texture, glm::vec2 uv, float lod) {
  if (texture.mips.empty() || texture.mips[0].empty()) return glm::vec4(1.0f);
  if (!std::isfinite(uv.x)) uv.x = 0.0f;
  if (!std::isfinite(uv.y)) uv.y = 0.0f;
  const int last = static_cast<int>(texture.mips.size()) - 1;
  if (!(lod > 0.0f)) lod = 0.0f;  // also NaN
  if (lod >= static_cast<float>(last)) return bilinear(texture.mips[static_cast<size_t>(last)], uv);
  const int l0 = static_cast<int>(lod);
  const float t = lod - static_cast<float>(l0);
  const glm::vec4 a = bilinear(texture.mips[static_cast<size_t>(l0)], uv);
  if (t == 0.0f) return a;
  const glm::vec4 b = bilinear(texture.mips[static_cast<size_t>(l0) + 1], uv);
  return a + (b - a) * t;
}

}  // namespace penumbra::engine
