// The frame's memory estimate and its limit: it grows with what a frame allocates, a frame too
// large for the limit is refused in one line naming both, sizes parse strictly.
#include "engine/memory.h"

#include <gtest/gtest.h>

#include "engine/builtin_scenes.h"

namespace penumbra::engine {
namespace {

ResolvedOptions resolved(RenderOptions o) { return resolveOptions(o).value(); }

TEST(Memory, EstimateFollowsWhatTheFrameHolds) {
  const Scene scene = makeBuiltinScene("default").value();
  RenderOptions small, big;
  small.width = 320, small.height = 180;
  big.width = big.height = 16384;
  const MemoryEstimate a = estimateFrameMemory(scene, resolved(small)), b = estimateFrameMemory(scene, resolved(big));
  EXPECT_GT(b.bytes, a.bytes * 100);
  // 16384^2 with soft shadows holds the G-buffer (40 B), targets and receivers: > 16 GiB.
  EXPECT_GT(b.bytes, uint64_t{16} << 30);
  EXPECT_LT(b.bytes, uint64_t{48} << 30);
  uint64_t sum = 0;
  for (const auto& [what, bytes] : b.parts) sum += bytes;
  EXPECT_EQ(sum, b.bytes);
  // A stochastic scene adds its layers; shadows off drops the shadow parts.
  const Scene motion = makeBuiltinScene("motion").value();
  small.shadow = "none";
  const MemoryEstimate m = estimateFrameMemory(motion, resolved(small));
  bool layers = false, receivers = false;
  for (const auto& [what, bytes] : m.parts) layers |= what == "stochastic layers", receivers |= what == "shadow receivers";
  EXPECT_TRUE(layers);
  EXPECT_FALSE(receivers);
  // The technique's own peak: VWSS's keys grow with the maps per pass.
  RenderOptions v = small;
  v.shadow = "vwss";
  const uint64_t few = estimateFrameMemory(scene, resolved(v)).bytes;
  v.shadowParams = {"views=128,views_per_pass=128"};
  EXPECT_GT(estimateFrameMemory(scene, resolved(v)).bytes, few + (uint64_t{100} << 20));
}

TEST(Memory, LimitRefusesInOneLine) {
  MemoryEstimate e;
  e.parts = {{"targets", uint64_t{3} << 30}};
  e.bytes = uint64_t{3} << 30;
  EXPECT_TRUE(checkMemory(e, uint64_t{4} << 30, "render", "--max-memory").ok());
  EXPECT_TRUE(checkMemory(e, 0, "render", "--max-memory").ok());
  const Status st = checkMemory(e, uint64_t{1} << 30, "render", "--max-memory");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().where, "render");
  EXPECT_NE(st.error().what.find("3.0 GiB"), std::string::npos) << st.error().line();
  EXPECT_NE(st.error().what.find("1.0 GiB"), std::string::npos) << st.error().line();
}

TEST(Memory, SizesParseStrictly) {
  EXPECT_EQ(parseBytes("8G", "--max-memory").value(), uint64_t{8} << 30);
  EXPECT_EQ(parseBytes("512m", "--max-memory").value(), uint64_t{512} << 20);
  EXPECT_EQ(parseBytes("1.5K", "--max-memory").value(), 1536u);
  EXPECT_EQ(parseBytes("1000", "--max-memory").value(), 1000u);
  for (const char* bad : {"", "0", "-1G", "8GB", "G", "1e400", "nan", "8 G"}) {
    const Result<uint64_t> r = parseBytes(bad, "--max-memory");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().where, "option --max-memory");
  }
  EXPECT_GT(availableMemoryBytes(), uint64_t{1} << 20);
}

}  // namespace
}  // namespace penumbra::engine
