// Frames with motion blur and depth of field: the stochastic pass against the ordinary one, the
// bounding methods against each other, thread counts, convergence to the accumulation reference,
// and the ordinary path that static instances keep.
#include <gtest/gtest.h>

#include "tests/engine/test_util.h"
#include <tbb/global_control.h>

#include <cstring>
#include <glm/ext/matrix_transform.hpp>

#include "engine/builtin_scenes.h"
#include "engine/metrics.h"
#include "engine/renderer.h"
#include "test_util.h"

namespace penumbra::engine {
namespace {

using test::bytes;

bool sameLinear(const raster::ImageFloat4& a, const raster::ImageFloat4& b) {
  const std::vector<raster::Float4> pa = a.packed(), pb = b.packed();
  return pa.size() == pb.size() && std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(raster::Float4)) == 0;
}

Scene builtin(const std::string& name) {
  Result<Scene> s = makeBuiltinScene(name);
  EXPECT_TRUE(s.ok());
  return std::move(*s);
}

RenderOptions small(int w = 128, int h = 72) {
  RenderOptions o;
  o.width = w;
  o.height = h;
  return o;
}

// With no motion and a pinhole, every triangle sent through the per-sample tester gives the
// ordinary frame bit for bit: coverage, depth, varyings, layers, shadows and the blend.
TEST(StochasticRender, StaticPinholeFrameEqualsTheOrdinaryFrame) {
  const Scene scene = builtin(kDefaultScene);
  Renderer r(2);
  RenderOptions o = small(160, 90);
  const Frame ordinary = test::renderFrame(r, scene, o);
  EXPECT_FALSE(ordinary.stats.stochastic);
  EXPECT_NE(ordinary.stats.report().find("skipped passes: stochastic pass (skipped: no visible instance moves"),
            std::string::npos);
  o.forceStochastic = true;
  o.spp = 4;
  for (bool staticPath : {true, false}) {
    o.staticPath = staticPath;
    const Frame forced = test::renderFrame(r, scene, o);
    ASSERT_TRUE(forced.stats.stochastic);
    EXPECT_EQ(forced.stats.trianglesStochastic, staticPath ? 0u : scene.triangleCount());
    EXPECT_EQ(bytes(forced.color), bytes(ordinary.color)) << "static path " << staticPath;
    EXPECT_TRUE(sameLinear(forced.linear, ordinary.linear)) << "static path " << staticPath;
  }
}

TEST(StochasticRender, BoundingMethodsGiveTheSameFrameWithFewerTests) {
  Renderer r(2);
  for (const char* name : {"motion", "defocus", "motion-defocus"}) {
    const Scene scene = builtin(name);
    RenderOptions o = small();
    o.spp = 4;
    o.shadow = "none";
    std::vector<uint8_t> first;
    uint64_t boxTests = 0;
    for (stochastic::BoundMethod m :
         {stochastic::BoundMethod::Box, stochastic::BoundMethod::Interval, stochastic::BoundMethod::DualSpace}) {
      o.bounds = m;
      const Frame f = test::renderFrame(r, scene, o);
      ASSERT_TRUE(f.stats.stochastic) << name;
      if (first.empty()) {
        first = bytes(f.color);
        boxTests = f.stats.stoch.tests;
      } else {
        EXPECT_EQ(bytes(f.color), first) << name << " " << stochastic::boundMethodName(m);
        EXPECT_LT(f.stats.stoch.tests, boxTests) << name << " " << stochastic::boundMethodName(m);
      }
    }
  }
}

TEST(StochasticRender, ByteIdenticalAcrossThreadCounts) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  const Scene scene = builtin("motion-defocus");
  RenderOptions o = small(120, 68);
  o.spp = 8;
  std::vector<uint8_t> first;
  for (int threads : {1, 2, 5}) {
    Renderer r(threads);
    const Frame f = test::renderFrame(r, scene, o);
    if (first.empty()) first = bytes(f.color);
    else EXPECT_EQ(bytes(f.color), first) << threads << " threads";
  }
}

// The static instances of a scene with few moving objects stay on the ordinary path (or, inside
// the stochastic pass, share one test per pixel): the same frame, far fewer sample tests.
TEST(StochasticRender, StaticInstancesKeepTheOrdinaryPath) {
  const Scene scene = builtin("motion");
  Renderer r(2);
  RenderOptions o = small();
  o.spp = 8;
  o.shadow = "none";
  const Frame fast = test::renderFrame(r, scene, o);
  o.staticPath = false;
  const Frame shared = test::renderFrame(r, scene, o);
  o.staticShortcut = false;
  const Frame slow = test::renderFrame(r, scene, o);
  EXPECT_EQ(bytes(fast.color), bytes(shared.color));
  EXPECT_EQ(bytes(fast.color), bytes(slow.color));
  EXPECT_GT(fast.stats.instancesOrdinary, 0u);
  EXPECT_EQ(shared.stats.instancesOrdinary, 0u);
  EXPECT_GT(shared.stats.stoch.trianglesStatic, 0u);
  EXPECT_EQ(slow.stats.stoch.trianglesStatic, 0u);
  // The static triangles' tests: one per pixel with the shortcut, one per sample without.
  const uint64_t moving = fast.stats.stoch.tests;
  EXPECT_GT(shared.stats.stoch.tests, moving);
  EXPECT_GT(slow.stats.stoch.tests - moving, 4 * (shared.stats.stoch.tests - moving));
  EXPECT_EQ(shared.stats.stoch.hits - fast.stats.stoch.hits, (slow.stats.stoch.hits - fast.stats.stoch.hits) / 8);
}

// Error against the accumulation-buffer reference falls as the samples per pixel grow.
TEST(StochasticRender, ConvergesToTheAccumulationReference) {
  for (const char* name : {"motion", "defocus"}) {
    const Scene scene = builtin(name);
    Renderer r(2);
    RenderOptions o = small(96, 54);
    o.shadow = "none";
    const raster::ImageFloat4 ref = accumulationReference(r, scene, o, 256).value();
    double last = 1.0;
    for (int spp : {1, 4, 16}) {
      o.spp = spp;
      const double e = imageRmse(test::renderFrame(r, scene, o).linear, ref);
      EXPECT_LT(e, last * 0.8) << name << " at " << spp << " spp";
      last = e;
    }
    // Beyond that the error reaches the floor of shading each surface once per pixel and of the
    // reference's own 256 frames (docs/stochastic.md).
    o.spp = 64;
    EXPECT_LT(imageRmse(test::renderFrame(r, scene, o).linear, ref), last * 1.05) << name;
    EXPECT_LT(last, 0.03) << name;
  }
}

TEST(StochasticRender, FixedSampleFramesMoveTheInstancesAndTheLens) {
  const Scene scene = builtin("motion-defocus");
  Renderer r(2);
  RenderOptions o = small();
  o.shadow = "none";
  o.at = stochastic::Sample{0.0f, 0.0f, 0.0f};
  const Frame open = test::renderFrame(r, scene, o);
  EXPECT_FALSE(open.stats.stochastic);
  o.at = stochastic::Sample{1.0f, 0.0f, 0.0f};
  const Frame close = test::renderFrame(r, scene, o);
  o.at = stochastic::Sample{0.0f, 0.9f, 0.0f};
  const Frame lens = test::renderFrame(r, scene, o);
  EXPECT_NE(bytes(open.color), bytes(close.color));
  EXPECT_NE(bytes(open.color), bytes(lens.color));
}

// An object just in front of a wide lens, far out of focus, is pushed off one side of the view by
// one lens corner and off the other side by the opposite one: it is still seen through the middle
// of the lens and must not be culled.
TEST(StochasticRender, LensFrustumCullingKeepsObjectsSeenThroughTheMiddleOfTheLens) {
  Scene scene = builtin("defocus");
  scene.camera->apertureRadius = 0.5f;
  scene.camera->focusDistance = 10.0f;
  const glm::vec3 eye = scene.camera->eye, fwd = glm::normalize(scene.camera->target - eye);
  Mesh ball = scene.meshes.back();
  scene.meshes.push_back(ball);
  Instance near;
  near.name = "near ball";
  near.mesh = static_cast<int>(scene.meshes.size()) - 1;
  near.transform = glm::scale(glm::translate(glm::mat4(1.0f), eye + fwd * 0.6f), glm::vec3(0.05f));
  scene.instances.push_back(near);
  ASSERT_TRUE(validateScene(scene, "test").ok());
  Renderer r(2);
  RenderOptions o = small();
  o.spp = 8;
  o.shadow = "none";
  o.camera = scene.camera;
  const Frame f = test::renderFrame(r, scene, o);
  for (const std::string& n : f.stats.culledNames) EXPECT_NE(n, "near ball");
  const uint32_t id = static_cast<uint32_t>(scene.instances.size() - 1);
  int pixels = 0;
  for (int y = 0; y < f.resolved.height(); ++y)
    for (int x = 0; x < f.resolved.width(); ++x)
      for (int l = 0; l < f.resolved.at(x, y).layers; ++l) pixels += f.resolved.at(x, y).layer[l].surface == id ? 1 : 0;
  EXPECT_GT(pixels, 100) << "the near ball's blur covers the middle of the view";
}

TEST(StochasticRender, RejectsSamplesPerPixelOutOfRange) {
  const Scene scene = builtin("motion");
  Renderer r(1);
  RenderOptions o = small(16, 16);
  for (int spp : {0, 65}) {
    o.spp = spp;
    const Result<Frame> f = r.render(scene, o);
    ASSERT_FALSE(f.ok());
    EXPECT_EQ(f.error().where, "option --spp");
    EXPECT_NE(f.error().what.find("[1, 64]"), std::string::npos) << f.error().line();
  }
}

}  // namespace
}  // namespace penumbra::engine
