// Several render targets of different pixel types written by one pass, and the depth-only path
// writing the same depths as the full path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>

#include "tests/raster/test_util.h"

namespace penumbra::raster {
namespace {

struct GTexel {
  float nx = 0, ny = 0, nz = 0;
  uint32_t primitive = ~0u;
};

// resizeParallel gives the same elements as resize (padding included) at any thread count, for
// images below and above the large-page size, and after shrinking and regrowing: the allocator
// skips value-initialization there, so an element it forgot would show here as garbage.
TEST(Targets, ResizeParallelEqualsResizeOnLargePages) {
  struct Texel {
    float a = 1.5f;
    int32_t b = -1;
    uint8_t c = 7;
  };
  for (int threads : {1, 2, 5})
    for (auto [w, h] : {std::pair{3, 5}, std::pair{1280, 720}, std::pair{1021, 1037}, std::pair{17, 9}}) {
      Rasterizer r({.threads = threads});
      Image<Texel> par(40, 40, Texel{9.0f, 9, 9});  // earlier contents that must not survive
      r.run([&] { par.resizeParallel(w, h, Texel{2.0f, 3, 4}); });
      const Image<Texel> seq(w, h, Texel{2.0f, 3, 4});
      ASSERT_EQ(par.stride(), seq.stride());
      ASSERT_EQ(par.paddedRows(), seq.paddedRows());
      size_t bad = 0;
      for (int y = 0; y < seq.paddedRows(); ++y)
        for (int x = 0; x < seq.stride(); ++x) {
          const Texel &p = par.row(y)[x], &q = seq.row(y)[x];
          bad += (p.a != q.a || p.b != q.b || p.c != q.c) ? 1 : 0;
        }
      EXPECT_EQ(bad, 0u) << w << "x" << h << " at " << threads << " threads";
      const size_t bytes = static_cast<size_t>(seq.stride()) * static_cast<size_t>(seq.paddedRows()) * sizeof(Texel);
      if (bytes >= kLargePageBytes)  // large blocks start on a large page (the madvise hint needs it)
        EXPECT_EQ(reinterpret_cast<uintptr_t>(par.data()) % kLargePageBytes, 0u);
    }
}

TEST(Targets, OnePassWritesRgba8FloatAndStructTargets) {
  const int w = 70, h = 45;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::vec4> pos;
  std::vector<uint32_t> idx;
  for (int t = 0; t < 300; ++t)
    for (int k = 0; k < 3; ++k) {
      pos.push_back(test::clipFromScreen(u(rng) * w, u(rng) * h, u(rng), 0.5 + u(rng), w, h));
      idx.push_back(static_cast<uint32_t>(idx.size()));
    }
  Rasterizer r({.threads = 2, .tileLog2 = 4});
  DepthTarget depth(w, h, 1.0f);
  ImageRgba8 color(w, h);
  ImageFloat4 hdr(w, h);
  Image<GTexel> gbuf(w, h);
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(pos.size());
  d.indices = idx;
  d.varyings = 3;
  r.draw(
      d, depth,
      [&](uint32_t i, float* v) {
        v[0] = static_cast<float>(i % 3 == 0), v[1] = static_cast<float>(i % 3 == 1), v[2] = static_cast<float>(i % 3 == 2);
        return pos[i];
      },
      [&](const Fragment& f) {
        color.at(f.x, f.y) = Rgba8{static_cast<uint8_t>(f.primitive & 255), 0, 0, 255};
        hdr.at(f.x, f.y) = Float4{f.varyings[0], f.varyings[1], f.varyings[2], f.depth};
        gbuf.at(f.x, f.y) = GTexel{f.b0, f.b1, f.b2, f.primitive};
      });
  // The three targets agree pixel by pixel, with the depth target, and with the barycentrics.
  DepthTarget depthOnly(w, h, 1.0f);
  r.drawDepth(d, depthOnly, [&](uint32_t i) { return pos[i]; });
  int written = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const GTexel& g = gbuf.at(x, y);
      ASSERT_EQ(depthOnly.at(x, y), depth.at(x, y)) << x << "," << y;
      if (g.primitive == ~0u) {
        EXPECT_EQ(depth.at(x, y), 1.0f);
        continue;
      }
      ++written;
      EXPECT_EQ(color.at(x, y).r, g.primitive & 255);
      EXPECT_EQ(hdr.at(x, y).a, depth.at(x, y));
      // Varyings are one-hot per submitted vertex: they equal the barycentrics.
      EXPECT_NEAR(hdr.at(x, y).r, g.nx, 1e-5);
      EXPECT_NEAR(hdr.at(x, y).g, g.ny, 1e-5);
      EXPECT_NEAR(hdr.at(x, y).b, g.nz, 1e-5);
    }
  EXPECT_GT(written, w * h / 2);
}

}  // namespace
}  // namespace penumbra::raster
