// The renderer: byte-identical frames whatever the thread count, frustum culling that skips work
// without changing the image, a fitted camera when the scene has none, the built-in scenes.
#include <gtest/gtest.h>

#include "tests/engine/test_util.h"
#include <tbb/global_control.h>

#include <glm/ext/matrix_transform.hpp>

#include "engine/builtin_scenes.h"
#include "engine/renderer.h"
#include "engine/shapes.h"
#include "test_util.h"

namespace penumbra::engine {
namespace {

using test::bytes;

TEST(Renderer, DefaultSceneIsByteIdenticalAcrossThreadCounts) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  Result<Scene> scene = makeBuiltinScene(kDefaultScene);
  ASSERT_TRUE(scene.ok()) << scene.error().line();
  RenderOptions opt;
  opt.width = 203;
  opt.height = 117;
  std::vector<uint8_t> first;
  for (int threads : {1, 2, 7}) {
    Renderer r(threads);
    const Frame f = test::renderFrame(r, *scene, opt);
    const auto b = bytes(f.color);
    if (first.empty()) first = b;
    EXPECT_EQ(b, first) << threads << " threads";
  }
  // Something worth looking at: most pixels are not background, several distinct colors.
  Renderer r(2);
  const Frame f = test::renderFrame(r, *scene, opt);
  int covered = 0;
  for (int y = 0; y < f.gbuffer.height(); ++y)
    for (int x = 0; x < f.gbuffer.width(); ++x) covered += f.gbuffer.at(x, y).material >= 0;
  EXPECT_GT(covered, opt.width * opt.height / 3);
  EXPECT_EQ(f.stats.instancesCulled, 0u);
}

TEST(Renderer, InstancesOutsideTheViewAreCulledWithoutChangingTheImage) {
  Scene s;
  s.meshes.push_back(makeSphere(1.0f, 16, 32));
  s.materials.push_back(Material{});
  s.meshes[0].material = 0;
  s.instances.push_back({"visible", 0, glm::mat4(1.0f)});
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  s.camera = cam;
  s.directionalLights.push_back({});
  ASSERT_TRUE(validateScene(s, "test").ok());
  RenderOptions opt;
  opt.width = 64;
  opt.height = 48;
  Renderer r(2);
  const Frame alone = test::renderFrame(r, s, opt);
  s.instances.push_back({"behind", 0, glm::translate(glm::mat4(1.0f), {0, 0, 20})});
  s.instances.push_back({"far left", 0, glm::translate(glm::mat4(1.0f), {-50, 0, 0})});
  const Frame more = test::renderFrame(r, s, opt);
  EXPECT_EQ(more.stats.instancesCulled, 2u);
  EXPECT_EQ(more.stats.trianglesSkippedByCulling, 2 * s.meshes[0].indices.size() / 3);
  EXPECT_EQ(more.stats.gbuffer.trianglesIn, alone.stats.gbuffer.trianglesIn);
  EXPECT_EQ(bytes(more.color), bytes(alone.color));
  EXPECT_NE(more.stats.report().find("'behind'"), std::string::npos);
}

TEST(Renderer, FitsACameraWhenTheSceneHasNone) {
  Scene s;
  s.meshes.push_back(makeBox({1, 2, 3}));
  s.instances.push_back({"box", 0, glm::translate(glm::mat4(1.0f), {100, -40, 7})});
  ASSERT_TRUE(validateScene(s, "test").ok());
  RenderOptions opt;
  opt.width = 80;
  opt.height = 60;
  Renderer r(1);
  const Frame f = test::renderFrame(r, s, opt);
  EXPECT_EQ(f.stats.cameraSource, "fitted to bounds");
  int covered = 0;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x) covered += f.gbuffer.at(x, y).material >= 0;
  EXPECT_GT(covered, 80 * 60 / 20);
  EXPECT_LT(covered, 80 * 60);
}

TEST(Renderer, BuiltinScenesValidateAndUnknownNamesListTheValidOnes) {
  for (const BuiltinInfo& b : builtinScenes()) {
    if (b.name == "synth4m") continue;  // large; synth1m covers the generator
    EXPECT_TRUE(makeBuiltinScene(b.name).ok()) << b.name;
  }
  const Result<Scene> bad = makeBuiltinScene("nope");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().line().find("default"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::engine
