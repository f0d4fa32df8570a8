// The multisampled G-buffer pass (engine/msaa_pass.h): edge error against 16 x 16 supersampling
// falls with the sample count, layers account for every sample, the bytes are the same at any
// thread count, and a frame with a stochastic pass keeps its own sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/ext/matrix_transform.hpp>

#include "engine/builtin_scenes.h"
#include "engine/renderer.h"
#include "engine/shapes.h"
#include "tests/engine/test_util.h"

namespace penumbra::engine {
namespace {

// A sphere, a rotated box and a thin pole on a plane: silhouettes against the ground, the sky and
// each other. Untextured (the supersampled reference must shade like the frame).
Scene silhouettes() {
  Scene s;
  s.meshes = {makePlane(12.0f, 12.0f, 2), makeSphere(0.8f, 24, 48), makeBox(glm::vec3(1.0f)),
              makeCylinder(0.06f, 2.0f, 16)};
  s.materials.resize(4);
  const glm::vec4 colors[4] = {
      {0.6f, 0.6f, 0.6f, 1}, {0.9f, 0.2f, 0.1f, 1}, {0.1f, 0.3f, 0.9f, 1}, {0.9f, 0.9f, 0.2f, 1}};
  for (int i = 0; i < 4; ++i) {
    s.materials[static_cast<size_t>(i)].baseColorFactor = colors[i];
    s.meshes[static_cast<size_t>(i)].material = i;
  }
  s.instances = {
      {.name = "ground", .mesh = 0},
      {.name = "ball", .mesh = 1, .transform = glm::translate(glm::mat4(1.0f), {-0.9f, 0.8f, 0.0f})},
      {.name = "box",
       .mesh = 2,
       .transform = glm::rotate(glm::translate(glm::mat4(1.0f), {0.9f, 0.5f, -0.3f}), 0.6f, {0, 1, 0})},
      {.name = "pole", .mesh = 3, .transform = glm::translate(glm::mat4(1.0f), {0.1f, 1.0f, 0.9f})}};
  s.areaLights.push_back(
      shadows::RectLight{.center = {1.0f, 5.0f, 1.0f}, .width = 1.5f, .height = 1.5f, .intensity = 3.0f});
  s.camera = Camera{.eye = {0.3f, 2.2f, 5.0f}, .target = {0.0f, 0.6f, 0.0f}, .fovYDegrees = 40.0f};
  EXPECT_TRUE(validateScene(s, "silhouettes").ok());
  return s;
}

TEST(MsaaRender, EdgeErrorFallsWithTheSampleCount) {
  const Scene scene = silhouettes();
  Renderer r(2);
  constexpr int kW = 64, kH = 40, kF = 16;
  RenderOptions opt;
  opt.shadow = "none";
  opt.width = kW * kF;
  opt.height = kH * kF;
  const Frame ref = test::renderFrame(r, scene, opt);
  opt.width = kW;
  opt.height = kH;
  std::vector<double> rmse;
  size_t edges = 0;
  for (int samples : {1, 4, 8}) {
    opt.msaa = samples;
    const Frame f = test::renderFrame(r, scene, opt);
    EXPECT_EQ(f.stats.msaa, samples);
    double sum = 0;
    edges = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        // Edge pixels: their 256 sub-pixels do not all see the same instance.
        const int first = ref.gbuffer.at(x * kF, y * kF).instance;
        bool edge = false;
        glm::dvec3 mean(0.0);
        for (int j = 0; j < kF; ++j)
          for (int i = 0; i < kF; ++i) {
            edge |= ref.gbuffer.at(x * kF + i, y * kF + j).instance != first;
            const raster::Float4 c = ref.linear.at(x * kF + i, y * kF + j);
            mean += glm::dvec3(c.r, c.g, c.b);
          }
        if (!edge) continue;
        mean /= double{kF * kF};
        const raster::Float4 c = f.linear.at(x, y);
        const glm::dvec3 d = glm::dvec3(c.r, c.g, c.b) - mean;
        sum += glm::dot(d, d) / 3.0;
        ++edges;
      }
    rmse.push_back(std::sqrt(sum / static_cast<double>(edges)));
  }
  EXPECT_GT(edges, 150u);
  EXPECT_LT(rmse[1], 0.7 * rmse[0]) << rmse[0] << " " << rmse[1];
  EXPECT_LT(rmse[2], rmse[1]) << rmse[1] << " " << rmse[2];
  EXPECT_LT(rmse[2], 0.5 * rmse[0]);
}

TEST(MsaaRender, LayersHoldEverySampleAndShadowsPerLayer) {
  const Scene scene = silhouettes();
  Renderer r(2);
  RenderOptions opt;
  opt.width = 80;
  opt.height = 48;
  opt.msaa = 8;
  opt.shadow = "pcss";
  const Frame f = test::renderFrame(r, scene, opt);
  ASSERT_EQ(f.spp, 8);
  size_t multi = 0;
  for (int y = 0; y < opt.height; ++y)
    for (int x = 0; x < opt.width; ++x) {
      const stochastic::ResolvedPixel& rp = f.resolved.at(x, y);
      int total = rp.background;
      for (int l = 0; l < rp.layers; ++l) {
        total += rp.layer[l].count;
        const GBufferTexel& t = f.layerTexel(l, x, y);
        ASSERT_GE(t.material, 0);
        EXPECT_GE(t.triangle, 0);
      }
      EXPECT_EQ(total, 8);
      multi += rp.layers > 1;
      const float v = f.visibility[0].at(x, y);
      EXPECT_TRUE(v >= 0.0f && v <= 1.0f);
    }
  EXPECT_GT(multi, 100u);
  EXPECT_NE(f.stats.report().find("multisampling: 8 samples"), std::string::npos);
}

TEST(MsaaRender, SameBytesAtAnyThreadCount) {
  const Scene scene = silhouettes();
  RenderOptions opt;
  opt.width = 72;
  opt.height = 40;
  opt.msaa = 4;
  opt.shadow = "pcss";
  std::vector<uint8_t> first;
  std::vector<float> firstV;
  for (int threads : {1, 2, 5}) {
    Renderer r(threads);
    const Frame f = test::renderFrame(r, scene, opt);
    const std::vector<uint8_t> b = test::bytes(f.color);
    const std::vector<float> v = f.visibility[0].packed();
    if (first.empty())
      first = b, firstV = v;
    else {
      EXPECT_EQ(b, first) << threads << " threads";
      EXPECT_EQ(v, firstV) << threads << " threads";
    }
  }
}

TEST(MsaaRender, AStochasticPassKeepsItsOwnSamples) {
  Result<Scene> scene = makeBuiltinScene("motion");
  ASSERT_TRUE(scene.ok());
  Renderer r(2);
  RenderOptions opt;
  opt.width = 64;
  opt.height = 36;
  opt.spp = 4;
  opt.shadow = "none";
  const Frame plain = test::renderFrame(r, *scene, opt);
  opt.msaa = 4;
  const Frame f = test::renderFrame(r, *scene, opt);
  EXPECT_EQ(test::bytes(f.color), test::bytes(plain.color));
  EXPECT_NE(f.stats.report().find("not applied"), std::string::npos);
  opt.msaa = 3;
  EXPECT_FALSE(r.render(*scene, opt).ok());
}

}  // namespace
}  // namespace penumbra::engine
