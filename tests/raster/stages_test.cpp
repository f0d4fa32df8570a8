// The pipeline's stages driven one at a time: the tile grid, binning against a brute-force
// reference, assembly's counters and clipping, the whole front end and tile stage run by hand
// equal to Rasterizer::drawDepth, and fragments told their tile.
#include <gtest/gtest.h>

#include <random>

#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

TEST(TileGrid, TilesCoverTheTargetOnceAndTileOfAgreesWithRect) {
  for (const auto& [w, h, l2] : {std::tuple{301, 203, 6}, std::tuple{64, 64, 6}, std::tuple{1, 1, 3}, std::tuple{97, 33, 4}}) {
    const TileGrid g(w, h, l2);
    std::vector<int> owner(static_cast<size_t>(w) * static_cast<size_t>(h), -1);
    for (uint32_t t = 0; t < g.count(); ++t) {
      const PixelRect r = g.rect(t);
      ASSERT_FALSE(r.empty());
      for (int y = r.y0; y <= r.y1; ++y)
        for (int x = r.x0; x <= r.x1; ++x) {
          int& o = owner[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)];
          EXPECT_EQ(o, -1) << "pixel in two tiles";
          o = static_cast<int>(t);
          EXPECT_EQ(g.tileOf(x, y), t);
        }
    }
    for (int o : owner) EXPECT_GE(o, 0) << "pixel in no tile";
  }
}

TEST(BinRects, EveryTileListsTheRectsThatReachItInOrder) {
  const TileGrid g(301, 203, 5);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ux(0, 300), uy(0, 202), big(0, 3);
  std::vector<PixelRect> rects;
  for (int i = 0; i < 500; ++i) {
    int x0 = ux(rng), y0 = uy(rng), x1 = x0 + big(rng) * ux(rng) / 8, y1 = y0 + big(rng) * uy(rng) / 8;
    x1 = std::min(x1, 300), y1 = std::min(y1, 202);
    rects.push_back(i % 17 == 0 ? PixelRect{} : PixelRect{x0, y0, x1, y1});  // some empty
  }
  TileBins bins;
  binRects(g, static_cast<uint32_t>(rects.size()), [&](uint32_t i) { return rects[i]; }, bins);
  uint64_t total = 0;
  for (uint32_t t = 0; t < g.count(); ++t) {
    std::vector<uint32_t> want;
    for (uint32_t i = 0; i < rects.size(); ++i)
      if (!intersect(rects[i], g.rect(t)).empty()) want.push_back(i);
    const std::span<const uint32_t> got = bins.tile(t);
    EXPECT_EQ(std::vector<uint32_t>(got.begin(), got.end()), want) << "tile " << t;
    total += want.size();
  }
  EXPECT_EQ(bins.entries.size(), total);
}

constexpr int kW = 160, kH = 96;

std::vector<glm::vec4> someTriangles(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::vec4> v;
  for (int t = 0; t < n; ++t) {
    const double cx = u(rng) * kW, cy = u(rng) * kH, size = 2.0 + 50.0 * u(rng);
    for (int k = 0; k < 3; ++k)
      v.push_back(test::clipFromScreen(cx + (u(rng) - 0.5) * size, cy + (u(rng) - 0.5) * size, u(rng), 0.5 + u(rng), kW, kH));
  }
  return v;
}

TEST(Assemble, CountsEveryOutcomeAndClipsAcrossTheNearPlane) {
  const Viewport vp{kW, kH};
  const GuardPlanes guard = guardPlanes(vp);
  std::vector<glm::vec4> clip = {
      test::clipFromScreen(10, 10, 0.5, 1, kW, kH), test::clipFromScreen(40, 10, 0.5, 1, kW, kH),
      test::clipFromScreen(10, 40, 0.5, 1, kW, kH),  // 0: drawn as it is
      {-5, 0, 0.5f, 1}, {-4, 0, 0.5f, 1}, {-5, 1, 0.5f, 1},  // 1: left of the frustum
      {0, 0, -1, 1}, {0.5f, 0, 0.5f, 1}, {0, 0.5f, 0.5f, 1},  // 2: crosses the near plane
      {NAN, 0, 0.5f, 1}, {0, 0, 0.5f, 1}, {0, 1, 0.5f, 1},   // 3: non-finite
  };
  std::vector<ScreenVert> screen;
  for (const glm::vec4& c : clip) screen.push_back(projectVertex(c.x, c.y, c.z, c.w, vp, guard));
  std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0, 1, 99};  // 4: index out of range
  AssembledChunk out;
  assembleTriangles({clip, screen, nullptr, 0}, idx, static_cast<uint32_t>(clip.size()), CullMode::None, vp, true, 0,
                    5, out);
  EXPECT_EQ(out.stats.trianglesIn, 5u);
  EXPECT_EQ(out.stats.trianglesCulledFrustum, 1u);
  EXPECT_EQ(out.stats.trianglesDroppedInvalid, 2u);
  EXPECT_EQ(out.stats.trianglesClipped, 1u);
  ASSERT_GE(out.stats.trianglesFromClipping, 1u);
  ASSERT_EQ(out.tris.size(), 1 + out.stats.trianglesFromClipping);
  ASSERT_EQ(out.attrs.size(), out.tris.size());
  // The direct triangle is exactly what setup makes of it; the clipped pieces keep primitive 2,
  // carry chunk-local varyings and lie in front of the near plane.
  SetupTri t;
  int order[3];
  ASSERT_EQ(setupTriangle(screen[0], screen[1], screen[2], CullMode::None, vp, t, nullptr, order), SetupResult::Ok);
  t.primitive = 0;
  EXPECT_EQ(std::memcmp(&t, &out.tris[0], sizeof t), 0);
  EXPECT_FALSE(out.attrs[0].clipped);
  for (size_t i = 1; i < out.tris.size(); ++i) {
    EXPECT_EQ(out.tris[i].primitive, 2u);
    EXPECT_TRUE(out.attrs[i].clipped);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(out.attrs[i].vary[k] & kChunkLocalVarying);
    EXPECT_GE(out.tris[i].zmin, 0.0f);
  }
  EXPECT_FALSE(out.clipVary.empty());
}

// vertex -> assemble -> bin -> tile, by hand, gives the depth that drawDepth gives.
TEST(Stages, DrivenOneAtATimeEqualTheRasterizer) {
  std::mt19937 rng(3);
  const std::vector<glm::vec4> clip = someTriangles(rng, 300);
  std::vector<uint32_t> idx(clip.size());
  for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  Rasterizer r({.threads = 2, .tileLog2 = 5});
  DepthTarget want(kW, kH, 1.0f);
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(clip.size());
  d.indices = idx;
  r.drawDepth(d, want, [&](uint32_t i) { return clip[i]; });

  const Viewport vp{kW, kH};
  const GuardPlanes guard = guardPlanes(vp);
  std::vector<ScreenVert> screen;
  for (const glm::vec4& c : clip) screen.push_back(projectVertex(c.x, c.y, c.z, c.w, vp, guard));
  // Two chunks, binned separately, read in order by each tile.
  const TileGrid grid = r.tileGrid(kW, kH);
  AssembledChunk chunks[2];
  TileBins bins[2];
  const uint64_t tris = idx.size() / 3, half = tris / 2;
  for (int c = 0; c < 2; ++c) {
    assembleTriangles({clip, screen, nullptr, 0}, idx, d.vertexCount, CullMode::None, vp, false, c ? half : 0,
                      c ? tris : half, chunks[c]);
    binRects(grid, static_cast<uint32_t>(chunks[c].tris.size()), [&](uint32_t i) {
      const SetupTri& t = chunks[c].tris[i];
      return PixelRect{t.minX, t.minY, t.maxX, t.maxY};
    }, bins[c]);
  }
  DepthTarget got(kW, kH, 1.0f);
  PassStats st;
  for (uint32_t t = 0; t < grid.count(); ++t) {
    std::vector<const SetupTri*> list;
    for (int c = 0; c < 2; ++c)
      for (uint32_t e : bins[c].tile(t)) list.push_back(&chunks[c].tris[e]);
    const PixelRect rect = grid.rect(t);
    TileJob job;
    job.x0 = rect.x0, job.y0 = rect.y0, job.x1 = rect.x1 + 1, job.y1 = rect.y1 + 1;
    job.width = kW, job.height = kH;
    job.depth = got.image().data();
    job.depthStride = got.image().stride();
    job.blockMin = got.blockMin(), job.blockMax = got.blockMax(), job.blocksX = got.blocksX();
    job.tris = list.data();
    job.count = static_cast<uint32_t>(list.size());
    rasterizeTile(job, st);
  }
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) ASSERT_EQ(got.at(x, y), want.at(x, y)) << x << ", " << y;
}

TEST(Fragment, KnowsItsTile) {
  std::mt19937 rng(5);
  const std::vector<glm::vec4> clip = someTriangles(rng, 200);
  Rasterizer r({.threads = 2, .tileLog2 = 4});
  const TileGrid grid = r.tileGrid(kW, kH);
  DepthTarget depth(kW, kH, 1.0f);
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(clip.size());
  d.depthFunc = DepthFunc::Always;
  std::atomic<uint64_t> fragments{0}, wrong{0};
  r.draw(d, depth, [&](uint32_t i, float*) { return clip[i]; },
         [&](const Fragment& f) {
           ++fragments;
           if (f.tile != grid.tileOf(f.x, f.y)) ++wrong;
         });
  EXPECT_GT(fragments.load(), 1000u);
  EXPECT_EQ(wrong.load(), 0u);
}

}  // namespace
}  // namespace penumbra::raster
