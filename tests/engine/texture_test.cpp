// Texture filtering: the sRGB pair, the box-filtered mip chain (sizes, constant images, linear-space
// averaging, odd-size footprints) and trilinear sampling (texel centers, wrapping, level blending).
#include "engine/texture.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace penumbra::engine {
namespace {

using raster::ImageRgba8;
using raster::Rgba8;

Texture makeTexture(int w, int h, Rgba8 (*texel)(int x, int y)) {
  Texture t;
  t.mips.emplace_back(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.mips[0].at(x, y) = texel(x, y);
  return t;
}

Rgba8 hashTexel(int x, int y) {
  const auto v = static_cast<unsigned>(x * 73856093 ^ y * 19349663);
  return {static_cast<uint8_t>(v), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v >> 16), static_cast<uint8_t>(v >> 3)};
}

glm::vec4 decoded(Rgba8 t) { return {srgbToLinear(t.r), srgbToLinear(t.g), srgbToLinear(t.b), t.a / 255.0f}; }

void expectNear(glm::vec4 a, glm::vec4 b, float eps = 1e-6f) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(a[c], b[c], eps) << "channel " << c;
}

TEST(Srgb, DecodeMatchesTheStandardAndRoundTrips) {
  EXPECT_EQ(srgbToLinear(0), 0.0f);
  EXPECT_EQ(srgbToLinear(255), 1.0f);
  EXPECT_NEAR(srgbToLinear(10), 10.0f / 255.0f / 12.92f, 1e-7f);  // linear segment
  EXPECT_NEAR(srgbToLinear(128), 0.2158605f, 1e-6f);
  for (int v = 0; v < 256; ++v) {
    EXPECT_EQ(linearToSrgb(srgbToLinear(static_cast<uint8_t>(v))), v);
    if (v > 0) {
      EXPECT_GT(srgbToLinear(static_cast<uint8_t>(v)), srgbToLinear(static_cast<uint8_t>(v - 1)));
    }
  }
  EXPECT_EQ(linearToSrgb(0.5f), 188);
  EXPECT_EQ(linearToSrgb(-1.0f), 0);
  EXPECT_EQ(linearToSrgb(7.0f), 255);
  EXPECT_EQ(linearToSrgb(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(linearToSrgb(std::numeric_limits<float>::infinity()), 255);
}

// The encoder before its bucket table: a binary search over the 255 thresholds, the decoded values
// of the codes' lower rounding bounds (k - 0.5) / 255.
float encodeThreshold(int k) {
  const double c = (k - 0.5) / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

uint8_t linearToSrgbBinarySearch(float linear) {
  static const std::array<float, 256> threshold = [] {
    std::array<float, 256> t{};
    t[0] = -1.0f;
    for (int k = 1; k < 256; ++k) t[static_cast<size_t>(k)] = encodeThreshold(k);
    return t;
  }();
  if (!(linear > 0.0f)) return 0;
  if (linear >= 1.0f) return 255;
  size_t k = 0;
  for (size_t step = 128; step > 0; step >>= 1)
    if (linear >= threshold[k + step]) k += step;
  return static_cast<uint8_t>(k);
}

TEST(Srgb, EncodeEqualsTheBinarySearchOverTheThresholds) {
  // Every 13th float in [0, 1] (all exponents, every bucket, mantissas of every residue), and every
  // float within 4096 ulps of each code's threshold, where the bucket table's step decides.
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  size_t checked = 0;
  for (uint32_t bits = 0; bits <= one + 13; bits += 13, ++checked)
    ASSERT_EQ(linearToSrgb(std::bit_cast<float>(bits)), linearToSrgbBinarySearch(std::bit_cast<float>(bits)))
        << std::bit_cast<float>(bits);
  for (int k = 1; k < 256; ++k) {
    const uint32_t mid = std::bit_cast<uint32_t>(encodeThreshold(k));
    for (uint32_t bits = mid - 4096; bits <= mid + 4096; ++bits, ++checked)
      ASSERT_EQ(linearToSrgb(std::bit_cast<float>(bits)), linearToSrgbBinarySearch(std::bit_cast<float>(bits)))
          << std::bit_cast<float>(bits);
  }
  EXPECT_GT(checked, size_t{80'000'000});
  for (float v : {-0.0f, 1e-30f, 1.2e-4f, 0.00015f, 0.0031308f, 0.999f, 0.99999994f, 1.0f, 2.0f})
    EXPECT_EQ(linearToSrgb(v), linearToSrgbBinarySearch(v)) << v;
}

TEST(Mips, SizesHalveDownToOneByOne) {
  Texture t = makeTexture(8, 4, hashTexel);
  buildMips(t);
  ASSERT_EQ(t.mips.size(), 4u);
  const int expected[4][2] = {{8, 4}, {4, 2}, {2, 1}, {1, 1}};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(t.mips[i].width(), expected[i][0]);
    EXPECT_EQ(t.mips[i].height(), expected[i][1]);
  }
  Texture odd = makeTexture(5, 3, hashTexel);
  buildMips(odd);
  ASSERT_EQ(odd.mips.size(), 3u);  // 5x3, 2x1, 1x1
  EXPECT_EQ(odd.mips[1].width(), 2);
  EXPECT_EQ(odd.mips[1].height(), 1);
  // Building twice replaces the chain rather than appending to it.
  buildMips(odd);
  EXPECT_EQ(odd.mips.size(), 3u);
  Texture one = makeTexture(1, 1, hashTexel);
  buildMips(one);
  EXPECT_EQ(one.mips.size(), 1u);
}

TEST(Mips, ConstantImageStaysConstantAtEveryLevel) {
  for (auto [w, h] : {std::pair{16, 16}, std::pair{7, 5}, std::pair{1, 9}, std::pair{13, 2}}) {
    Texture t = makeTexture(w, h, [](int, int) { return Rgba8{200, 100, 3, 77}; });
    buildMips(t);
    for (const ImageRgba8& level : t.mips)
      for (int y = 0; y < level.height(); ++y)
        for (int x = 0; x < level.width(); ++x) ASSERT_EQ(level.at(x, y), (Rgba8{200, 100, 3, 77}));
  }
}

TEST(Mips, AverageInLinearSpaceAlphaAsStored) {
  // Black and white average to linear 0.5, which is sRGB 188, not 128.
  Texture t = makeTexture(2, 1, [](int x, int) { return x == 0 ? Rgba8{0, 0, 0, 0} : Rgba8{255, 255, 255, 255}; });
  buildMips(t);
  ASSERT_EQ(t.mips.size(), 2u);
  EXPECT_EQ(t.mips[1].at(0, 0), (Rgba8{188, 188, 188, 128}));
}

TEST(Mips, OddSizesWeighTexelsByTheAreaTheyCover) {
  // 3 -> 1 texel: the footprint covers all three texels fully, a third each.
  Texture t = makeTexture(3, 1, [](int x, int) { return Rgba8{0, 0, 0, static_cast<uint8_t>(x == 1 ? 255 : 0)}; });
  buildMips(t);
  ASSERT_EQ(t.mips.size(), 2u);
  EXPECT_EQ(t.mips[1].at(0, 0).a, 85);
  // 5 -> 2 texels: texel 0 covers [0, 2.5): weights 0.4, 0.4, 0.2 for texels 0, 1, 2.
  Texture u = makeTexture(5, 1, [](int x, int) { return Rgba8{0, 0, 0, static_cast<uint8_t>(x == 2 ? 250 : 0)}; });
  buildMips(u);
  EXPECT_EQ(u.mips[1].at(0, 0).a, 50);
  EXPECT_EQ(u.mips[1].at(1, 0).a, 50);
}

TEST(Sample, TexelCentersReturnTexelValues) {
  Texture t = makeTexture(4, 3, hashTexel);
  buildMips(t);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      const glm::vec2 uv((static_cast<float>(x) + 0.5f) / 4.0f, (static_cast<float>(y) + 0.5f) / 3.0f);
      expectNear(sampleBilinear(t, uv, 0.0f), decoded(hashTexel(x, y)));
    }
}

TEST(Sample, InterpolatesDecodedValuesBetweenCenters) {
  Texture t = makeTexture(4, 3, hashTexel);
  const glm::vec4 a = decoded(hashTexel(1, 2)), b = decoded(hashTexel(2, 2));
  expectNear(sampleBilinear(t, {2.0f / 4.0f, 2.5f / 3.0f}, 0.0f), (a + b) * 0.5f);
  expectNear(sampleBilinear(t, {1.75f / 4.0f, 2.5f / 3.0f}, 0.0f), a * 0.75f + b * 0.25f);
}

TEST(Sample, WrapsWithRepeat) {
  Texture t = makeTexture(4, 3, hashTexel);
  buildMips(t);
  const glm::vec2 uv(0.3f, 0.7f);
  for (glm::vec2 shift : {glm::vec2(1.0f, 0.0f), glm::vec2(-3.0f, 2.0f), glm::vec2(12.0f, -7.0f)})
    expectNear(sampleBilinear(t, uv + shift, 0.0f), sampleBilinear(t, uv, 0.0f), 2e-5f);
  // u = 0 lies halfway between the centers of the last and the first column.
  const glm::vec4 edge = sampleBilinear(t, {0.0f, 0.5f / 3.0f}, 0.0f);
  expectNear(edge, (decoded(hashTexel(3, 0)) + decoded(hashTexel(0, 0))) * 0.5f);
}

TEST(Sample, RepeatWrapEqualsTheFloorFormulaBitForBit) {
  // The lookup wraps texel indices with integer remainders below 2^30: the same bits as the double
  // formula i - n * floor(i / n) it replaced, which this reference keeps, at any distance.
  Texture t = makeTexture(5, 3, hashTexel);
  auto reference = [&](glm::vec2 uv) {
    const int w = 5, h = 3;
    const double x = static_cast<double>(uv.x) * w - 0.5, y = static_cast<double>(uv.y) * h - 0.5;
    const double xf = std::floor(x), yf = std::floor(y);
    const float fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf);
    auto wrap = [](double i, int n) {
      const int k = static_cast<int>(i - n * std::floor(i / n));
      return k >= n ? 0 : k;
    };
    const int x0 = wrap(xf, w), y0 = wrap(yf, h), x1 = (x0 + 1) % w, y1 = (y0 + 1) % h;
    auto texel = [](int i, int j) {  // decoded as the lookup does: alpha times 1 / 255
      const Rgba8 c = hashTexel(i, j);
      return glm::vec4(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b), c.a * (1.0f / 255.0f));
    };
    const glm::vec4 t00 = texel(x0, y0), t10 = texel(x1, y0), t01 = texel(x0, y1), t11 = texel(x1, y1);
    const glm::vec4 top = t00 + (t10 - t00) * fx, bottom = t01 + (t11 - t01) * fx;
    return top + (bottom - top) * fy;
  };
  int checked = 0;
  for (float base : {0.0f, 1.0f, -1.0f, 2.0f, -7.0f, 1e3f, -4.5e4f, 2.1e8f, -2.2e8f, 3e9f, -1e12f})
    for (float frac : {0.0f, 0.05f, 0.1f, 0.5f, 0.77f, 0.9999f})
      for (float v : {-2.6f, 0.4f, 0.99f, 31.2f}) {
        const glm::vec2 uv(base + frac, v + frac);
        const glm::vec4 got = sampleBilinear(t, uv, 0.0f), want = reference(uv);
        for (int c = 0; c < 4; ++c)
          ASSERT_EQ(std::bit_cast<uint32_t>(got[c]), std::bit_cast<uint32_t>(want[c])) << uv.x << "," << uv.y << " channel " << c;
        ++checked;
      }
  EXPECT_EQ(checked, 264);
}

TEST(Sample, BlendsLevelsLinearlyAndClampsLod) {
  Texture t = makeTexture(2, 2, hashTexel);
  buildMips(t);
  ASSERT_EQ(t.mips.size(), 2u);
  const glm::vec2 uv(0.25f, 0.25f);
  const glm::vec4 l0 = sampleBilinear(t, uv, 0.0f), l1 = decoded(t.mips[1].at(0, 0));
  expectNear(sampleBilinear(t, uv, 1.0f), l1);
  expectNear(sampleBilinear(t, uv, 0.25f), l0 * 0.75f + l1 * 0.25f);
  expectNear(sampleBilinear(t, uv, 40.0f), l1);
  expectNear(sampleBilinear(t, uv, -3.0f), l0);
  expectNear(sampleBilinear(t, uv, std::numeric_limits<float>::quiet_NaN()), l0);
}

TEST(Sample, SurvivesDegenerateInput) {
  const Texture empty;
  expectNear(sampleBilinear(empty, {0.5f, 0.5f}, 0.0f), glm::vec4(1.0f));
  Texture t = makeTexture(3, 3, hashTexel);
  const float inf = std::numeric_limits<float>::infinity();
  const glm::vec4 v = sampleBilinear(t, {inf, -inf}, 0.0f);
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(std::isfinite(v[c]));
  const glm::vec4 far = sampleBilinear(t, {1e30f, -3e29f}, 0.0f);
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(std::isfinite(far[c]));
}

}  // namespace
}  // namespace penumbra::engine
