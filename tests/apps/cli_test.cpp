// End-to-end tests of the `penumbra` command line: bad input gets one line naming the problem,
// exit status 2 and no output file; good input works.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct CliResult {
  int status = -1;
  std::string out;  // stdout and stderr together
};

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

}  // namespace
