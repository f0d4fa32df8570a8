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

TEST(Renderer, WithoutTheLinearImageTheSameBytesAndNoRadianceKept) {
  // The command line's render without --exr: the 8-bit image only, the same bytes, the skip reported.
  Result<Scene> scene = makeBuiltinScene(kDefaultScene);
  ASSERT_TRUE(scene.ok()) << scene.error().line();
  RenderOptions opt;
  opt.width = 96;
  opt.height = 54;
  Renderer r(2);
  const Frame kept = test::renderFrame(r, *scene, opt);
  opt.linearImage = false;
  const Frame dropped = test::renderFrame(r, *scene, opt);
  EXPECT_EQ(kept.linear.width(), opt.width);
  EXPECT_TRUE(dropped.linear.empty());
  EXPECT_EQ(bytes(dropped.color), bytes(kept.color));
  EXPECT_NE(dropped.stats.report().find("linear radiance image"), std::string::npos);
  EXPECT_EQ(kept.stats.report().find("linear radiance image"), std::string::npos);
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
  EXPECT_EQ(f.stats.cameraSource, "fitted to the objects' bounds");
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

namespace penumbra::engine {
namespace {

// Pixels of the frame that show geometry, and whether any touches the image's border columns.
struct Coverage {
  int covered = 0;
  bool leftOrRight = false, topOrBottom = false;
};
Coverage coverage(const Frame& f) {
  Coverage c;
  const int w = f.gbuffer.width(), h = f.gbuffer.height();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (f.gbuffer.at(x, y).material >= 0) {
        ++c.covered;
        c.leftOrRight |= x == 0 || x == w - 1;
        c.topOrBottom |= y == 0 || y == h - 1;
      }
  return c;
}

Scene sphereScene() {
  Scene s;
  s.meshes.push_back(makeSphere(1.0f, 24, 48));
  s.instances.push_back({"ball", 0, glm::mat4(1.0f)});
  EXPECT_TRUE(validateScene(s, "test").ok());
  return s;
}

// The fitted camera frames the bounds in both directions: a portrait image does not cut the
// object off at its sides.
TEST(RendererDefaults, FittedCameraFramesPortraitAndLandscape) {
  const Scene s = sphereScene();
  Renderer r(2);
  for (const auto& [w, h] : {std::pair{48, 160}, std::pair{160, 48}, std::pair{64, 64}}) {
    RenderOptions o;
    o.width = w, o.height = h, o.shadow = "none";
    const Coverage c = coverage(test::renderFrame(r, s, o));
    EXPECT_FALSE(c.leftOrRight) << w << "x" << h;
    EXPECT_FALSE(c.topOrBottom) << w << "x" << h;
    EXPECT_GT(c.covered, std::min(w, h) * std::min(w, h) / 6) << w << "x" << h;  // fills the narrow direction
  }
}

// A ground far larger than the objects is not what the camera frames.
TEST(RendererDefaults, FittedCameraFramesTheObjectsNotAHugeGround) {
  Scene s = sphereScene();
  s.meshes.push_back(makePlane(400.0f, 400.0f, 4));
  s.instances.push_back({"ground", 1, glm::translate(glm::mat4(1.0f), {0, -1, 0})});
  ASSERT_TRUE(validateScene(s, "test").ok());
  glm::vec3 lo, hi;
  ASSERT_TRUE(s.objectBounds(lo, hi));
  EXPECT_LT(glm::length(hi - lo), 5.0f);
  Renderer r(2);
  RenderOptions o;
  o.width = 96, o.height = 64, o.shadow = "none";
  const Frame f = test::renderFrame(r, s, o);
  int ball = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) ball += f.gbuffer.at(x, y).material >= 0 && f.gbuffer.at(x, y).position.y > -0.99f;
  EXPECT_GT(ball, 96 * 64 / 10);  // the ball, not a speck on a vast plane
}

// A scene without lights gets a key area light and a sky: lit, shadowed, and said so.
TEST(RendererDefaults, ALightlessSceneGetsAKeyLightAndASky) {
  Scene s = sphereScene();
  s.meshes.push_back(makePlane(6.0f, 6.0f, 1));
  s.instances.push_back({"ground", 1, glm::translate(glm::mat4(1.0f), {0, -1, 0})});
  ASSERT_TRUE(validateScene(s, "test").ok());
  Scene unlit = s;
  ASSERT_TRUE(addDefaultLighting(s));
  EXPECT_FALSE(addDefaultLighting(s));  // it has a light now
  ASSERT_EQ(s.areaLights.size(), 1u);
  EXPECT_TRUE(s.sky.has_value());
  // A white surface at the centre facing the key light reflects about 0.8 of it.
  glm::vec3 lo, hi;
  s.objectBounds(lo, hi);
  const glm::vec3 c = (lo + hi) * 0.5f, toLight = glm::normalize(s.areaLights[0].center - c);
  const float reflected = s.areaLights[0].intensity * shadows::irradianceFactor(s.areaLights[0], c, toLight) / 3.14159265f;
  EXPECT_NEAR(reflected, 0.8f, 1e-3f);
  Renderer r(2);
  RenderOptions o;
  o.width = 96, o.height = 64;
  const Frame lit = test::renderFrame(r, s, o), dark = test::renderFrame(r, unlit, o);
  EXPECT_NE(lit.stats.lighting.find("default key area light"), std::string::npos);
  EXPECT_NE(lit.stats.report().find("lighting: the scene has no light"), std::string::npos);
  // Brighter than the unlit grey, with light and shadow on the ground (V from 0 to 1).
  double sumLit = 0, sumDark = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) sumLit += double{lit.linear.at(x, y).r}, sumDark += double{dark.linear.at(x, y).r};
  EXPECT_GT(sumLit, 3 * sumDark);
  float vmin = 1, vmax = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x)
      if (lit.gbuffer.at(x, y).material >= 0) vmin = std::min(vmin, lit.visibility[0].at(x, y)), vmax = std::max(vmax, lit.visibility[0].at(x, y));
  EXPECT_LT(vmin, 0.2f);
  EXPECT_EQ(vmax, 1.0f);
}

// Exposure and the filmic tone map shape the 8-bit image only; off, the bytes are the plain ones.
TEST(RendererDefaults, ExposureAndToneMap) {
  Scene s = sphereScene();
  ASSERT_TRUE(addDefaultLighting(s));
  Renderer r(2);
  RenderOptions o;
  o.width = 64, o.height = 48;
  const Frame plain = test::renderFrame(r, s, o);
  o.exposure = 2.0;
  const Frame bright = test::renderFrame(r, s, o);
  o.toneMap = ToneMap::Aces;
  const Frame aces = test::renderFrame(r, s, o);
  o.exposure = 0.0;
  o.toneMap = ToneMap::None;
  EXPECT_EQ(test::bytes(test::renderFrame(r, s, o).color), test::bytes(plain.color));
  int brighter = 0, clipped = 0, clippedAces = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      brighter += bright.color.at(x, y).r > plain.color.at(x, y).r;
      clipped += bright.color.at(x, y).r == 255;
      clippedAces += aces.color.at(x, y).r == 255;
      EXPECT_EQ(bright.linear.at(x, y).r, plain.linear.at(x, y).r);  // the EXR keeps radiance
    }
  EXPECT_GT(brighter, 100);
  EXPECT_GT(clipped, 50);
  EXPECT_LT(clippedAces, clipped / 4);  // highlights roll off instead of clipping
  RenderOptions bad;
  bad.exposure = 21;
  EXPECT_FALSE(resolveOptions(bad).ok());
}

}  // namespace
}  // namespace penumbra::engine

namespace penumbra::engine {
namespace {

// Vertex colors multiply the material's base color, interpolated like every varying: the G-buffer
// albedo is the base color times the barycentric blend of the seen triangle's vertex colors.
TEST(Renderer, VertexColorsMultiplyTheBaseColor) {
  Scene s;
  Mesh m = makePlane(2.0f, 2.0f, 3);
  for (size_t i = 0; i < m.positions.size(); ++i)
    m.colors.emplace_back(static_cast<float>(i % 3) / 2.0f, static_cast<float>(i % 5) / 4.0f, 1.0f);
  s.meshes.push_back(m);
  Material mat;
  mat.baseColorFactor = glm::vec4(0.5f, 0.25f, 1.0f, 1.0f);
  s.materials.push_back(mat);
  s.meshes[0].material = 0;
  s.instances.push_back({.name = "plane", .mesh = 0});
  s.camera = Camera{.eye = glm::vec3(0.0f, 3.0f, 0.5f), .target = glm::vec3(0.0f)};
  ASSERT_TRUE(validateScene(s, "colors").ok());
  Renderer r(2);
  RenderOptions opt;
  opt.width = 40;
  opt.height = 30;
  opt.shadow = "none";
  const Frame f = test::renderFrame(r, s, opt);
  size_t seen = 0;
  for (int y = 0; y < opt.height; ++y)
    for (int x = 0; x < opt.width; ++x) {
      const GBufferTexel& t = f.gbuffer.at(x, y);
      if (t.material < 0) continue;
      ++seen;
      glm::vec3 blend(0.0f);
      for (int k = 0; k < 3; ++k)
        blend += t.bary[k] * s.meshes[0].colors[s.meshes[0].indices[static_cast<size_t>(t.triangle) * 3 +
                                                                     static_cast<size_t>(k)]];
      const glm::vec3 want = glm::vec3(mat.baseColorFactor) * blend;
      EXPECT_NEAR(t.albedo.x, want.x, 1e-5f);
      EXPECT_NEAR(t.albedo.y, want.y, 1e-5f);
      EXPECT_NEAR(t.albedo.z, want.z, 1e-5f);
    }
  EXPECT_GT(seen, 400u);
  // Wrong counts and non-finite colors are refused, naming the mesh.
  Scene bad = s;
  bad.meshes[0].colors.pop_back();
  EXPECT_NE(validateScene(bad, "colors").error().line().find("color count"), std::string::npos);
  bad = s;
  bad.meshes[0].colors[2].y = NAN;
  EXPECT_NE(validateScene(bad, "colors").error().line().find("non-finite vertex color"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::engine
