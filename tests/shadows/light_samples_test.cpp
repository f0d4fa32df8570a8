// The depth tests of MVR and VWSS (shadows/light_samples.h): the SIMD kernel over a row of receivers
// and a group of maps against the plain reference, bit for bit (the counts) on every SIMD target,
// with float maps and depth-bit maps, interleaved subsets, the normal offset, off-map taps, bias
// reaching the receiver (an infinite threshold) and receivers below the horizon or without a test.
#include "shadows/light_samples.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "raster/simd.h"
#include "shadows/area_light.h"
#include "shadows/kernel_taps.h"

namespace penumbra::shadows {
namespace {

struct Rows {
  std::vector<float> x, y, d, invD, bias, nx, ny, nz;
  std::vector<int32_t> subsetOfX;
  int count = 0;

  SampleRow row(int k, int rowY, float normalOffset) const {
    return {x.data(),  y.data(),  d.data(),         invD.data(),    bias.data(), nx.data(),
            ny.data(), nz.data(), subsetOfX.data(), k * (rowY % k), count,       normalOffset};
  }
};

// count receivers (padded to kTapLanes) about 1 to 6 units in front of light-space views near the
// origin: a few with nothing to test (d = -1), normals mostly facing the light (some turned away:
// below the horizon), bias factors up to 40 (with texels near 0.03, beta >= 1 for some: +inf).
Rows randomRows(std::mt19937& rng, int count, int k) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
  Rows r;
  r.count = count;
  const size_t n = static_cast<size_t>((count + kTapLanes - 1) / kTapLanes * kTapLanes);
  for (auto* a : {&r.x, &r.y, &r.invD, &r.bias, &r.nx, &r.ny, &r.nz}) a->assign(n, 0.0f);
  r.d.assign(n, -1.0f);
  for (size_t i = 0; i < n; ++i) r.subsetOfX.push_back(static_cast<int32_t>(i % static_cast<size_t>(k)));
  for (int i = 0; i < count; ++i) {
    const size_t j = static_cast<size_t>(i);
    r.x[j] = 2.0f * s(rng), r.y[j] = 2.0f * s(rng);
    glm::vec3 nrm(0.4f * s(rng), 0.4f * s(rng), -1.0f);
    if (u(rng) < 0.15f) nrm.z = 0.5f;  // turned away from the light
    nrm = glm::normalize(nrm);
    r.nx[j] = nrm.x, r.ny[j] = nrm.y, r.nz[j] = nrm.z;
    if (u(rng) < 0.1f) continue;  // nothing to test
    r.d[j] = 1.0f + 5.0f * u(rng);
    r.invD[j] = 1.0f / r.d[j];
    r.bias[j] = u(rng) < 0.05f ? 40.0f : 0.2f + 2.0f * u(rng);
  }
  return r;
}

// A map of w x h texels over tangents [-0.8, 0.9] x [-0.7, 0.6] from light point lp: stored values
// near / depth for depths around the receivers' (so tests go both ways), a fifth of them 0.
struct Map {
  std::vector<float> texels;
  std::vector<uint32_t> bits;
  SampleLookup lookup;
};
Map randomMap(std::mt19937& rng, bool asBits, int subset) {
  std::uniform_int_distribution<int> size(1, 90);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
  const int w = size(rng), h = size(rng), stride = (w + 7) / 8 * 8;
  Map m;
  LightView v;
  v.tanLo = {-0.8f, -0.7f}, v.tanHi = {0.9f, 0.6f}, v.width = w, v.height = h, v.znear = 0.5f;
  m.texels.resize(static_cast<size_t>(stride) * static_cast<size_t>(h));
  for (float& t : m.texels) t = u(rng) < 0.2f ? 0.0f : v.znear / (1.0f + 5.5f * u(rng));
  for (float t : m.texels) m.bits.push_back(std::bit_cast<uint32_t>(t));
  SampleMap sm;
  sm.view = v;
  sm.stride = stride;
  if (asBits)
    sm.depthBits = m.bits.data();
  else
    sm.depth = m.texels.data();
  sm.lightPoint = {0.3f * s(rng), 0.3f * s(rng)};
  sm.subset = subset;
  // The lookup with ShadowMap::prepareLookup's expressions, as LightSampleTests builds it.
  SampleLookup& l = m.lookup;
  l.data = asBits ? static_cast<const void*>(m.bits.data()) : static_cast<const void*>(m.texels.data());
  l.bits = asBits;
  l.stride = stride;
  l.ax = static_cast<float>(w) / (v.tanHi.x - v.tanLo.x);
  l.bx = -v.tanLo.x * l.ax;
  l.ay = -static_cast<float>(h) / (v.tanHi.y - v.tanLo.y);
  l.by = -v.tanHi.y * l.ay;
  l.maxX = static_cast<float>(w - 1), l.maxY = static_cast<float>(h - 1);
  l.invAx = 1.0f / l.ax, l.invAy = 1.0f / l.ay;
  l.texelTanX = (v.tanHi.x - v.tanLo.x) / static_cast<float>(w);
  l.texelTanY = (v.tanHi.y - v.tanLo.y) / static_cast<float>(h);
  l.texel = v.texelWorld(1.0f);
  l.znear = v.znear;
  l.lpx = sm.lightPoint.x, l.lpy = sm.lightPoint.y;
  l.subset = subset;
  return m;
}

TEST(SampleKernel, EveryTargetCountsLikeTheReference) {
  std::mt19937 rng(11);
  // The texel and its 4 neighbours, and taps far off the map (clamped to its edge).
  const float tapX[] = {0, -1, 1, 0, 0, 400, -3}, tapY[] = {0, 0, 0, -1, 1, -2, 900};
  uint64_t counted = 0, possible = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int k = 1 + trial % 3, y = trial % 5;
    const Rows rows = randomRows(rng, 1 + trial * 7, k);
    std::vector<Map> maps;
    for (int i = 0; i < 1 + trial % 6; ++i)
      maps.push_back(randomMap(rng, (i + trial) % 2 == 1, k > 1 ? i % (k * k) : -1));
    std::vector<SampleLookup> lookups;
    for (const Map& m : maps) lookups.push_back(m.lookup);
    const float offset = trial % 4 == 3 ? 1.5f : 0.0f;
    const int taps = trial % 2 ? 7 : 1;
    const SampleRow row = rows.row(k, y, offset);
    std::vector<uint16_t> want(static_cast<size_t>(rows.count), 3);
    accumulateSampleRowReference(row, lookups, tapX, tapY, taps, want.data());
    for (uint16_t c : want) counted += c - 3u;
    possible += static_cast<uint64_t>(rows.count) * lookups.size() * static_cast<uint64_t>(taps);
    for (int64_t target : raster::supportedSimdTargets()) {
      std::vector<uint16_t> got(static_cast<size_t>(rows.count), 3);
      accumulateSampleRow(row, lookups, tapX, tapY, taps, got.data(), target);
      ASSERT_EQ(got, want) << "trial " << trial << ", " << raster::simdTargetName(target);
    }
  }
  // The cases mix: neither (almost) every tap lit nor none.
  EXPECT_GT(counted, possible / 5);
  EXPECT_LT(counted, possible * 4 / 5);
}

// Poisson-disk light samples (the VWSS paper's): inside the light, no two closer than half the
// spacing sqrt(area / n) (uniform random points come far closer; best-candidate sampling keeps
// 0.58 to 0.95 here), the same on every call, split evenly over interleaved subsets; the Hammersley set is
// what "hammersley" gives.
TEST(LightSamples, PoissonDiskPointsSpreadOverTheLight) {
  RectLight light;
  makeRectLight({0, 4, 0}, {0, -1, 0}, {1, 0, 0}, 3.0f, 1.0f, glm::vec3(1), 1, light);
  for (int n : {8, 64, 512}) {
    const std::vector<glm::vec2> p = poissonDiskPoints(light, n);
    ASSERT_EQ(p.size(), static_cast<size_t>(n));
    EXPECT_EQ(poissonDiskPoints(light, n), p);
    float closest = INFINITY;
    for (size_t i = 0; i < p.size(); ++i) {
      EXPECT_LE(std::abs(p[i].x), 1.5f);
      EXPECT_LE(std::abs(p[i].y), 0.5f);
      for (size_t j = 0; j < i; ++j) closest = std::min(closest, glm::length(p[i] - p[j]));
    }
    const float spacing = std::sqrt(3.0f / static_cast<float>(n));
    std::printf("n %d: closest pair %.3f of the spacing\n", n, static_cast<double>(closest / spacing));
    EXPECT_GT(closest, 0.5f * spacing) << n;
  }
  const LightSampleSet set = lightSamples(light, 37, 2, "poisson");
  EXPECT_EQ(set.k, 2);
  EXPECT_EQ(set.count, (std::vector<int>{10, 9, 9, 9}));
  const LightSampleSet ham = lightSamples(light, 37, 2, "hammersley"),
                       ref = interleavedLightSamples(light, 37, 2);
  EXPECT_EQ(ham.points, ref.points);
  EXPECT_EQ(ham.subset, ref.subset);
}

}  // namespace
}  // namespace penumbra::shadows
