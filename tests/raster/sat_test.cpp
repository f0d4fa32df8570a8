// Multi-channel summed-area tables, the SAT tile grid and four-channel mips against brute force:
// box queries at fractional coordinates are the exact area-weighted integral of the texels.
#include "raster/sat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

namespace penumbra::raster {
namespace {

Planes<float> randomPlanes(int w, int h, int ch, uint32_t seed, float scale = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, scale);
  Planes<float> p(w, h, ch);
  for (float& v : p.data) v = u(rng);
  return p;
}

// Area-weighted integral over [x0, x1) x [y0, y1), clamped, texel by texel in long double.
long double bruteBox(const Planes<float>& p, int c, double x0, double y0, double x1, double y1) {
  long double s = 0;
  for (int y = 0; y < p.height; ++y) {
    const double wy = std::max(0.0, std::min(y1, y + 1.0) - std::max(y0, static_cast<double>(y)));
    if (wy <= 0) continue;
    for (int x = 0; x < p.width; ++x) {
      const double wx = std::max(0.0, std::min(x1, x + 1.0) - std::max(x0, static_cast<double>(x)));
      if (wx > 0) s += static_cast<long double>(wx * wy) * p.pixel(x, y)[c];
    }
  }
  return s;
}

struct Box {
  double x0, y0, x1, y1;
};
std::vector<Box> boxes(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Box> out = {{0, 0, static_cast<double>(w), static_cast<double>(h)},  // whole image
                          {2.25, 3.5, 2.75, 3.9},                                  // inside one texel
                          {-5, -5, 1.5, 0.5},                                      // clamped
                          {4, 4, 9, 6},                                            // integer corners
                          {5.5, 2.0, 5.5, 9.0},                                    // empty
                          {static_cast<double>(w) - 0.3, 1.0, static_cast<double>(w) + 4, 7.25}};
  for (int i = 0; i < 40; ++i) {
    const double x0 = u(rng) + w * 0.5, y0 = u(rng) + h * 0.5;
    out.push_back({x0, y0, x0 + std::abs(u(rng)) * w / 4, y0 + std::abs(u(rng)) * h / 4});
  }
  return out;
}

// Sub-box (i, j) of b split into n x n equal parts.
Box subBox(const Box& b, int n, int i, int j) {
  return {b.x0 + (b.x1 - b.x0) * i / n, b.y0 + (b.y1 - b.y0) * j / n, b.x0 + (b.x1 - b.x0) * (i + 1) / n,
          b.y0 + (b.y1 - b.y0) * (j + 1) / n};
}

TEST(Sat, BoxSumsAreTheAreaWeightedIntegralInEveryPrecision) {
  const Planes<float> p = randomPlanes(37, 23, 3, 7);
  const MultiSat<double> d = buildSatDouble(p);
  const MultiSat<float> f = buildSatFloat(p);
  for (const Box& b : boxes(37, 23, 11)) {
    double od[3], of[3];
    const double area = d.boxSum(b.x0, b.y0, b.x1, b.y1, od);
    f.boxSum(b.x0, b.y0, b.x1, b.y1, of);
    const double ca = std::max(0.0, std::min(b.x1, 37.0) - std::max(b.x0, 0.0)) *
                      std::max(0.0, std::min(b.y1, 23.0) - std::max(b.y0, 0.0));
    EXPECT_NEAR(area, b.x1 > b.x0 && b.y1 > b.y0 ? ca : 0.0, 1e-12);
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(bruteBox(p, c, b.x0, b.y0, b.x1, b.y1));
      EXPECT_NEAR(od[c], e, 1e-11 * (1.0 + e)) << b.x0 << " " << b.y0 << " " << b.x1 << " " << b.y1;
      EXPECT_NEAR(of[c], e, 2e-3 * (1.0 + e));
    }
  }
}

TEST(Sat, IntegerTableIsExactAndGridSumsMatchSeparateQueries) {
  const Planes<float> p = randomPlanes(50, 41, 2, 3);
  const Planes<uint32_t> q = quantizePlanes(p, {0.0, 0.0}, {1.0, 1.0}, 24);
  const MultiSat<uint64_t> t = buildSatInteger(q);
  // The integer-rectangle query is exact.
  for (const Box& b : boxes(50, 41, 5)) {
    const int x0 = static_cast<int>(std::floor(b.x0)), y0 = static_cast<int>(std::floor(b.y0));
    const int x1 = static_cast<int>(std::floor(b.x1)), y1 = static_cast<int>(std::floor(b.y1));
    double o[2];
    t.boxSum(x0, y0, x1, y1, o);
    for (int c = 0; c < 2; ++c) {
      uint64_t e = 0;
      for (int y = std::max(y0, 0); y < std::min(y1, 41); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, 50); ++x) e += q.pixel(x, y)[c];
      EXPECT_EQ(static_cast<uint64_t>(o[c]), e);
    }
  }
  // Sub-box grids equal n x n separate queries (to rounding relative to the whole box).
  for (int n : {1, 3, 5}) {
    for (const Box& b : boxes(50, 41, 9)) {
      std::vector<double> g(static_cast<size_t>(n * n * 2)), area(static_cast<size_t>(n * n));
      t.gridSums(b.x0, b.y0, b.x1, b.y1, n, g.data(), area.data());
      double whole[2];
      t.boxSum(b.x0, b.y0, b.x1, b.y1, whole);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Box sb = subBox(b, n, i, j);
          double o[2];
          const double a = t.boxSum(sb.x0, sb.y0, sb.x1, sb.y1, o);
          EXPECT_NEAR(area[static_cast<size_t>(j * n + i)], a, 1e-9);
          for (int c = 0; c < 2; ++c)
            EXPECT_NEAR(g[static_cast<size_t>((j * n + i) * 2 + c)], o[c], 1e-12 * (1.0 + whole[c])) << n;
        }
    }
  }
}

TEST(Sat, FloatLosesWhatIntegerAndTiledKeepAt4096) {
  // A bright image with one dim corner far from the origin: the float table's entries there hold
  // ~1.6e7 and a one-texel box keeps no digits; the integer and tiled ones keep their bound.
  const int n = 4096;
  Planes<float> p(n, n, 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      p.pixel(x, y)[0] = (x >= n - 64 && y >= n - 64) ? 1e-3f * static_cast<float>((x + y) % 7) : 1.0f;
  const MultiSat<float> f = buildSatFloat(p);
  const TiledSat tiled = buildTiledSat(p, 20);
  ASSERT_EQ(tiled.tile, 64);
  double worstFloat = 0, worstTiled = 0;
  for (int k = 0; k < 50; ++k) {
    const double x = n - 60 + k % 50, y = n - 60 + (k * 7) % 50;
    const double e = static_cast<double>(bruteBox(p, 0, x, y, x + 1.5, y + 1.25));
    double of, ot;
    f.boxSum(x, y, x + 1.5, y + 1.25, &of);
    tiled.boxSum(x, y, x + 1.5, y + 1.25, &ot);
    worstFloat = std::max(worstFloat, std::abs(of - e));
    worstTiled = std::max(worstTiled, std::abs(ot - e));
  }
  // The tile holds values in [0, 6e-3]: half a step of 6e-3 / (2^20 - 1) per texel, 1.875 texels.
  EXPECT_LE(worstTiled, 1.875 * 0.5 * 6e-3 / ((1 << 20) - 1) + 1e-15);
  EXPECT_GT(worstFloat, 1e-3);  // the float table's error is the size of the values themselves
}

TEST(Sat, TiledQueriesSplitAtTileBordersAndSkippedTilesAreNeverRead) {
  const Planes<float> p = randomPlanes(300, 170, 3, 21, 50.0f);
  for (int bits : {24, 20, 16}) {
    const TiledSat t = buildTiledSat(p, bits);
    EXPECT_EQ(t.tile, 1 << ((32 - bits) / 2));
    for (const Box& b : boxes(300, 170, 13)) {
      double o[3];
      const double area = t.boxSum(b.x0, b.y0, b.x1, b.y1, o);
      for (int c = 0; c < 3; ++c) {
        const double e = static_cast<double>(bruteBox(p, c, b.x0, b.y0, b.x1, b.y1));
        // At most half a step of the widest tile range (50) per unit of area.
        EXPECT_NEAR(o[c], e, area * 0.5 * 50.0 / ((1u << bits) - 1) + 1e-9) << bits;
      }
    }
  }
  // Grids of sub-boxes equal n x n separate queries, bounds included, across tile borders.
  {
    const TiledSat t = buildTiledSat(p, 24);  // 16-texel tiles: most boxes cross several
    for (int n : {1, 3, 4}) {
      for (const Box& b : boxes(300, 170, 17)) {
        std::vector<double> g(static_cast<size_t>(n * n * 3)), area(static_cast<size_t>(n * n)),
            bound(static_cast<size_t>(n * n * 3));
        t.gridSums(b.x0, b.y0, b.x1, b.y1, n, g.data(), area.data(), bound.data());
        double whole[3];
        t.boxSum(b.x0, b.y0, b.x1, b.y1, whole);
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const Box sb = subBox(b, n, i, j);
            double o[3], ob[3];
            const double a = t.boxSum(sb.x0, sb.y0, sb.x1, sb.y1, o, ob);
            const auto k = static_cast<size_t>(j * n + i);
            EXPECT_NEAR(area[k], a, 1e-9);
            for (int c = 0; c < 3; ++c) {
              EXPECT_NEAR(g[k * 3 + static_cast<size_t>(c)], o[c], 1e-12 * (1.0 + std::abs(whole[c]))) << n;
              EXPECT_NEAR(bound[k * 3 + static_cast<size_t>(c)], ob[c], 1e-12 * (1.0 + ob[c])) << n;
            }
          }
      }
    }
  }
  // Only the needed tiles are built; a query inside them is unaffected, one outside reads NaN.
  const int T = stgTileSize(20);
  const int tx = (300 + T - 1) / T, ty = (170 + T - 1) / T;
  std::vector<uint8_t> need(static_cast<size_t>(tx * ty), 0);
  need[0] = 1;
  const TiledSat part = buildTiledSat(p, 20, need), all = buildTiledSat(p, 20);
  EXPECT_EQ(part.tilesBuilt, 1u);
  double a[3], b[3];
  part.boxSum(1.5, 2.5, 40.25, 33.0, a);
  all.boxSum(1.5, 2.5, 40.25, 33.0, b);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], b[c]);
  part.boxSum(60.0, 2.0, 70.0, 3.0, a);
  EXPECT_TRUE(std::isnan(a[0]));
  double g[9 * 3], ga[9];
  part.gridSums(1.5, 2.5, 40.25, 33.0, 3, g, ga);
  double sum[3] = {};
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c) sum[c] += g[k * 3 + c];
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], b[c], 1e-9 * b[c]);
  part.gridSums(30.0, 2.0, 70.0, 3.0, 3, g, ga);
  EXPECT_TRUE(std::isnan(g[0]));
}

TEST(Sat, FourChannelMipsAreMeansAndTrilinearInterpolates) {
  ImageFloat4 img(13, 7);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 13; ++x)
      img.at(x, y) = {static_cast<float>(x), static_cast<float>(y), 1.0f, static_cast<float>(x * y)};
  const std::vector<ImageFloat4> m = mipChain4(img);
  ASSERT_EQ(m.size(), 5u);  // 13x7, 7x4, 4x2, 2x1, 1x1
  EXPECT_FLOAT_EQ(m[1].at(0, 0).r, 0.5f);
  EXPECT_FLOAT_EQ(m[1].at(6, 3).r, 12.0f);  // one child
  EXPECT_FLOAT_EQ(m[1].at(6, 3).g, 6.0f);
  for (const ImageFloat4& l : m) EXPECT_FLOAT_EQ(l.at(0, 0).b, 1.0f);  // constants stay exact
  // Level 0 at a texel centre is the texel; between centres linear (x and y are linear images).
  std::array<double, 4> s = sampleTrilinear(m, 3.5, 2.5, 0.0);
  EXPECT_DOUBLE_EQ(s[0], 3.0);
  s = sampleTrilinear(m, 3.75, 2.5, 0.0);
  EXPECT_DOUBLE_EQ(s[0], 3.25);
  // Halfway between levels 0 and 1: the mean of the two bilinear lookups.
  const std::array<double, 4> l0 = sampleTrilinear(m, 5.0, 3.0, 0.0), l1 = sampleTrilinear(m, 5.0, 3.0, 1.0);
  s = sampleTrilinear(m, 5.0, 3.0, 0.5);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(s[static_cast<size_t>(c)], 0.5 * (l0[c] + l1[c]), 1e-12);
  s = sampleTrilinear(m, 5.0, 3.0, 99.0);  // clamped to the top level
  EXPECT_NEAR(s[2], 1.0, 1e-12);
}

}  // namespace
}  // namespace penumbra::raster
