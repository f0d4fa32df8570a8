// End-to-end tests of the `penumbra` command line: bad input gets one line naming the problem,
// exit status 2 and no output file; good input works.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "apps/point_cloud.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/texture.h"

namespace {

namespace fs = std::filesystem;

struct CliResult {
  int status = -1;
  std::string out;  // stdout and stderr together
};

std::string readText(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CliResult run(const std::string& args) {
  const std::string cmd = std::string(PENUMBRA_BIN) + " " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra_cli_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name), std::ios::binary) << text; }
  // Exactly one line of output naming `mention`, status 2, and nothing written to `out`.
  void expectBadInput(const std::string& args, const std::string& mention, const std::string& out) const {
    const CliResult r = run(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(mention), std::string::npos) << "expected '" << mention << "' in: " << r.out;
    const auto lines = std::count(r.out.begin(), r.out.end(), '\n');
    EXPECT_EQ(lines, 1) << "not one line: " << r.out;
    EXPECT_FALSE(fs::exists(out)) << out;
    // No temporary left behind either.
    for (const auto& e : fs::directory_iterator(dir_)) {
      const auto ext = e.path().extension();
      EXPECT_TRUE(ext != ".png" && ext != ".exr") << "left behind: " << e.path();
    }
  }
  fs::path dir_;
};

std::string base64(const std::vector<uint8_t>& d) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < d.size(); i += 3) {
    const uint32_t v = (uint32_t{d[i]} << 16) | (i + 1 < d.size() ? uint32_t{d[i + 1]} << 8 : 0) |
                       (i + 2 < d.size() ? uint32_t{d[i + 2]} : 0);
    s += t[(v >> 18) & 63];
    s += t[(v >> 12) & 63];
    s += i + 1 < d.size() ? t[(v >> 6) & 63] : '=';
    s += i + 2 < d.size() ? t[v & 63] : '=';
  }
  return s;
}

// A one-triangle glTF: positions (3 floats each) then u16 indices, in a data-URI buffer.
std::string gltfTriangle(std::array<float, 9> pos, std::array<uint16_t, 3> idx, const std::string& extra = "") {
  std::vector<uint8_t> bin(36 + 6 + 2, 0);
  std::memcpy(bin.data(), pos.data(), 36);
  std::memcpy(bin.data() + 36, idx.data(), 6);
  const std::string minmax = "\"min\":[0,0,0],\"max\":[1,1,0]";
  return "{\"asset\":{\"version\":\"2.0\"}," + extra +
         "\"buffers\":[{\"byteLength\":44,\"uri\":\"data:application/octet-stream;base64," + base64(bin) + "\"}],"
         "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":6}],"
         "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"," + minmax + "},"
         "{\"bufferView\":1,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}],"
         "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
         "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
}

TEST_F(Cli, RendersTheDefaultSceneAndAGltfFile) {
  CliResult r = run("render --width 96 --height 64 -o " + path("a.png"));
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::exists(path("a.png")));
  EXPECT_NE(r.out.find("wrote"), std::string::npos);
  write("tri.gltf", gltfTriangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}));
  r = run("render " + path("tri.gltf") + " --width 32 --height 32 --stats -o " + path("t.png"));
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::exists(path("t.png")));
  EXPECT_NE(r.out.find("G-buffer pass"), std::string::npos) << r.out;
}

TEST_F(Cli, RendersTheSceneFilesOfTheRepository) {
  for (const auto& e : fs::directory_iterator(fs::path(PENUMBRA_SOURCE_DIR) / "scenes")) {
    if (e.path().extension() != ".json") continue;
    const std::string out = path(e.path().stem().string() + ".png");
    const CliResult r = run("render " + e.path().string() + " --width 64 --height 48 --exr " + path("x.exr") + " -o " + out);
    EXPECT_EQ(r.status, 0) << e.path() << "\n" << r.out;
    EXPECT_TRUE(fs::exists(out)) << out;
    EXPECT_TRUE(fs::exists(path("x.exr")));
  }
}

TEST_F(Cli, MissingFile) { expectBadInput("render " + path("nope.glb") + " -o " + path("o.png"), "nope.glb", path("o.png")); }

TEST_F(Cli, MalformedFiles) {
  write("garbage.glb", "this is not a glb file at all");
  expectBadInput("render " + path("garbage.glb") + " -o " + path("o.png"), "garbage.glb", path("o.png"));
  write("garbage.gltf", "{ not json");
  expectBadInput("render " + path("garbage.gltf") + " -o " + path("o.png"), "garbage.gltf", path("o.png"));
  write("scene.json", "{\"objects\": [{\"shape\": \"sphere\", \"radius\": -1}]}");
  expectBadInput("render " + path("scene.json") + " -o " + path("o.png"), "scene.json", path("o.png"));
  write("scene.txt", "hello");
  expectBadInput("render " + path("scene.txt") + " -o " + path("o.png"), "scene.txt", path("o.png"));
}

TEST_F(Cli, GltfWithOutOfRangeIndices) {
  write("bad.gltf", gltfTriangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 7}));
  expectBadInput("render " + path("bad.gltf") + " -o " + path("o.png"), "bad.gltf", path("o.png"));
}

TEST_F(Cli, GltfWithUnsupportedRequiredExtension) {
  write("ext.gltf", gltfTriangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2},
                                 "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                                 "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],"));
  expectBadInput("render " + path("ext.gltf") + " -o " + path("o.png"), "KHR_draco_mesh_compression", path("o.png"));
}

TEST_F(Cli, GltfWithNonFinitePositions) {
  const float nan = std::nanf(""), inf = INFINITY;
  write("nan.gltf", gltfTriangle({0, 0, 0, nan, 0, 0, 0, 1, 0}, {0, 1, 2}));
  expectBadInput("render " + path("nan.gltf") + " -o " + path("o.png"), "nan.gltf", path("o.png"));
  write("inf.gltf", gltfTriangle({0, 0, 0, 1, inf, 0, 0, 1, 0}, {0, 1, 2}));
  expectBadInput("render " + path("inf.gltf") + " -o " + path("o.png"), "inf.gltf", path("o.png"));
}

TEST_F(Cli, BadOptions) {
  const std::string o = path("o.png");
  expectBadInput("render --width 0 -o " + o, "--width", o);
  expectBadInput("render --height 100000 -o " + o, "--height", o);
  expectBadInput("render --width -5 -o " + o, "--width", o);
  expectBadInput("render --bogus -o " + o, "bogus", o);
  expectBadInput("render --builtin nosuchscene -o " + o, "nosuchscene", o);
  expectBadInput("render --eye 1,2 -o " + o, "--eye", o);
  expectBadInput("render --fov 200 -o " + o, "--fov", o);
  expectBadInput("render --fov 0 -o " + o, "--fov", o);
  // An empty output name is an error, not the default name (run in the test's folder).
  expectBadInput("render --width 8 --height 8 -o ''", "--output", "default.png");
  EXPECT_FALSE(fs::exists("default.png"));
  expectBadInput("render --threads -1 -o " + o, "--threads", o);
  expectBadInput("render -o " + path("o.jpgx"), "o.jpgx", path("o.jpgx"));
  expectBadInput("bench raster --synth 100 --frames 1", "--synth", o);
  expectBadInput("frobnicate", "frobnicate", o);
}

TEST_F(Cli, UnwritableOutputLeavesNothing) {
  const std::string o = path("no/such/dir/o.png");
  expectBadInput("render --width 16 --height 16 -o " + o, "o.png", o);
  // The EXR can be written but the PNG cannot: neither is left behind.
  expectBadInput("render --width 16 --height 16 --exr " + path("x.exr") + " -o " + o, "o.png", o);
  EXPECT_FALSE(fs::exists(path("x.exr")));
  // The PNG could be written but the EXR cannot: nothing written.
  expectBadInput("render --width 16 --height 16 --exr " + path("no/dir/x.exr") + " -o " + path("ok.png"), "x.exr",
                 path("ok.png"));
}

// A PNG render never loads the image module (OpenImageIO: engine/image_module.h); an EXR needs it,
// and without it the render is a one-line error naming the module, with nothing written.
TEST_F(Cli, PngNeedsNoImageModuleAndAMissingOneIsAnError) {
  const std::string absent = path("absent-module.so");
  ASSERT_EQ(::setenv("PENUMBRA_IMAGE_MODULE", absent.c_str(), 1), 0);
  const std::string o = path("b.png");
  expectBadInput("render --width 32 --height 24 --exr " + path("b.exr") + " -o " + o, "absent-module.so", o);
  const CliResult png = run("render --width 32 --height 24 -o " + path("a.png"));
  ::unsetenv("PENUMBRA_IMAGE_MODULE");
  EXPECT_FALSE(fs::exists(path("b.exr")));
  EXPECT_EQ(png.status, 0) << png.out;
  ASSERT_TRUE(fs::exists(path("a.png")));
  const auto back = penumbra::engine::readImageRgba8(path("a.png"));
  ASSERT_TRUE(back.ok()) << back.error().line();
  EXPECT_EQ(back->width(), 32);
}

// The module is never taken from the folder the process runs in: started as ./penumbra (a
// relative argv[0]) beside a planted libpenumbra_image_oiio.so, the render loads the real one.
TEST_F(Cli, ImageModuleIsNotLoadedFromTheWorkingFolder) {
  write("libpenumbra_image_oiio.so", "not a library");
  fs::create_symlink(PENUMBRA_BIN, path("penumbra"));
  const std::string cmd = "cd " + dir_.string() + " && ./penumbra render --width 16 --height 16 --exr " +
                          path("p.exr") + " -o " + path("p.png") + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 512> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int st = pclose(p);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << out;
  EXPECT_TRUE(fs::exists(path("p.exr"))) << out;
}

TEST_F(Cli, AovBuffersAndTheirErrors) {
  const CliResult r = run("render --builtin knot --width 48 --height 32 --shadow pcss --aov visibility,instance --aov-out " +
                          path("k") + " -o " + path("k.png"));
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::exists(path("k.visibility.exr")));
  EXPECT_TRUE(fs::exists(path("k.instance.exr")));
  EXPECT_NE(r.out.find("2 buffers"), std::string::npos) << r.out;
  for (const char* f : {"k.visibility.exr", "k.instance.exr", "k.png"}) fs::remove(path(f));  // the checks below want none
  // The buffer they are written from is in the memory estimate, before any work.
  const CliResult big = run("render --width 16384 --height 8192 --aov depth --aov-out " + path("b") +
                            " --max-memory 4G -o " + path("b.png"));
  EXPECT_EQ(big.status, 2) << big.out;
  EXPECT_NE(big.out.find("AOV buffer"), std::string::npos) << big.out;
  const std::string o = path("o.png");
  expectBadInput("render --width 16 --height 16 --aov colour --aov-out " + path("a") + " -o " + o, "--aov", o);
  expectBadInput("render --width 16 --height 16 --aov depth -o " + o, "--aov-out", o);
  expectBadInput("render --width 16 --height 16 --aov-out " + path("a") + " -o " + o, "--aov", o);
  expectBadInput("render --width 16 --height 16 --aov depth --aov-out " + path("no/dir/a") + " -o " + o, "a.exr", o);
}

TEST_F(Cli, BenchRasterPrintsTheWorkloadFields) {
  const CliResult r = run("bench raster --synth 2048 --threads 1 --frames 1 --min-time 0 --json");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* field : {"\"name\":\"synth2048\"", "\"tris\":", "\"workload\":\"W1\"", "\"workload\":\"W2\"",
                            "\"res\":\"2048x2048\"", "\"res\":\"1920x1080\"", "\"threads\":1", "\"median_ms\":",
                            "\"min_ms\":", "\"max_ms\":", "\"mtris_per_s\":"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " in " << r.out;
}

TEST_F(Cli, StressPassesAndPrintsATable) {
  const CliResult r = run("stress --threads 2");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("far from origin"), std::string::npos);
  EXPECT_NE(r.out.find("0 broken"), std::string::npos) << r.out;
}

// --- render --points and bench points ---------------------------------------------------------

// The pixels of a PNG that differ from `background`, as packed 0xAABBGGRR.
std::vector<uint32_t> nonBackground(const std::string& png, penumbra::raster::Rgba8 background) {
  const auto img = penumbra::engine::readImageRgba8(png);
  EXPECT_TRUE(img.ok()) << png;
  std::vector<uint32_t> out;
  if (!img.ok()) return out;
  for (int y = 0; y < img.value().height(); ++y)
    for (int x = 0; x < img.value().width(); ++x) {
      const penumbra::raster::Rgba8 c = img.value().at(x, y);
      if (!(c == background))
        out.push_back(uint32_t{c.r} | (uint32_t{c.g} << 8) | (uint32_t{c.b} << 16) | (uint32_t{c.a} << 24));
    }
  return out;
}

penumbra::raster::Rgba8 defaultBackground() {
  const auto scene = penumbra::engine::makeBuiltinScene(penumbra::engine::kDefaultScene);
  const glm::vec3 bg = scene.value().background;
  using penumbra::engine::linearToSrgb;
  return {linearToSrgb(bg.x), linearToSrgb(bg.y), linearToSrgb(bg.z), 255};
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The sampler behind render --points and bench points, called directly: two triangles of world
// areas 1 and 3 (an instance scaled by 2 in x) get 1/4 and 3/4 of the points, within 4 sigma of
// the binomial; every point lies in its triangle; the mean of a triangle's points is its centroid;
// the same points at 1 and 2 threads.
TEST(PointCloud, SamplesUniformlyByArea) {
  penumbra::engine::Scene scene;
  penumbra::engine::Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {3, 0, 1}, {0, 1, 1}};
  mesh.normals.assign(6, glm::vec3(0, 0, 1));
  mesh.indices = {0, 1, 2, 3, 4, 5};
  scene.meshes.push_back(mesh);
  scene.instances.push_back({"i", 0, glm::mat4(glm::vec4(2, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0),
                                               glm::vec4(0, 0, 0, 1))});
  constexpr int64_t n = 100000;
  auto sample = [&](int threads) {
    return tbb::task_arena(threads).execute([&] { return penumbra::apps::sampleSurface(scene, n, true); });
  };
  const auto one = sample(1), two = sample(2);
  ASSERT_TRUE(one.ok() && two.ok());
  EXPECT_EQ(one.value().positions, two.value().positions);
  int64_t upper = 0;
  glm::dvec2 sum0(0.0);
  for (const glm::vec3& p : one.value().positions) {
    const bool top = p.z > 0.5f;
    ASSERT_NEAR(p.z, top ? 1.0f : 0.0f, 1e-6f);
    const float u = p.x / (top ? 6.0f : 2.0f), v = p.y;  // barycentrics of the world triangle
    ASSERT_TRUE(u >= 0.0f && v >= 0.0f && u + v <= 1.0f + 1e-6f) << p.x << " " << p.y;
    if (top) ++upper;
    else sum0 += glm::dvec2(p.x, p.y);
  }
  const double sigma = std::sqrt(0.75 * 0.25 / n);
  EXPECT_NEAR(static_cast<double>(upper) / n, 0.75, 4 * sigma);
  const double lower = static_cast<double>(n - upper);
  EXPECT_NEAR(sum0.x / lower, 2.0 / 3.0, 0.015);
  EXPECT_NEAR(sum0.y / lower, 1.0 / 3.0, 0.01);
}

TEST_F(Cli, RenderPointsOfTheDefaultScene) {
  const std::string args = "render --points --point-count 100000 --width 96 --height 64 ";
  CliResult r = run(args + "--threads 1 --stats -o " + path("p1.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("points: 100000 sampled"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("splat: written"), std::string::npos) << r.out;
  // The scene fills most of the view: many points land, and the background shows between them.
  const size_t covered = nonBackground(path("p1.png"), defaultBackground()).size();
  EXPECT_GT(covered, 96u * 64u / 4) << r.out;
  EXPECT_LT(covered, 96u * 64u) << r.out;
  // The same bytes at 2 threads.
  r = run(args + "--threads 2 -o " + path("p2.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(readAll(path("p1.png")), readAll(path("p2.png")));
}

TEST_F(Cli, RenderPointsFromAnXyzFile) {
  write("three.xyz", "# three colored points\n\n0 0 0 255 0 0\r\n  1 0 0\t0 255 0\n0 1 0 0 0 255\n");
  const CliResult r = run("render --points --points-file " + path("three.xyz") + " --width 64 --height 64 -o " +
                          path("three.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  // The camera is fitted to the points: each lands in its own pixel with its own color.
  std::vector<uint32_t> px = nonBackground(path("three.png"), defaultBackground());
  std::sort(px.begin(), px.end());
  EXPECT_EQ(px, (std::vector<uint32_t>{0xFF0000FFu, 0xFF00FF00u, 0xFFFF0000u}));
}

TEST_F(Cli, RenderPointsRejectsMalformedFilesAndOptions) {
  const std::string o = path("o.png");
  const std::string render = "render --points --width 16 --height 16 -o " + o + " --points-file ";
  write("bad.xyz", "# header\n0 0 0\n1 2 abc\n3 4 5\n");
  expectBadInput(render + path("bad.xyz"), "bad.xyz: line 3", o);
  write("color.xyz", "0 0 0 1 2 3\n0 0 1 1 256 3\n");
  expectBadInput(render + path("color.xyz"), "color.xyz: line 2", o);
  write("inf.xyz", "\n\n0 0 inf 1 2 3\n");
  expectBadInput(render + path("inf.xyz"), "inf.xyz: line 3", o);
  expectBadInput("render --points --point-count 0 -o " + o, "--point-count", o);
  expectBadInput("render --point-count 10 -o " + o, "--point-count", o);
  expectBadInput("render --points --exr " + path("x.exr") + " -o " + o, "--exr", o);
}

// An output that is one of the run's inputs is refused before anything is written.
TEST_F(Cli, OutputsNeverOverwriteInputs) {
  write("pts.png", "0 0 0\n1 1 1\n");  // a points file with a .png name
  CliResult r = run("render --points --points-file " + path("pts.png") + " --width 8 --height 8 -o " + path("pts.png"));
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("refusing to overwrite"), std::string::npos) << r.out;
  EXPECT_EQ(readText(path("pts.png")), "0 0 0\n1 1 1\n");
  // A scene file as the EXR (a link to it counts too).
  write("s.json", "{\"objects\": [{\"shape\": \"box\"}]}");
  fs::create_symlink(path("s.json"), path("s.exr"));
  r = run("render " + path("s.json") + " --width 8 --height 8 --exr " + path("s.exr") + " -o " + path("o.png"));
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("refusing to overwrite"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("o.png")));
}

TEST_F(Cli, XyzMagnitudesAreJudgedAsFloats) {
  const std::string o = path("o.png");
  write("tiny.xyz", "1e-50 0 0\n1e-39 0 1\n1e-400 1 0\n");
  const CliResult r = run("render --points --width 8 --height 8 -o " + o + " --points-file " + path("tiny.xyz"));
  EXPECT_EQ(r.status, 0) << r.out;  // all three tiny values are (almost) 0, alike
  fs::remove(o);
  write("big.xyz", "1e39 0 0\n");
  expectBadInput("render --points --width 8 --height 8 -o " + path("b.png") + " --points-file " + path("big.xyz"),
                 "out of the float range", path("b.png"));
}

TEST_F(Cli, UnknownBenchSceneNamesTheOption) {
  expectBadInput("bench shadows --scene nosuch --out " + path("b"), "option --scene", path("o.png"));
  for (const char* scale : {"0", "-1", "65", "nan"})
    expectBadInput("bench shadows --light-scale " + std::string(scale) + " --out " + path("b"), "--light-scale",
                   path("o.png"));
  const CliResult r = run("bench shadows --scene nosuch --out " + path("b"));
  EXPECT_EQ(r.out.find("--builtin"), std::string::npos) << r.out;
}

// SIGTERM and SIGINT in the middle of a render: one line, exit 128 + signal, no file left (the
// output nor a temporary). The temporaries of a write in progress are removed by the same handler
// (tests/engine/atomic_file_test.cpp).
// Whether process pid has a handler for sig (Linux: the SigCgt mask of /proc/PID/status).
bool catches(pid_t pid, int sig) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("SigCgt:", 0) == 0) {
      const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
      return (mask >> (sig - 1)) & 1ULL;
    }
  return false;
}

TEST_F(Cli, SignalsLeaveNoFileAndExit128PlusTheSignal) {
  for (int sig : {SIGTERM, SIGINT}) {
    const std::string out = path("big.png"), log = path("log.txt");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execl(PENUMBRA_BIN, PENUMBRA_BIN, "render", "--builtin", "complex", "--width", "4096", "--height", "4096",
              "--shadow", "mvr", "-o", out.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Wait (at most 30 s: a loaded machine starts slowly) until the child catches the signal, so
    // that it is its handler, not the default action, that the test sees; then let it work a while.
    for (int i = 0; i < 600 && !catches(pid, sig); ++i) ::usleep(50 * 1000);
    ::usleep(500 * 1000);
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    const std::string text = readText(log);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
    EXPECT_NE(text.find(sig == SIGTERM ? "terminated (SIGTERM)" : "interrupted (SIGINT)"), std::string::npos) << text;
    fs::remove(log);
    for (const auto& e : fs::directory_iterator(dir_)) ADD_FAILURE() << "left behind: " << e.path();
  }
}

// A frame estimated beyond the memory limit is refused at once, before any allocation.
TEST_F(Cli, FrameBeyondTheMemoryLimitIsRefused) {
  const std::string o = path("o.png");
  expectBadInput("render --width 16384 --height 16384 --max-memory 1G -o " + o, "--max-memory", o);
  expectBadInput("render --points --point-count 60000000 --max-memory 100M -o " + o, "--max-memory", o);
  expectBadInput("render --max-memory 12X -o " + o, "--max-memory", o);
  // A scene file whose procedural shapes would exceed the triangle cap: refused before they are built.
  write("many.json", "{\"objects\": [{\"shape\": \"plane\", \"divisions\": 4096}, {\"shape\": \"plane\", \"divisions\": 4096},"
                     " {\"shape\": \"plane\", \"divisions\": 4096}]}");
  expectBadInput("render " + path("many.json") + " -o " + o, "objects[2]: the scene's shapes exceed", o);
}

// A glTF without lights (most real files) is lit by default, and says so; the camera is printed.
TEST_F(Cli, LightlessGltfGetsADefaultLightAndStatsShowTheCamera) {
  write("tri.gltf", gltfTriangle({-1, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}));
  CliResult r = run("render " + path("tri.gltf") + " --width 32 --height 32 --stats -o " + path("t.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("default key area light"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("area light 0: pcss"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("camera fitted to the objects' bounds: eye ("), std::string::npos) << r.out;
  r = run("render " + path("tri.gltf") + " --no-default-light --width 32 --height 32 --stats -o " + path("t.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("default key area light"), std::string::npos) << r.out;
  fs::remove(path("t.png"));
  expectBadInput("render --tonemap filmic -o " + path("o.png"), "--tonemap", path("o.png"));
  expectBadInput("render --exposure 30 -o " + path("o.png"), "--exposure", path("o.png"));
}

TEST_F(Cli, Version) {
  const CliResult r = run("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("penumbra ", 0), 0u) << r.out;
}

TEST_F(Cli, BenchPointsPrintsOneJsonObjectPerRun) {
  const CliResult r = run("bench points --points 100000 --views 1,4 --runs 1 --json");
  ASSERT_EQ(r.status, 0) << r.out;
  std::set<std::pair<int, int>> seen;  // (views, threads)
  std::stringstream lines(r.out);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '{') continue;
    const nlohmann::json j = nlohmann::json::parse(line);
    for (const char* key : {"points", "views", "threads", "ms_median", "mpoints_per_s", "mpointviews_per_s",
                            "bytes_per_pointview", "bound_mpointviews_per_s", "fraction_of_bound", "written_fraction"})
      EXPECT_TRUE(j.contains(key)) << key << " in " << line;
    EXPECT_EQ(j["points"].get<int>(), 100000);
    const int views = j["views"].get<int>();
    seen.insert({views, j["threads"].get<int>()});
    // Every point lands in every view, so the model's bytes are 12 / M + 8 or 64.
    EXPECT_DOUBLE_EQ(j["written_fraction"].get<double>(), 1.0) << line;
    const double bytes = j["bytes_per_pointview"].get<double>();
    EXPECT_TRUE(std::abs(bytes - (12.0 / views + 8.0)) < 1e-3 || std::abs(bytes - (12.0 / views + 64.0)) < 1e-3)
        << line;
    EXPECT_GT(j["mpointviews_per_s"].get<double>(), 0.0);
    EXPECT_NEAR(j["mpointviews_per_s"].get<double>(), views * j["mpoints_per_s"].get<double>(), 0.01 * views + 0.01);
    EXPECT_GT(j["bound_mpointviews_per_s"].get<double>(), 0.0);
  }
  EXPECT_EQ(seen, (std::set<std::pair<int, int>>{{1, 1}, {1, 2}, {4, 1}, {4, 2}})) << r.out;
}

TEST_F(Cli, RendersTheStochasticScenesAndShowsThePlan) {
  for (const char* scene : {"motion", "defocus", "motion-defocus"}) {
    const std::string out = path(std::string(scene) + ".png");
    const CliResult r = run(std::string("render --builtin ") + scene + " --width 64 --height 36 --spp 4 --stats -o " + out);
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_NE(r.out.find("stochastic pass (dual bounds, 4 spp)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("STE"), std::string::npos) << r.out;
  }
  const CliResult r = run("render --width 64 --height 36 --stats -o " + path("d.png"));
  EXPECT_NE(r.out.find("skipped passes: stochastic pass (skipped: no visible instance moves and the camera is a pinhole)"),
            std::string::npos)
      << r.out;
}

TEST_F(Cli, StochasticBadOptions) {
  const std::string o = path("o.png");
  expectBadInput("render --builtin motion --spp 0 -o " + o, "--spp", o);
  expectBadInput("render --builtin motion --spp 65 -o " + o, "--spp", o);
  expectBadInput("render --builtin motion --bounds sphere -o " + o, "--bounds", o);
  expectBadInput("render --builtin motion --strata 0 -o " + o, "--strata", o);
  expectBadInput("render --builtin motion --strata 4,9 -o " + o, "--strata", o);
  expectBadInput("render --builtin motion --dual-block 3 -o " + o, "--dual-block", o);
  expectBadInput("render --builtin motion --aperture -2 -o " + o, "--aperture", o);
  // No value means "unset": each of these is out of range, not the default.
  expectBadInput("render --builtin motion --aperture -1 -o " + o, "--aperture", o);
  expectBadInput("render --builtin motion --focus -1 -o " + o, "--focus", o);
  expectBadInput("render --builtin motion --focus 0 -o " + o, "--focus", o);
  expectBadInput("render --builtin motion --strata 4, -o " + o, "--strata", o);
  expectBadInput("render --builtin motion --strata 4,2x -o " + o, "--strata", o);
  expectBadInput("explain shadows", "shadows", o);
  expectBadInput("bench stochastic --spp 0 --out " + path("b"), "--spp", o);
  expectBadInput("bench stochastic --method sphere --out " + path("b"), "sphere", o);
}

TEST_F(Cli, BenchStochasticPrintsOneJsonObjectPerRun) {
  const std::string out = path("bench");
  const CliResult r = run("bench stochastic --scene motion --spp 1,2 --runs 1 --ref-frames 4 --width 48 --height 27 --out " +
                          out + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  std::set<std::pair<std::string, int>> seen;
  std::stringstream lines(r.out);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '{') continue;
    const nlohmann::json j = nlohmann::json::parse(line);
    for (const char* key : {"scene", "method", "spp", "ms", "tests", "hits", "ste", "rmse"})
      EXPECT_TRUE(j.contains(key)) << key << " in " << line;
    EXPECT_EQ(j["scene"].get<std::string>(), "motion");
    EXPECT_LE(j["hits"].get<uint64_t>(), j["tests"].get<uint64_t>());
    if (j["static_path"].get<bool>()) seen.insert({j["method"].get<std::string>(), j["spp"].get<int>()});
    ++rows;
  }
  EXPECT_EQ(rows, 7) << r.out;  // 3 methods x 2 sample counts, and the frame without the ordinary path
  EXPECT_EQ(seen.size(), 6u);
  for (const char* f : {"results.json", "results.csv", "index.html", "pareto-motion.svg", "motion-reference.png",
                        "motion-dual-2.png", "motion-box-1-tests.png"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
}

TEST_F(Cli, ExplainStochasticWritesItsPictures) {
  const std::string out = path("explain");
  const CliResult r = run("explain stochastic --spp 2 --out " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* f : {"samples-xt.png", "samples-uv.png", "footprint-bounds.png", "tests-box.png", "tests-interval.png",
                        "tests-dual.png"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
}

TEST_F(Cli, BenchPointsBadOptions) {
  const std::string o = path("o.png");
  expectBadInput("bench points --views 1,0", "--views", o);
  expectBadInput("bench points --views 1024 --size 4096", "--views/--size", o);
}

}  // namespace
