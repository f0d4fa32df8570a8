// The pipeline's stages driven one at a time: the tile grid, binning against a brute-force
// reference, assembly's counters and clipping, the whole front end and tile stage run by hand
// equal to Rasterizer::drawDepth, and fragments told their tile.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>

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

// Projection in lanes equals projectVertex bit for bit on every SIMD target: flags (frustum,
// guard band, non-finite), snapped positions (rounding ties included: positions with few mantissa
// bits land on half subpixels), z / w and 1 / w, for any count (partial last vectors).
TEST(ProjectVertices, EqualProjectVertexBitForBitOnEveryTarget) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float specials[] = {NAN, INFINITY, -INFINITY, 0.0f, -0.0f, 1e-30f, -1e30f};
  const Viewport vps[] = {{kW, kH}, {2048, 2048}, {1, 1}, {kW, kH, 16, -48}};
  std::vector<float> clip;
  auto coordinate = [&](float w, int kind) {
    switch (kind) {
      case 0: return u(rng) * w * 1.2f;                                              // on screen, or just off
      case 1: return static_cast<float>(static_cast<int>(rng() % 8193) - 4096) / 4096.0f * w;  // half subpixels
      case 2: return u(rng) * w * 5000.0f;                                           // near the guard band
      default: return specials[rng() % 7];
    }
  };
  for (int i = 0; i < 20000; ++i) {
    const float w = rng() % 16 == 0 ? specials[rng() % 7] * (rng() % 2 ? 1.0f : -1.0f)
                                    : (rng() % 4 == 0 ? static_cast<float>(1 << (rng() % 3)) : 0.01f + 50.0f * (u(rng) + 1.0f));
    const int kind = rng() % 32 == 0 ? 3 : static_cast<int>(rng() % 3);
    clip.push_back(coordinate(w, kind));
    clip.push_back(coordinate(w, kind));
    clip.push_back(rng() % 8 == 0 ? specials[rng() % 7] : (u(rng) + 0.3f) * w);
    clip.push_back(w);
  }
  const size_t total = clip.size() / 4;
  size_t outside = 0, nonFinite = 0, guardOut = 0;
  for (int64_t target : supportedSimdTargets()) {
    for (const Viewport& vp : vps) {
      const GuardPlanes guard = guardPlanes(vp);
      std::vector<ScreenVert> got(total);
      uint64_t bad = 0;
      for (size_t first = 0, n = 1; first < total; first += n, n = n % 37 + 1)
        bad += projectVertices(clip.data() + 4 * first, std::min(n, total - first), vp, guard, got.data() + first, target);
      uint64_t wantBad = 0;
      for (size_t i = 0; i < total; ++i) {
        const float* c = clip.data() + 4 * i;
        const ScreenVert want = projectVertex(c[0], c[1], c[2], c[3], vp, guard);
        wantBad += (want.flags & kNonFinite) ? 1 : 0;
        outside += (want.flags & kFrustumMask) ? 1 : 0;
        nonFinite += (want.flags & kNonFinite) ? 1 : 0;
        guardOut += (want.flags & kOutGuard) ? 1 : 0;
        ASSERT_EQ(std::memcmp(&want, &got[i], sizeof want), 0)
            << simdTargetName(target) << " vertex " << i << ": " << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3]
            << " want " << want.x << ", " << want.y << ", " << want.flags << " got " << got[i].x << ", " << got[i].y << ", "
            << got[i].flags;
      }
      ASSERT_EQ(bad, wantBad) << simdTargetName(target);
    }
  }
  EXPECT_GT(outside, 1000u);
  EXPECT_GT(nonFinite, 1000u);
  EXPECT_GT(guardOut, 1000u);
}

// Setup in lanes makes setupTriangle's records bit for bit, on every SIMD target: verdicts, vertex
// order, bounding boxes, planes and depth ranges, for triangles from a few subpixels to the guard
// band, on and off the pixel grid (edges through pixel centres, planes whose origin lies on an
// edge), degenerate ones, depths of +0 and -0 and equal depths, each cull mode, with and without
// the attribute planes.
TEST(SetupLanes, EqualSetupTriangleBitForBitOnEveryTarget) {
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int32_t> anywhere(-(1 << 23), 1 << 23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const Viewport vps[] = {{kW, kH}, {2048, 2048}, {1, 1}, {kW, kH, 16, -48}};
  const float depths[] = {0.0f, -0.0f, 0.5f, -0.25f};  // negative: not from the pipeline, but exact too
  auto coordinate = [&](int kind, int32_t base, int extent) -> int32_t {
    const int32_t off = static_cast<int32_t>(rng() % static_cast<uint64_t>(2 * extent + 1)) - extent;
    switch (kind) {
      case 0: return base + off;                      // anywhere near the base
      case 1: return (base + off) & ~(kSubpixelOne - 1);  // on the pixel grid
      default: return anywhere(rng);                  // anywhere in the guard band
    }
  };
  auto depth = [&] { return rng() % 2 == 0 ? depths[rng() % 4] : unit(rng); };
  uint64_t counts[4] = {0, 0, 0, 0};
  for (int64_t target : supportedSimdTargets()) {
    rng.seed(17);
    for (int g = 0; g < 4000; ++g) {
      const Viewport& vp = vps[g % 4];
      const CullMode cull = static_cast<CullMode>(g % 3);
      const bool attrs = (g / 3) % 2 == 0;
      const int n = 1 + static_cast<int>(rng() % kSetupGroup);
      SetupGroupIn in{};
      ScreenVert v[kSetupGroup][3];
      for (int l = 0; l < n; ++l) {
        const int kind = static_cast<int>(rng() % 3);
        const int extent = rng() % 2 ? 3 * kSubpixelOne : 40 * kSubpixelOne;
        const int32_t bx = static_cast<int32_t>(rng() % static_cast<uint64_t>(vp.width + 2) * kSubpixelOne) - kSubpixelOne;
        const int32_t by = static_cast<int32_t>(rng() % static_cast<uint64_t>(vp.height + 2) * kSubpixelOne) - kSubpixelOne;
        for (int k = 0; k < 3; ++k) {
          v[l][k].x = coordinate(kind, bx, extent);
          v[l][k].y = coordinate(kind, by, extent);
          v[l][k].z = depth();
          v[l][k].iw = rng() % 4 == 0 ? 1.0f : rng() % 16 == 0 ? 3e38f : 0.1f + 10.0f * unit(rng);  // 3e38: planes overflow
        }
        if (rng() % 4 == 0) {  // a right triangle on the pixel grid, its corner on a pixel centre
          const int32_t cx = bx & ~(kSubpixelOne - 1), cy = by & ~(kSubpixelOne - 1);
          const int32_t dx = (static_cast<int32_t>(rng() % 9) - 4) * kSubpixelOne;
          const int32_t dy = (static_cast<int32_t>(rng() % 9) - 4) * kSubpixelOne;
          const int r = static_cast<int>(rng() % 3);
          v[l][r].x = cx, v[l][r].y = cy;
          v[l][(r + 1) % 3].x = cx + dx, v[l][(r + 1) % 3].y = cy;
          v[l][(r + 2) % 3].x = cx, v[l][(r + 2) % 3].y = cy + dy;
          if (rng() % 2) {  // the third vertex less than a pixel above the grid row: the plane's
                            // origin lies on the horizontal edge, away from its vertices
            v[l][(r + 2) % 3].x = cx + static_cast<int32_t>(rng() % 601) - 300;
            v[l][(r + 2) % 3].y = cy - 1 - static_cast<int32_t>(rng() % (kSubpixelOne - 1));
          }
          if (rng() % 2)  // or the same, transposed
            for (int k = 0; k < 3; ++k) std::swap(v[l][k].x, v[l][k].y);
        }
        if (rng() % 8 == 0) v[l][2] = v[l][rng() % 2];  // a repeated vertex
        if (rng() % 8 == 0) {                           // collinear
          v[l][2].x = 2 * v[l][1].x - v[l][0].x;
          v[l][2].y = 2 * v[l][1].y - v[l][0].y;
        }
        for (int k = 0; k < 3; ++k) {
          in.x[k][l] = v[l][k].x, in.y[k][l] = v[l][k].y;
          in.z[k][l] = v[l][k].z, in.iw[k][l] = v[l][k].iw;
        }
      }
      for (int l = 0; l < n; ++l) in.primitive[l] = static_cast<uint32_t>(g * kSetupGroup + l);
      SetupTri tris[kSetupGroup];
      SetupAttr attrsOut[kSetupGroup];
      uint64_t verdicts[4] = {0, 0, 0, 0};
      const uint32_t kept = setupLanes(in, n, cull, vp, tris, attrs ? attrsOut : nullptr, verdicts, target);
      uint64_t wantVerdicts[4] = {0, 0, 0, 0};
      int j = 0;  // the next kept record
      for (int l = 0; l < n; ++l) {
        SetupTri t;
        SetupAttr a;
        int order[3];
        const SetupResult want = setupTriangle(v[l][0], v[l][1], v[l][2], cull, vp, t, attrs ? &a : nullptr, order);
        ++wantVerdicts[static_cast<int>(want)];
        ++counts[static_cast<int>(want)];
        ASSERT_EQ((kept >> l) & 1, want == SetupResult::Ok ? 1u : 0u) << simdTargetName(target) << " group " << g << " lane " << l;
        if (want != SetupResult::Ok) continue;
        t.primitive = in.primitive[l];
        ASSERT_EQ(std::memcmp(&t, &tris[j], sizeof t), 0) << simdTargetName(target) << " group " << g << " lane " << l;
        if (attrs) {
          const SetupAttr& b = attrsOut[j];
          const float wantPlanes[9] = {a.sw0, a.swx, a.swy, a.s10, a.s1x, a.s1y, a.s20, a.s2x, a.s2y};
          const float gotPlanes[9] = {b.sw0, b.swx, b.swy, b.s10, b.s1x, b.s1y, b.s20, b.s2x, b.s2y};
          ASSERT_EQ(std::memcmp(wantPlanes, gotPlanes, sizeof wantPlanes), 0) << simdTargetName(target) << " group " << g;
          for (int k = 0; k < 3; ++k) ASSERT_EQ(b.order[k], order[k]);
          ASSERT_EQ(b.frontFacing, a.frontFacing);
        }
        ++j;
      }
      for (int r = 0; r < 4; ++r) ASSERT_EQ(verdicts[r], wantVerdicts[r]) << simdTargetName(target) << " group " << g;
    }
  }
  // Every verdict was exercised.
  for (uint64_t c : counts) EXPECT_GT(c, 100u);
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
