// The stochastic rasterizer's stages on their own: strata membership against their domains, and
// the resolve's grouping, ordering, median sample and merging.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "stochastic/resolve.h"
#include "stochastic/setup.h"

namespace penumbra::stochastic {
namespace {

TEST(Strata, EverySampleLiesInTheDomainOfItsStratum) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> t(0.0f, std::nextafter(1.0f, 0.0f)), l(-1.0f, 1.0f);
  for (const auto& [T, L] : {std::pair{8, 3}, std::pair{1, 1}, std::pair{64, 8}, std::pair{5, 2}}) {
    const Strata s(T, L);
    std::vector<int> hits(static_cast<size_t>(s.count()), 0);
    for (int i = 0; i < 20000; ++i) {
      Sample smp{t(rng), l(rng), l(rng)};
      if (i == 0) smp = {0.0f, -1.0f, -1.0f};
      if (i == 1) smp = {s.tEdge[T / 2], s.lEdge[L / 2], 1.0f};  // on boundaries
      const int si = s.of(smp);
      ASSERT_GE(si, 0);
      ASSERT_LT(si, s.count());
      const Domain d = s.domain(si);
      EXPECT_TRUE(smp.t >= d.t0 && smp.t <= d.t1 && smp.u >= d.u0 && smp.u <= d.u1 && smp.v >= d.v0 && smp.v <= d.v1)
          << "sample " << i << " stratum " << si;
      EXPECT_EQ(s.timeOf(si), std::min(T - 1, static_cast<int>(smp.t * static_cast<float>(T)))) << i;
      ++hits[static_cast<size_t>(si)];
    }
    if (s.count() <= 64) {
      for (int h : hits) EXPECT_GT(h, 0);
    }
  }
}

TEST(Resolve, GroupsBySurfaceLargestFirstWithTheMedianSample) {
  const std::vector<uint32_t> surface = {7, 7, 3, 9, 4, 5};  // triangle -> surface
  // 12 samples: surface 7 (triangles 0, 1) x5, static x3, surface 3 x2, background x2.
  const uint32_t ref[12] = {0, kStaticRef, 1, 2, kNoTriangle, 0, kStaticRef, 1, 2, kNoTriangle, 0, kStaticRef};
  Sample samples[12];
  for (int k = 0; k < 12; ++k) samples[k] = {static_cast<float>(k) / 12.0f, 0.1f * static_cast<float>(k), 0.0f};
  ResolvedPixel p;
  EXPECT_FALSE(resolvePixel(ref, 12, surface, samples, p));
  EXPECT_EQ(p.background, 2);
  ASSERT_EQ(p.layers, 3);
  EXPECT_EQ(p.layer[0].surface, 7u);
  EXPECT_EQ(p.layer[0].count, 5);
  EXPECT_EQ(p.layer[0].sample, 5);  // samples 0, 2, 5, 7, 10: the median is the third
  EXPECT_EQ(p.layer[0].triangle, 0u);
  EXPECT_EQ(p.layer[0].at.t, samples[5].t);
  EXPECT_EQ(p.layer[1].surface, kStaticSurface);
  EXPECT_EQ(p.layer[1].count, 3);
  EXPECT_EQ(p.layer[1].triangle, kNoTriangle);
  EXPECT_EQ(p.layer[2].surface, 3u);
  EXPECT_EQ(p.layer[2].count, 2);
  EXPECT_EQ(p.layer[2].sample, 3);
}

TEST(Resolve, MergesSurfacesBeyondTheLayersIntoTheFirst) {
  const std::vector<uint32_t> surface = {1, 2, 3, 4, 5};
  const uint32_t ref[8] = {0, 0, 0, 1, 1, 2, 3, 4};
  ResolvedPixel p;
  EXPECT_TRUE(resolvePixel(ref, 8, surface, nullptr, p));
  ASSERT_EQ(p.layers, kMaxLayers);
  int total = p.background;
  for (int l = 0; l < p.layers; ++l) total += p.layer[l].count;
  EXPECT_EQ(total, 8);
  EXPECT_EQ(p.layer[0].count, 3 + 2);  // surfaces 4 and 5 (one sample each) go to layer 0
  // Ties in count: the smaller surface id first.
  EXPECT_EQ(p.layer[1].surface, 2u);
  EXPECT_EQ(p.layer[2].surface, 3u);
}

TEST(Resolve, AnUntouchedPixelMatchesTheFullResolve) {
  for (bool covered : {false, true})
    for (int spp : {1, 4, 16, 64}) {
      std::vector<uint32_t> ref(static_cast<size_t>(spp), covered ? kStaticRef : kNoTriangle);
      ResolvedPixel full;
      resolvePixel(ref.data(), spp, {}, nullptr, full);
      const ResolvedPixel quick = resolveUntouched(covered, spp);
      EXPECT_EQ(quick.background, full.background);
      ASSERT_EQ(quick.layers, full.layers);
      for (int l = 0; l < full.layers; ++l) {
        EXPECT_EQ(quick.layer[l].surface, full.layer[l].surface);
        EXPECT_EQ(quick.layer[l].count, full.layer[l].count);
        EXPECT_EQ(quick.layer[l].sample, full.layer[l].sample);
        EXPECT_EQ(quick.layer[l].triangle, full.layer[l].triangle);
      }
    }
}

}  // namespace
}  // namespace penumbra::stochastic
