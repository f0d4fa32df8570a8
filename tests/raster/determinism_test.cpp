// Same inputs, same bytes: across thread counts, tile sizes' scheduling, and SIMD targets. Also
// that skipping (empty tiles, coarse depth) changes nothing but the work done.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <thread>
#include <tbb/global_control.h>

#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

constexpr int kW = 301, kH = 203;

struct Soup {
  std::vector<glm::vec4> pos;
  std::vector<float> color;  // 3 per vertex
  std::vector<uint32_t> idx;
};

Soup randomSoup(int tris, uint64_t seed) {
  Soup s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int t = 0; t < tris; ++t) {
    const double cx = u(rng) * kW, cy = u(rng) * kH, size = 2.0 + 60.0 * u(rng) * u(rng);
    for (int k = 0; k < 3; ++k) {
      s.pos.push_back(test::clipFromScreen(cx + (u(rng) - 0.5) * size, cy + (u(rng) - 0.5) * size, u(rng), 0.2 + 3.0 * u(rng),
                                           kW, kH));
      for (int c = 0; c < 3; ++c) s.color.push_back(static_cast<float>(u(rng)));
      s.idx.push_back(static_cast<uint32_t>(s.idx.size()));
    }
  }
  return s;
}

// Renders color (RGBA8) and depth; returns the bytes of both.
std::vector<uint8_t> render(const Soup& s, int threads, int tileLog2, int chunk, PassStats* stats = nullptr,
                            int batchChunks = 0, int64_t target = 0) {
  Rasterizer r({.threads = threads,
                .tileLog2 = tileLog2,
                .chunkTriangles = chunk,
                .batchChunks = batchChunks,
                .simd = {.tile = target, .setup = target}});
  DepthTarget depth(kW, kH, 1.0f);
  ImageRgba8 color(kW, kH);
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(s.pos.size());
  d.indices = s.idx;
  d.varyings = 3;
  const PassStats st = r.draw(
      d, depth,
      [&](uint32_t i, float* v) {
        std::memcpy(v, &s.color[i * 3], 3 * sizeof(float));
        return s.pos[i];
      },
      [&](const Fragment& f) {
        auto q = [](float x) { return static_cast<uint8_t>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
        color.at(f.x, f.y) = Rgba8{q(f.varyings[0]), q(f.varyings[1]), q(f.varyings[2]), 255};
      });
  if (stats) *stats = st;
  std::vector<uint8_t> bytes(reinterpret_cast<const uint8_t*>(color.data()),
                             reinterpret_cast<const uint8_t*>(color.data() + color.stride() * color.paddedRows()));
  const auto* db = reinterpret_cast<const uint8_t*>(depth.image().data());
  bytes.insert(bytes.end(), db, db + sizeof(float) * static_cast<size_t>(depth.image().stride() * depth.image().paddedRows()));
  return bytes;
}

TEST(Determinism, ByteIdenticalAcrossThreadCounts) {
  // Allow more workers than this machine has cores, so that 7 threads really are 7.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  const Soup s = randomSoup(5000, 42);
  const auto one = render(s, 1, 6, 256);
  EXPECT_EQ(render(s, 2, 6, 256), one);
  EXPECT_EQ(render(s, 7, 6, 256), one);
}

TEST(Determinism, ByteIdenticalAcrossSimdTargets) {
  const Soup s = randomSoup(3000, 43);
  std::vector<uint8_t> first;
  for (int64_t t : supportedSimdTargets()) {
    const auto img = render(s, 2, 6, 512, nullptr, 0, t);
    if (first.empty()) first = img;
    EXPECT_EQ(img, first) << simdTargetName(t);
  }
}

// The target is the rasterizer's, not the process's: rasterizers on different targets run side
// by side, each gives the same bytes, and a target this CPU cannot run is refused.
TEST(Determinism, SimdChoiceBelongsToTheRasterizer) {
  const std::vector<int64_t> targets = supportedSimdTargets();
  ASSERT_FALSE(targets.empty());
  const Soup s = randomSoup(2000, 47);
  const auto best = render(s, 2, 6, 512);
  const int64_t slowest = targets.back();
  std::vector<uint8_t> a, b;
  std::thread other([&] { a = render(s, 1, 6, 512, nullptr, 0, slowest); });
  b = render(s, 1, 6, 512, nullptr, 0, targets.front());
  other.join();
  EXPECT_EQ(a, best);
  EXPECT_EQ(b, best);
  EXPECT_THROW(Rasterizer({.simd = {.tile = 3}}), std::invalid_argument);  // two targets at once
  EXPECT_THROW(Rasterizer({.simd = {.taps = -1}}), std::invalid_argument);
  EXPECT_THROW(Rasterizer({.simd = {.setup = 3}}), std::invalid_argument);
  EXPECT_THROW(Rasterizer({.simd = {.shade = 3}}), std::invalid_argument);
  // Dispatch by index runs the target asked for (the index serves every kernel family's table).
  for (int64_t t : targets) EXPECT_EQ(simdTargetRun(t), t) << simdTargetName(t);
  EXPECT_EQ(simdTargetRun(0), targets.front());
  // Once Highway has chosen, target 0 is its cached entry, not the entry that detects the CPU
  // (which runs CPUID on every call: 30-60x slower tap kernels).
  EXPECT_EQ(simdDispatchIndex(0), simdDispatchIndex(targets.front()));
}

TEST(Determinism, ChunkSizeDoesNotChangeTheImage) {
  // Submission order is preserved per tile however the triangles are cut into chunks.
  const Soup s = randomSoup(3000, 44);
  EXPECT_EQ(render(s, 2, 6, 64), render(s, 2, 6, 4096));
}

TEST(Determinism, BatchSizeDoesNotChangeTheImage) {
  // Batches of one chunk (many set-up/raster rounds) against one batch holding everything.
  const Soup s = randomSoup(3000, 46);
  PassStats many, one;
  const auto a = render(s, 2, 6, 64, &many, 1);
  const auto b = render(s, 2, 6, 64, &one, 1 << 20);
  EXPECT_EQ(a, b);
  EXPECT_EQ(many.tilesTouched, one.tilesTouched);
  EXPECT_EQ(many.pixelsDepthPassed, one.pixelsDepthPassed);
}

TEST(Skipping, EmptyTilesAreSkippedAndCounted) {
  Soup s;
  // One small triangle in the top-left corner.
  for (int k = 0; k < 3; ++k) {
    s.pos.push_back(test::clipFromScreen(3 + 5 * (k == 1), 3 + 5 * (k == 2), 0.5, 1, kW, kH));
    s.color.insert(s.color.end(), {1, 1, 1});
    s.idx.push_back(static_cast<uint32_t>(k));
  }
  PassStats st;
  render(s, 2, 6, 256, &st);
  const uint64_t tiles = ((kW + 63) / 64) * ((kH + 63) / 64);
  EXPECT_EQ(st.tilesTotal, tiles);
  EXPECT_EQ(st.tilesTouched, 1u);
  EXPECT_EQ(st.tilesSkipped, tiles - 1);
}

TEST(Skipping, CoarseDepthRejectsHiddenBlocksWithoutChangingTheImage) {
  // A full-screen near quad first, then many triangles behind it: every block of the later
  // triangles is rejected by coarse depth, and the image equals the near quad alone.
  Soup behind = randomSoup(2000, 45);
  for (auto& p : behind.pos) p.z = std::max(p.z, 0.6f * p.w);
  Soup s;
  const double corners[4][2] = {{-10, -10}, {kW + 10, -10}, {kW + 10, kH + 10}, {-10, kH + 10}};
  for (const auto& c : corners) {
    s.pos.push_back(test::clipFromScreen(c[0], c[1], 0.1, 1.0, kW, kH));
    s.color.insert(s.color.end(), {0.2f, 0.4f, 0.6f});
  }
  s.idx = {0, 1, 2, 0, 2, 3};
  const Soup quadOnly = s;
  for (size_t i = 0; i < behind.pos.size(); ++i) {
    s.pos.push_back(behind.pos[i]);
    s.color.insert(s.color.end(), {behind.color[i * 3], behind.color[i * 3 + 1], behind.color[i * 3 + 2]});
    s.idx.push_back(static_cast<uint32_t>(s.pos.size() - 1));
  }
  PassStats st;
  const auto img = render(s, 2, 6, 256, &st);
  EXPECT_EQ(img, render(quadOnly, 2, 6, 256));
  EXPECT_GT(st.blocksRejectedDepth, 1000u);
  EXPECT_EQ(st.pixelsDepthPassed, static_cast<uint64_t>(kW) * kH);
}

}  // namespace
}  // namespace penumbra::raster
