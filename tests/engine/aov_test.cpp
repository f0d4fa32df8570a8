// The frame's buffers as float EXRs (engine/aov.h): names and errors, channels and values read
// back, NaN on background, and the same bytes across thread counts and reruns.
#include "engine/aov.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "engine/builtin_scenes.h"
#include "engine/renderer.h"
#include "tests/engine/test_util.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;

std::string fileBytes(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Exr {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  std::vector<float> samples;
};
Exr readExr(const std::string& p) {
  Exr e;
  auto in = OIIO::ImageInput::open(p);
  if (!in) return e;
  const OIIO::ImageSpec& spec = in->spec();
  e.width = spec.width, e.height = spec.height, e.channels = spec.channelnames;
  e.samples.resize(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) * static_cast<size_t>(spec.nchannels));
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, e.samples.data());
  in->close();
  return e;
}

constexpr const char* kAllAovs =
    "visibility,depth,position,normal,geometric-normal,albedo,instance,triangle,barycentrics";

TEST(Aov, NamesParseAndErrorsNameTheOption) {
  const Result<std::vector<Aov>> all = parseAovList(kAllAovs);
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->size(), 9u);
  EXPECT_EQ(aovName((*all)[4]), std::string("geometric-normal"));
  for (const char* bad : {"", "visibility,", "colour", "depth,depth"}) {
    const Result<std::vector<Aov>> r = parseAovList(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error().line().find("--aov"), std::string::npos) << r.error().line();
  }
  EXPECT_EQ(aovPaths("out/f", {Aov::Depth, Aov::Visibility}, 3),
            (std::vector<std::string>{"out/f.depth.exr", "out/f.visibility.exr", "out/f.visibility-1.exr",
                                      "out/f.visibility-2.exr"}));
}

class AovFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra-aov-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(AovFiles, ChannelsValuesAndNanOnBackground) {
  Result<Scene> scene = makeBuiltinScene("creature");
  ASSERT_TRUE(scene.ok());
  Renderer r(2);
  RenderOptions opt;
  opt.width = 64;
  opt.height = 40;
  opt.shadow = "mvr";
  opt.shadowParams = {"views=8"};
  const Frame f = test::renderFrame(r, *scene, opt);
  const std::vector<Aov> all = *parseAovList(kAllAovs);
  const std::string prefix = (dir_ / "f").string();
  ASSERT_TRUE(writeAovs(f, all, prefix).ok());
  size_t background = 0, receivers = 0;
  const Exr vis = readExr(prefix + ".visibility.exr"), depth = readExr(prefix + ".depth.exr"),
            pos = readExr(prefix + ".position.exr"), gn = readExr(prefix + ".geometric-normal.exr"),
            inst = readExr(prefix + ".instance.exr"), tri = readExr(prefix + ".triangle.exr"),
            bary = readExr(prefix + ".barycentrics.exr");
  ASSERT_EQ(vis.width, 64);
  ASSERT_EQ(vis.height, 40);
  EXPECT_EQ(vis.channels, std::vector<std::string>{"Y"});
  EXPECT_EQ(pos.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 64; ++x) {
      const size_t i = static_cast<size_t>(y) * 64 + static_cast<size_t>(x);
      const GBufferTexel& t = f.gbuffer.at(x, y);
      if (t.material < 0) {
        ++background;
        EXPECT_TRUE(std::isnan(vis.samples[i]) && std::isnan(depth.samples[i]) && std::isnan(pos.samples[3 * i]) &&
                    std::isnan(inst.samples[i]));
        continue;
      }
      ++receivers;
      EXPECT_EQ(vis.samples[i], f.visibility[0].at(x, y));
      EXPECT_EQ(pos.samples[3 * i + 1], t.position.y);
      EXPECT_EQ(gn.samples[3 * i + 2], t.geometricNormal.z);
      EXPECT_EQ(inst.samples[i], static_cast<float>(t.instance));
      EXPECT_GT(depth.samples[i], 0.0f);
      // The triangle and its barycentrics give back the world position.
      EXPECT_EQ(tri.samples[i], static_cast<float>(t.triangle));
      const Instance& in = scene->instances[static_cast<size_t>(t.instance)];
      const Mesh& mesh = scene->meshes[static_cast<size_t>(in.mesh)];
      ASSERT_LT(static_cast<size_t>(t.triangle) * 3 + 2, mesh.indices.size());
      glm::vec3 rebuilt(0.0f);
      float sum = 0.0f;
      for (int k = 0; k < 3; ++k) {
        const float b = bary.samples[3 * i + static_cast<size_t>(k)];
        EXPECT_GE(b, -1e-4f);
        sum += b;
        const uint32_t v = mesh.indices[static_cast<size_t>(t.triangle) * 3 + static_cast<size_t>(k)];
        rebuilt += b * glm::vec3(in.transform * glm::vec4(mesh.positions[v], 1.0f));
      }
      EXPECT_NEAR(sum, 1.0f, 1e-4f);
      EXPECT_LT(glm::length(rebuilt - t.position), 1e-3f * (1.0f + glm::length(t.position)));
      // The geometric normal is a unit face normal facing the camera.
      const glm::vec3 n(gn.samples[3 * i], gn.samples[3 * i + 1], gn.samples[3 * i + 2]);
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
      EXPECT_GE(glm::dot(n, f.stats.camera.eye - t.position), 0.0f);
    }
  EXPECT_GT(background, 100u);
  EXPECT_GT(receivers, 1000u);
}

TEST_F(AovFiles, SameBytesAcrossThreadCountsAndReruns) {
  Result<Scene> scene = makeBuiltinScene("knot");
  ASSERT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 48;
  opt.height = 32;
  opt.shadow = "pcss";
  const std::vector<Aov> all = *parseAovList(kAllAovs);
  std::vector<std::string> first;
  for (int threads : {1, 3, 3}) {
    Renderer r(threads);
    const Frame f = test::renderFrame(r, *scene, opt);
    const std::string prefix = (dir_ / ("t" + std::to_string(threads))).string();
    ASSERT_TRUE(writeAovs(f, all, prefix).ok());
    std::vector<std::string> bytes;
    for (const std::string& p : aovPaths(prefix, all, f.visibility.size())) bytes.push_back(fileBytes(p));
    if (first.empty()) first = bytes;
    else EXPECT_EQ(bytes, first) << threads << " threads";
  }
}

TEST_F(AovFiles, AFailedWriteLeavesNothing) {
  Result<Scene> scene = makeBuiltinScene("contact");
  ASSERT_TRUE(scene.ok());
  Renderer r(2);
  RenderOptions opt;
  opt.width = 16;
  opt.height = 16;
  opt.shadow = "none";
  const Frame f = test::renderFrame(r, *scene, opt);
  // The third file cannot be written (a folder is in its place): the first two are removed.
  fs::create_directories(dir_ / "f.normal.exr");
  const Status st = writeAovs(f, *parseAovList("depth,position,normal"), (dir_ / "f").string());
  EXPECT_FALSE(st.ok());
  EXPECT_FALSE(fs::exists(dir_ / "f.depth.exr"));
  EXPECT_FALSE(fs::exists(dir_ / "f.position.exr"));
}

}  // namespace
}  // namespace penumbra::engine
