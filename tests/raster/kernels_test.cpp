// Image kernels against slow obvious references: blurs against a direct 2D convolution, summed-area
// tables against brute-force sums, pyramids and mips against their footprints. Also same bits at
// 1, 2 and 7 threads, and the argument checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <utility>
#include <vector>

#include "raster/kernels.h"

namespace penumbra::raster {
namespace {

ImageFloat randomImage(int w, int h, uint32_t seed, float lo = 0.25f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  ImageFloat img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = dist(rng);
  return img;
}

template <class T>
bool sameBits(const Image<T>& a, const Image<T>& b) {
  if (a.width() != b.width() || a.height() != b.height()) return false;
  const std::vector<T> pa = a.packed(), pb = b.packed();
  return std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(T)) == 0;
}

int clampi(int v, int lo, int hi) { return std::min(std::max(v, lo), hi); }

// Direct 2D convolution with the separable weights w (taps -r..r), clamp-to-edge, in double.
std::vector<double> convolve2D(const ImageFloat& src, const std::vector<double>& w) {
  const int r = static_cast<int>(w.size() / 2), W = src.width(), H = src.height();
  std::vector<double> out(static_cast<size_t>(W) * static_cast<size_t>(H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double s = 0.0;
      for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i)
          s += w[static_cast<size_t>(i + r)] * w[static_cast<size_t>(j + r)] *
               static_cast<double>(src.at(clampi(x + i, 0, W - 1), clampi(y + j, 0, H - 1)));
      out[static_cast<size_t>(y) * static_cast<size_t>(W) + static_cast<size_t>(x)] = s;
    }
  return out;
}

void expectNear(const ImageFloat& got, const std::vector<double>& ref, double rel) {
  ASSERT_EQ(ref.size(), static_cast<size_t>(got.width()) * static_cast<size_t>(got.height()));
  int bad = 0;
  for (int y = 0; y < got.height(); ++y)
    for (int x = 0; x < got.width(); ++x) {
      const double r = ref[static_cast<size_t>(y) * static_cast<size_t>(got.width()) + static_cast<size_t>(x)];
      const double g = static_cast<double>(got.at(x, y));
      if (std::abs(g - r) > rel * std::abs(r) && bad++ < 5)
        ADD_FAILURE() << "pixel (" << x << ", " << y << "): got " << g << ", reference " << r;
    }
  EXPECT_EQ(bad, 0);
}

std::vector<double> gaussianTaps(double sigma) {
  const int r = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> w;
  double sum = 0.0;
  for (int k = -r; k <= r; ++k) {
    w.push_back(std::exp(-0.5 * k * k / (sigma * sigma)));
    sum += w.back();
  }
  for (double& v : w) v /= sum;
  return w;
}

const std::pair<int, int> kSizes[] = {{37, 23}, {5, 3}, {1, 1}, {64, 1}, {1, 19}};

// --- Blurs -------------------------------------------------------------------------------------

TEST(KernelsBlur, BoxMatchesDirectConvolution) {
  uint32_t seed = 1;
  for (auto [w, h] : kSizes)
    for (int radius : {1, 3, 8, 40}) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " radius " << radius);
      const ImageFloat src = randomImage(w, h, seed++);
      ImageFloat dst;
      boxBlur(src, dst, radius);
      ASSERT_EQ(dst.width(), w);
      ASSERT_EQ(dst.height(), h);
      expectNear(dst, convolve2D(src, std::vector<double>(static_cast<size_t>(2 * radius + 1), 1.0 / (2 * radius + 1))),
                 1e-5);
    }
}

TEST(KernelsBlur, GaussianMatchesDirectConvolution) {
  uint32_t seed = 100;
  for (auto [w, h] : kSizes)
    for (float sigma : {0.3f, 1.0f, 2.5f, 7.0f}) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " sigma " << sigma);
      const ImageFloat src = randomImage(w, h, seed++);
      ImageFloat dst;
      gaussianBlur(src, dst, sigma);
      ASSERT_EQ(dst.width(), w);
      ASSERT_EQ(dst.height(), h);
      expectNear(dst, convolve2D(src, gaussianTaps(static_cast<double>(sigma))), 1e-5);
    }
}

TEST(KernelsBlur, ZeroRadiusAndZeroSigmaCopy) {
  const ImageFloat src = randomImage(19, 11, 7);
  ImageFloat a, b;
  boxBlur(src, a, 0);
  gaussianBlur(src, b, 0.0f);
  EXPECT_TRUE(sameBits(a, src));
  EXPECT_TRUE(sameBits(b, src));
}

TEST(KernelsBlur, InPlaceEqualsOutOfPlace) {
  const ImageFloat src = randomImage(29, 17, 8);
  ImageFloat out, inPlace = src;
  gaussianBlur(src, out, 1.7f);
  gaussianBlur(inPlace, inPlace, 1.7f);
  EXPECT_TRUE(sameBits(out, inPlace));
  ImageFloat boxOut, boxInPlace = src;
  boxBlur(src, boxOut, 4);
  boxBlur(boxInPlace, boxInPlace, 4);
  EXPECT_TRUE(sameBits(boxOut, boxInPlace));
}

TEST(KernelsBlur, Float4EqualsEachChannelBitForBit) {
  const int w = 23, h = 31;
  ImageFloat ch[4] = {randomImage(w, h, 11), randomImage(w, h, 12, -3.0f, 3.0f), randomImage(w, h, 13),
                      randomImage(w, h, 14, 0.0f, 100.0f)};
  ImageFloat4 src(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) src.at(x, y) = {ch[0].at(x, y), ch[1].at(x, y), ch[2].at(x, y), ch[3].at(x, y)};
  ImageFloat4 dst;
  gaussianBlur(src, dst, 2.2f);
  ASSERT_EQ(dst.width(), w);
  ASSERT_EQ(dst.height(), h);
  float Float4::*members[4] = {&Float4::r, &Float4::g, &Float4::b, &Float4::a};
  for (int c = 0; c < 4; ++c) {
    ImageFloat one;
    gaussianBlur(ch[c], one, 2.2f);
    ImageFloat got(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) got.at(x, y) = dst.at(x, y).*members[c];
    EXPECT_TRUE(sameBits(got, one)) << "channel " << c;
  }
}

TEST(KernelsBlur, RejectsOutOfRangeArguments) {
  const ImageFloat src = randomImage(4, 3, 9);
  ImageFloat dst;
  EXPECT_THROW(boxBlur(src, dst, -1), std::invalid_argument);
  EXPECT_THROW(boxBlur(src, dst, 1025), std::invalid_argument);
  EXPECT_THROW(gaussianBlur(src, dst, -0.5f), std::invalid_argument);
  EXPECT_THROW(gaussianBlur(src, dst, 300.5f), std::invalid_argument);
  EXPECT_THROW(gaussianBlur(src, dst, std::numeric_limits<float>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(gaussianBlur(src, dst, std::numeric_limits<float>::infinity()), std::invalid_argument);
  ImageFloat4 src4(4, 3), dst4;
  EXPECT_THROW(gaussianBlur(src4, dst4, -1.0f), std::invalid_argument);
  // The limits themselves are valid; on a 4x3 image every tap clamps, so the result is the mean of
  // the image weighted by edge multiplicity, which stays within the input's range.
  EXPECT_NO_THROW(boxBlur(src, dst, 1024));
  EXPECT_NO_THROW(gaussianBlur(src, dst, 300.0f));
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      EXPECT_GE(dst.at(x, y), 0.25f);
      EXPECT_LE(dst.at(x, y), 1.0f);
    }
}

// --- Determinism ---------------------------------------------------------------------------------

struct AllOutputs {
  ImageFloat box, gauss;
  ImageFloat4 gauss4;
  std::vector<double> sat;
  std::vector<uint64_t> satU64;
  Image<uint32_t> quantized;
  MinMaxPyramid pyramid;
  std::vector<ImageFloat> mips;
};

AllOutputs runAll(const ImageFloat& src, const ImageFloat4& src4) {
  AllOutputs o;
  boxBlur(src, o.box, 5);
  gaussianBlur(src, o.gauss, 2.0f);
  gaussianBlur(src4, o.gauss4, 1.5f);
  o.sat = buildSat(src).sums;
  o.quantized = quantize(src, 0.0f, 1.0f, 24);
  o.satU64 = buildSatU64(o.quantized).sums;
  o.pyramid = buildMinMaxPyramid(src);
  o.mips = mipChain(src);
  return o;
}

TEST(KernelsDeterminism, SameBitsAt1And2And7Threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 8);
  const int w = 263, h = 197;
  const ImageFloat src = randomImage(w, h, 21, -2.0f, 5.0f);
  ImageFloat4 src4(w, h);
  const ImageFloat g = randomImage(w, h, 22), b = randomImage(w, h, 23), a = randomImage(w, h, 24);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) src4.at(x, y) = {src.at(x, y), g.at(x, y), b.at(x, y), a.at(x, y)};

  AllOutputs ref;
  tbb::task_arena(1).execute([&] { ref = runAll(src, src4); });
  for (int threads : {2, 7}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    AllOutputs o;
    tbb::task_arena(threads).execute([&] { o = runAll(src, src4); });
    EXPECT_TRUE(sameBits(o.box, ref.box));
    EXPECT_TRUE(sameBits(o.gauss, ref.gauss));
    EXPECT_TRUE(sameBits(o.gauss4, ref.gauss4));
    EXPECT_TRUE(sameBits(o.quantized, ref.quantized));
    ASSERT_EQ(o.sat.size(), ref.sat.size());
    EXPECT_EQ(std::memcmp(o.sat.data(), ref.sat.data(), o.sat.size() * sizeof(double)), 0);
    EXPECT_EQ(o.satU64, ref.satU64);
    ASSERT_EQ(o.pyramid.levels(), ref.pyramid.levels());
    for (int k = 0; k < ref.pyramid.levels(); ++k) {
      EXPECT_TRUE(sameBits(o.pyramid.mins[static_cast<size_t>(k)], ref.pyramid.mins[static_cast<size_t>(k)]));
      EXPECT_TRUE(sameBits(o.pyramid.maxs[static_cast<size_t>(k)], ref.pyramid.maxs[static_cast<size_t>(k)]));
    }
    ASSERT_EQ(o.mips.size(), ref.mips.size());
    for (size_t k = 0; k < ref.mips.size(); ++k) EXPECT_TRUE(sameBits(o.mips[k], ref.mips[k])) << "mip " << k;
  }
}

// --- Summed-area tables --------------------------------------------------------------------------

// Random rectangles, some beyond the image, some empty or inverted, plus the border cases.
std::vector<std::array<int, 4>> testRects(int w, int h, uint32_t seed) {
  std::vector<std::array<int, 4>> rects = {
      {0, 0, w, h},         {0, 0, 1, 1},         {w - 1, h - 1, w, h}, {0, h - 1, w, h},
      {w - 1, 0, w, h},     {-10, -10, w + 10, h + 10}, {3, 2, 3, 9},   {2, 5, 9, 5},
      {7, 4, 2, 1},         {w, 0, w + 5, h},     {-5, -5, 0, 0},       {0, 0, w, 1}};
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dx(-4, w + 4), dy(-4, h + 4);
  for (int i = 0; i < 600; ++i) {
    int x0 = dx(rng), x1 = dx(rng), y0 = dy(rng), y1 = dy(rng);
    if (i % 3 != 0) {  // two thirds well-formed, the rest possibly inverted
      if (x0 > x1) std::swap(x0, x1);
      if (y0 > y1) std::swap(y0, y1);
    }
    rects.push_back({x0, y0, x1, y1});
  }
  return rects;
}

template <class T, class Sum>
Sum bruteSum(const Image<T>& img, std::array<int, 4> r) {
  Sum s{0};
  for (int y = std::max(r[1], 0); y < std::min(r[3], img.height()); ++y)
    for (int x = std::max(r[0], 0); x < std::min(r[2], img.width()); ++x) s += static_cast<Sum>(img.at(x, y));
  return s;
}

TEST(KernelsSat, DoubleMatchesBruteForce) {
  const int w = 61, h = 47;
  const ImageFloat src = randomImage(w, h, 31, -1.0f, 2.0f);
  const SummedAreaTable sat = buildSat(src);
  ASSERT_EQ(sat.width, w);
  ASSERT_EQ(sat.height, h);
  ASSERT_EQ(sat.sums.size(), static_cast<size_t>((w + 1) * (h + 1)));
  for (int x = 0; x <= w; ++x) EXPECT_EQ(sat.at(x, 0), 0.0);
  for (int y = 0; y <= h; ++y) EXPECT_EQ(sat.at(0, y), 0.0);
  int empty = 0;
  for (const auto& r : testRects(w, h, 32)) {
    const double ref = bruteSum<float, double>(src, r);
    const double got = sat.rectSum(r[0], r[1], r[2], r[3]);
    if (ref == 0.0) ++empty;
    EXPECT_NEAR(got, ref, 1e-9 * std::max(1.0, std::abs(ref)))
        << "rect [" << r[0] << ", " << r[2] << ") x [" << r[1] << ", " << r[3] << ")";
  }
  EXPECT_GT(empty, 10);  // the empty and inverted cases were exercised
}

TEST(KernelsSat, U64IsExact) {
  const int w = 53, h = 41;
  const Image<uint32_t> q = quantize(randomImage(w, h, 41, 0.0f, 1.0f), 0.0f, 1.0f, 24);
  const SummedAreaTableU64 sat = buildSatU64(q);
  ASSERT_EQ(sat.sums.size(), static_cast<size_t>((w + 1) * (h + 1)));
  for (const auto& r : testRects(w, h, 42))
    EXPECT_EQ(sat.rectSum(r[0], r[1], r[2], r[3]), (bruteSum<uint32_t, uint64_t>(q, r)))
        << "rect [" << r[0] << ", " << r[2] << ") x [" << r[1] << ", " << r[3] << ")";
  // Entries past 2^32: the table must not truncate to 32 bits anywhere.
  const Image<uint32_t> full(300, 300, (1u << 24) - 1u);
  const SummedAreaTableU64 big = buildSatU64(full);
  EXPECT_EQ(big.rectSum(0, 0, 300, 300), uint64_t{90000} * ((uint64_t{1} << 24) - 1u));
  EXPECT_EQ(big.rectSum(17, 5, 18, 6), (uint64_t{1} << 24) - 1u);
}

TEST(KernelsSat, EmptyImage) {
  const SummedAreaTable sat = buildSat(ImageFloat(0, 5));
  EXPECT_EQ(sat.sums.size(), 6u);
  EXPECT_EQ(sat.rectSum(0, 0, 10, 10), 0.0);
}

TEST(KernelsQuantize, MapsRangeRoundsAndClamps) {
  ImageFloat src(7, 1);
  const float values[7] = {-5.0f, -1.0f, 1.0f, 3.0f, 10.0f, 0.0f, std::numeric_limits<float>::quiet_NaN()};
  for (int x = 0; x < 7; ++x) src.at(x, 0) = values[x];
  const Image<uint32_t> q8 = quantize(src, -1.0f, 3.0f, 8);
  const uint32_t expect8[7] = {0, 0, 128, 255, 255, 64, 0};  // 127.5 -> 128, 63.75 -> 64
  for (int x = 0; x < 7; ++x) EXPECT_EQ(q8.at(x, 0), expect8[x]) << "x " << x;
  const Image<uint32_t> q24 = quantize(src, -1.0f, 3.0f, 24);
  EXPECT_EQ(q24.at(3, 0), (1u << 24) - 1u);
  EXPECT_EQ(q24.at(4, 0), (1u << 24) - 1u);
  EXPECT_EQ(q24.at(2, 0), 1u << 23);  // 0.5 * (2^24 - 1) = 8388607.5 -> 8388608
  const Image<uint32_t> q1 = quantize(src, -1.0f, 3.0f, 1);
  EXPECT_EQ(q1.at(1, 0), 0u);
  EXPECT_EQ(q1.at(3, 0), 1u);
  EXPECT_THROW(quantize(src, 0.0f, 1.0f, 0), std::invalid_argument);
  EXPECT_THROW(quantize(src, 0.0f, 1.0f, 25), std::invalid_argument);
  EXPECT_THROW(quantize(src, 1.0f, 1.0f, 8), std::invalid_argument);
  EXPECT_THROW(quantize(src, 2.0f, 1.0f, 8), std::invalid_argument);
  EXPECT_THROW(quantize(src, 0.0f, std::numeric_limits<float>::infinity(), 8), std::invalid_argument);
}

// --- Min/max pyramid and mips ------------------------------------------------------------------

std::vector<std::pair<int, int>> expectedSizes(int w, int h) {
  std::vector<std::pair<int, int>> s = {{w, h}};
  while (w > 1 || h > 1) {
    w = (w + 1) / 2;
    h = (h + 1) / 2;
    s.emplace_back(w, h);
  }
  return s;
}

TEST(KernelsPyramid, SizesForOddDimensions) {
  const std::vector<std::pair<int, int>> want13x7 = {{13, 7}, {7, 4}, {4, 2}, {2, 1}, {1, 1}};
  EXPECT_EQ(expectedSizes(13, 7), want13x7);
  for (auto [w, h] : {std::pair{13, 7}, std::pair{1, 1}, std::pair{1, 5}, std::pair{16, 8}, std::pair{33, 2}}) {
    SCOPED_TRACE(testing::Message() << w << "x" << h);
    const MinMaxPyramid p = buildMinMaxPyramid(randomImage(w, h, 51));
    const auto want = expectedSizes(w, h);
    ASSERT_EQ(p.levels(), static_cast<int>(want.size()));
    ASSERT_EQ(p.maxs.size(), want.size());
    for (size_t k = 0; k < want.size(); ++k) {
      EXPECT_EQ(p.mins[k].width(), want[k].first);
      EXPECT_EQ(p.mins[k].height(), want[k].second);
      EXPECT_EQ(p.maxs[k].width(), want[k].first);
      EXPECT_EQ(p.maxs[k].height(), want[k].second);
    }
  }
  EXPECT_EQ(buildMinMaxPyramid(ImageFloat()).levels(), 0);
}

// Min and max over pixels [x0, x1) x [y0, y1) (already inside the image).
std::pair<float, float> bruteMinMax(const ImageFloat& img, int x0, int y0, int x1, int y1) {
  float mn = std::numeric_limits<float>::infinity(), mx = -mn;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      mn = std::min(mn, img.at(x, y));
      mx = std::max(mx, img.at(x, y));
    }
  return {mn, mx};
}

TEST(KernelsPyramid, LevelsEqualBruteForceOverFootprint) {
  for (auto [w, h] : {std::pair{13, 7}, std::pair{37, 21}, std::pair{1, 9}}) {
    SCOPED_TRACE(testing::Message() << w << "x" << h);
    const ImageFloat src = randomImage(w, h, 61, -1.0f, 1.0f);
    const MinMaxPyramid p = buildMinMaxPyramid(src);
    EXPECT_TRUE(sameBits(p.mins[0], src));
    EXPECT_TRUE(sameBits(p.maxs[0], src));
    for (int k = 1; k < p.levels(); ++k)
      for (int j = 0; j < p.mins[static_cast<size_t>(k)].height(); ++j)
        for (int i = 0; i < p.mins[static_cast<size_t>(k)].width(); ++i) {
          const auto [mn, mx] = bruteMinMax(src, i << k, j << k, std::min((i + 1) << k, w), std::min((j + 1) << k, h));
          EXPECT_EQ(p.mins[static_cast<size_t>(k)].at(i, j), mn) << "level " << k << " texel " << i << "," << j;
          EXPECT_EQ(p.maxs[static_cast<size_t>(k)].at(i, j), mx) << "level " << k << " texel " << i << "," << j;
        }
  }
}

TEST(KernelsPyramid, QueryBoundsContainBruteForceAndAreExactForTexels) {
  const int w = 45, h = 29;
  const ImageFloat src = randomImage(w, h, 71, -1.0f, 1.0f);
  const MinMaxPyramid p = buildMinMaxPyramid(src);
  const auto [globalMin, globalMax] = bruteMinMax(src, 0, 0, w, h);
  int tighter = 0;
  for (const auto& r : testRects(w, h, 72)) {
    float mn = 0, mx = 0;
    queryMinMax(p, r[0], r[1], r[2], r[3], mn, mx);
    const int x0 = std::clamp(r[0], 0, w), x1 = std::clamp(r[2], 0, w);
    const int y0 = std::clamp(r[1], 0, h), y1 = std::clamp(r[3], 0, h);
    const auto [bmn, bmx] = bruteMinMax(src, x0, y0, x1, y1);
    if (x0 >= x1 || y0 >= y1) {
      EXPECT_EQ(mn, std::numeric_limits<float>::infinity());
      EXPECT_EQ(mx, -std::numeric_limits<float>::infinity());
      continue;
    }
    EXPECT_LE(mn, bmn);
    EXPECT_GE(mx, bmx);
    EXPECT_GE(mn, globalMin);
    EXPECT_LE(mx, globalMax);
    if (mn > globalMin || mx < globalMax) ++tighter;
  }
  EXPECT_GT(tighter, 100);  // the bounds are not just the whole image's
  // Single pixels and every texel's footprint at every level: exact.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float mn = 0, mx = 0;
      queryMinMax(p, x, y, x + 1, y + 1, mn, mx);
      EXPECT_EQ(mn, src.at(x, y));
      EXPECT_EQ(mx, src.at(x, y));
    }
  for (int k = 1; k < p.levels(); ++k)
    for (int j = 0; j < p.mins[static_cast<size_t>(k)].height(); ++j)
      for (int i = 0; i < p.mins[static_cast<size_t>(k)].width(); ++i) {
        const int x0 = i << k, y0 = j << k, x1 = std::min((i + 1) << k, w), y1 = std::min((j + 1) << k, h);
        float mn = 0, mx = 0;
        queryMinMax(p, x0, y0, x1, y1, mn, mx);
        const auto [bmn, bmx] = bruteMinMax(src, x0, y0, x1, y1);
        EXPECT_EQ(mn, bmn) << "level " << k << " texel " << i << "," << j;
        EXPECT_EQ(mx, bmx) << "level " << k << " texel " << i << "," << j;
      }
  // The level read is the finest where the rectangle spans at most 2x2 texels (the loop below, the
  // definition), over every rectangle of a 1000 x 600 image with corners on a coarse lattice.
  {
    const int bw = 1000, bh = 600;
    const MinMaxPyramid big = buildMinMaxPyramid(ImageFloat(bw, bh, 0.5f));
    int compared = 0;
    for (int x0 = 0; x0 < bw; x0 += 37)
      for (int x1 = x0 + 1; x1 <= bw; x1 += 11)
        for (int y0 = 0; y0 < bh; y0 += 41)
          for (int y1 = y0 + 1; y1 <= bh; y1 += 29) {
            int k = 0;
            while ((((x1 - 1) >> k) - (x0 >> k)) > 1 || (((y1 - 1) >> k) - (y0 >> k)) > 1) ++k;
            const int want[4] = {(x0 >> k) << k, (y0 >> k) << k, std::min((((x1 - 1) >> k) + 1) << k, bw),
                                 std::min((((y1 - 1) >> k) + 1) << k, bh)};
            float bmn = 0, bmx = 0;
            int covered[4];
            queryMinMax(big, x0, y0, x1, y1, bmn, bmx, covered);
            for (int c = 0; c < 4; ++c) ASSERT_EQ(covered[c], want[c]) << x0 << "," << y0 << "," << x1 << "," << y1;
            ++compared;
          }
    EXPECT_GT(compared, 200'000);
  }
  float mn = 0, mx = 0;
  queryMinMax(MinMaxPyramid{}, 0, 0, 4, 4, mn, mx);
  EXPECT_EQ(mn, std::numeric_limits<float>::infinity());
  EXPECT_EQ(mx, -std::numeric_limits<float>::infinity());
}

TEST(KernelsStack, QueriesAreExactOverTheGridTexelsTouched) {
  // Base 0 (the multi-scale shadow map): exact min/max of the rectangle's pixels. Base 1 and 2 (the
  // hybrid Y map's stack on a pyramid level): exact over the rectangle rounded out to that level's
  // texels. Odd sizes, rectangles partly outside, thin and single-texel ones.
  for (auto [w, h] : {std::pair{45, 29}, std::pair{16, 16}, std::pair{1, 9}, std::pair{70, 3}}) {
    const ImageFloat src = randomImage(w, h, 81, -1.0f, 1.0f);
    const MinMaxPyramid p = buildMinMaxPyramid(src);
    for (int base = 0; base < std::min(3, p.levels()); ++base) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " base " << base);
      const MinMaxStack st = buildMinMaxStack(p, base);
      ASSERT_GT(st.levels(), 0);
      auto rects = testRects(w, h, 82);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) rects.push_back({x, y, x + 1, y + 1});
      rects.push_back({0, 0, w, h});
      rects.push_back({-5, -5, w + 5, h + 5});
      for (const auto& r : rects) {
        float mn = 0, mx = 0;
        int windows = 0;
        queryMinMax(st, r[0], r[1], r[2], r[3], mn, mx, &windows);
        int x0 = std::clamp(r[0], 0, w), x1 = std::clamp(r[2], 0, w);
        int y0 = std::clamp(r[1], 0, h), y1 = std::clamp(r[3], 0, h);
        if (x0 >= x1 || y0 >= y1) {
          EXPECT_EQ(mn, std::numeric_limits<float>::infinity());
          EXPECT_EQ(mx, -std::numeric_limits<float>::infinity());
          continue;
        }
        x0 = (x0 >> base) << base, y0 = (y0 >> base) << base;
        x1 = std::min((((x1 - 1) >> base) + 1) << base, w), y1 = std::min((((y1 - 1) >> base) + 1) << base, h);
        const auto [bmn, bmx] = bruteMinMax(src, x0, y0, x1, y1);
        ASSERT_EQ(mn, bmn) << r[0] << "," << r[1] << " " << r[2] << "," << r[3];
        ASSERT_EQ(mx, bmx) << r[0] << "," << r[1] << " " << r[2] << "," << r[3];
        // A rectangle of a x b texels reads at most ceil(a / s) ceil(b / s) windows, s >= min(a, b) / 2.
        const int a = ((x1 - 1) >> base) - (x0 >> base) + 1, b = ((y1 - 1) >> base) - (y0 >> base) + 1;
        const int small = std::min(a, b), large = std::max(a, b);
        EXPECT_LE(windows, 2 * ((2 * large + small - 1) / small)) << a << "x" << b;
      }
    }
  }
  float mn = 0, mx = 0;
  queryMinMax(MinMaxStack{}, 0, 0, 4, 4, mn, mx);
  EXPECT_EQ(mn, std::numeric_limits<float>::infinity());
  EXPECT_EQ(buildMinMaxStack(MinMaxPyramid{}, 0).levels(), 0);
}

TEST(KernelsMip, ConstantImageStaysConstantWithCeilSizes) {
  const ImageFloat src(13, 7, 0.1f);
  const std::vector<ImageFloat> mips = mipChain(src);
  const auto want = expectedSizes(13, 7);
  ASSERT_EQ(mips.size(), want.size());
  for (size_t k = 0; k < mips.size(); ++k) {
    EXPECT_EQ(mips[k].width(), want[k].first);
    EXPECT_EQ(mips[k].height(), want[k].second);
    for (int y = 0; y < mips[k].height(); ++y)
      for (int x = 0; x < mips[k].width(); ++x) EXPECT_EQ(mips[k].at(x, y), 0.1f) << "level " << k;
  }
  EXPECT_TRUE(mipChain(ImageFloat()).empty());
}

TEST(KernelsMip, LevelsAreMeansOfExistingChildren) {
  // Odd sizes: each texel the mean of its existing children in the previous level.
  const ImageFloat src = randomImage(13, 7, 81, -1.0f, 1.0f);
  const std::vector<ImageFloat> mips = mipChain(src);
  EXPECT_TRUE(sameBits(mips[0], src));
  for (size_t k = 1; k < mips.size(); ++k) {
    const ImageFloat& prev = mips[k - 1];
    for (int j = 0; j < mips[k].height(); ++j)
      for (int i = 0; i < mips[k].width(); ++i) {
        double sum = 0.0;
        int n = 0;
        for (int y = 2 * j; y < std::min(2 * j + 2, prev.height()); ++y)
          for (int x = 2 * i; x < std::min(2 * i + 2, prev.width()); ++x) {
            sum += static_cast<double>(prev.at(x, y));
            ++n;
          }
        EXPECT_FLOAT_EQ(mips[k].at(i, j), static_cast<float>(sum / n)) << "level " << k << " texel " << i << "," << j;
      }
  }
  // Power-of-two sizes: level k is the plain mean over each 2^k x 2^k block of pixels.
  const ImageFloat pot = randomImage(16, 8, 82, 0.0f, 1.0f);
  const std::vector<ImageFloat> potMips = mipChain(pot);
  ASSERT_EQ(potMips.size(), 5u);
  for (int k = 1; k < 5; ++k)
    for (int j = 0; j < potMips[static_cast<size_t>(k)].height(); ++j)
      for (int i = 0; i < potMips[static_cast<size_t>(k)].width(); ++i) {
        double sum = 0.0;
        int n = 0;
        for (int y = j << k; y < std::min((j + 1) << k, 8); ++y)
          for (int x = i << k; x < std::min((i + 1) << k, 16); ++x) {
            sum += static_cast<double>(pot.at(x, y));
            ++n;
          }
        EXPECT_NEAR(static_cast<double>(potMips[static_cast<size_t>(k)].at(i, j)), sum / n, 1e-6)
            << "level " << k << " texel " << i << "," << j;
      }
}

}  // namespace
}  // namespace penumbra::raster
