// glTF loading against fixtures this test writes: .gltf with data-URI and external buffers and
// images, .glb assembled byte by byte, every index type, strips and fans, node hierarchies, cameras,
// textures; then malformed files, each of which must give a one-line Error naming the file.
#include "engine/gltf_loader.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "engine/image_io.h"
#include "engine/texture.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kFloat = 5126, kU8 = 5121, kU16 = 5123, kU32 = 5125;

std::string base64(const std::vector<unsigned char>& data) {
  static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    const unsigned v = static_cast<unsigned>(data[i]) << 16 | (i + 1 < data.size() ? data[i + 1] << 8 : 0) |
                       (i + 2 < data.size() ? data[i + 2] : 0);
    out += alphabet[v >> 18 & 63];
    out += alphabet[v >> 12 & 63];
    out += i + 1 < data.size() ? alphabet[v >> 6 & 63] : '=';
    out += i + 2 < data.size() ? alphabet[v & 63] : '=';
  }
  return out;
}

// A glTF document under construction: JSON plus one binary buffer.
struct Gltf {
  json doc = {{"asset", {{"version", "2.0"}}},
              {"bufferViews", json::array()},
              {"accessors", json::array()},
              {"meshes", json::array()},
              {"nodes", json::array()}};
  std::vector<unsigned char> bin;

  int view(const void* data, size_t bytes, size_t stride = 0) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    const size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (stride != 0) v["byteStride"] = stride;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  template <class T>
  int view(const std::vector<T>& v) {
    return view(v.data(), v.size() * sizeof(T));
  }
  int accessor(int bufferView, int componentType, size_t count, const char* type, size_t offset = 0, bool normalized = false) {
    json a = {{"bufferView", bufferView}, {"componentType", componentType}, {"count", count}, {"type", type}};
    if (offset != 0) a["byteOffset"] = offset;
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  int positions(const std::vector<glm::vec3>& p) { return accessor(view(p), kFloat, p.size(), "VEC3"); }
  template <class T>
  int indices(const std::vector<T>& i, int componentType) {
    return accessor(view(i), componentType, i.size(), "SCALAR");
  }
  int mesh(const json& primitives) {
    doc["meshes"].push_back({{"primitives", primitives}});
    return static_cast<int>(doc["meshes"].size()) - 1;
  }
  int node(const json& n) {
    doc["nodes"].push_back(n);
    return static_cast<int>(doc["nodes"].size()) - 1;
  }
  // A scene holding just these nodes.
  void scene(const std::vector<int>& roots) { doc["scenes"] = json::array({{{"nodes", roots}}}); }

  std::string text() const {
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    return d.dump(1);
  }
  std::string textWithExternalBuffer(const std::string& uri) const {
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
    return d.dump();
  }
  // GLB container (glTF 2.0, 4.4): 12-byte header, JSON chunk padded with spaces, BIN chunk
  // padded with zeros, little-endian lengths.
  std::vector<unsigned char> glb() const {
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string js = d.dump();
    while (js.size() % 4 != 0) js += ' ';
    std::vector<unsigned char> b = bin;
    while (b.size() % 4 != 0) b.push_back(0);
    std::vector<unsigned char> out;
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    for (char c : {'g', 'l', 'T', 'F'}) out.push_back(static_cast<unsigned char>(c));
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + js.size() + 8 + b.size()));
    u32(static_cast<uint32_t>(js.size()));
    u32(0x4E4F534Au);  // "JSON"
    out.insert(out.end(), js.begin(), js.end());
    u32(static_cast<uint32_t>(b.size()));
    u32(0x004E4942u);  // "BIN\0"
    out.insert(out.end(), b.begin(), b.end());
    return out;
  }
};

// One triangle in the z = 0 plane, counter-clockwise seen from +z, u16 indices, one node.
Gltf triangle() {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int idx = g.indices(std::vector<uint16_t>{0, 1, 2}, kU16);
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
  g.node({{"mesh", 0}});
  g.scene({0});
  return g;
}

class GltfLoader : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra-gltf-" + std::to_string(::getpid()) + "-" +
                                        testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  std::string write(const std::string& name, const std::vector<unsigned char>& bytes) const {
    return write(name, std::string(bytes.begin(), bytes.end()));
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  Scene load(const std::string& file) {
    Result<Scene> r = loadGltf(file);
    EXPECT_TRUE(r.ok()) << r.error().line();
    return r.ok() ? std::move(*r) : Scene{};
  }
  // The corners of the mesh's triangles, in order: independent of how vertices are shared (without
  // NORMAL, the loader unshares vertices to give each triangle its flat normal).
  static std::vector<glm::vec3> corners(const Mesh& m) {
    std::vector<glm::vec3> c;
    for (uint32_t i : m.indices) c.push_back(m.positions[i]);
    return c;
  }
  static std::vector<glm::vec3> corners(const std::vector<glm::vec3>& pos, const std::vector<uint32_t>& idx) {
    std::vector<glm::vec3> c;
    for (uint32_t i : idx) c.push_back(pos[i]);
    return c;
  }
  // The error must be one line naming the file, and contain `expected`.
  void expectError(const std::string& file, const std::string& expected) {
    Result<Scene> r = loadGltf(file);
    ASSERT_FALSE(r.ok()) << file << " loaded but should not";
    EXPECT_EQ(r.error().where, file);
    EXPECT_EQ(r.error().line().find('\n'), std::string::npos) << r.error().line();
    EXPECT_NE(r.error().what.find(expected), std::string::npos) << "got: " << r.error().line();
  }

  fs::path dir_;
};

glm::vec3 worldOf(const Scene& s, size_t instance, glm::vec3 p) {
  return glm::vec3(s.instances[instance].transform * glm::vec4(p, 1.0f));
}

void expectVec(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST_F(GltfLoader, MinimalGltfWithDataUriBuffer) {
  const Scene s = load(write("tri.gltf", triangle().text()));
  EXPECT_EQ(s.name, "tri");
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.positions.size(), 3u);
  expectVec(m.positions[1], {1, 0, 0});
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
  // No NORMAL in the file: computed, facing +z for this winding.
  ASSERT_EQ(m.normals.size(), 3u);
  for (const glm::vec3& n : m.normals) expectVec(n, {0, 0, 1});
  EXPECT_TRUE(m.texcoords.empty());
  EXPECT_EQ(m.material, -1);
  expectVec(m.boundsMax, {1, 1, 0});
  EXPECT_EQ(s.instances[0].transform, glm::mat4(1.0f));
  EXPECT_FALSE(s.camera.has_value());
}

TEST_F(GltfLoader, ExternalBufferFile) {
  const Gltf g = triangle();
  write("tri.bin", g.bin);
  const Scene s = load(write("tri.gltf", g.textWithExternalBuffer("tri.bin")));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices.size(), 3u);
}

TEST_F(GltfLoader, GlbWrittenByteByByte) {
  const Scene s = load(write("tri.glb", triangle().glb()));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
  expectVec(s.meshes[0].positions[2], {0, 1, 0});
}

TEST_F(GltfLoader, EveryIndexComponentType) {
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<uint32_t> expected = {0, 1, 2, 0, 2, 3};
  for (int type : {kU8, kU16, kU32}) {
    SCOPED_TRACE(type);
    Gltf g;
    const int pos = g.positions(quad);
    int idx = 0;
    if (type == kU8) idx = g.indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3}, kU8);
    if (type == kU16) idx = g.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, kU16);
    if (type == kU32) idx = g.indices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3}, kU32);
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
    g.node({{"mesh", 0}});
    const Scene s = load(write("quad.gltf", g.text()));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(corners(s.meshes[0]), corners(quad, expected));
  }
  // Signed or float indices are not allowed.
  Gltf g;
  const int pos = g.positions(quad);
  const int idx = g.indices(std::vector<float>{0, 1, 2}, kFloat);
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
  g.node({{"mesh", 0}});
  expectError(write("float-indices.gltf", g.text()), "index accessor 1");
}

TEST_F(GltfLoader, MissingNormalsAreFlatPerTriangle) {
  // A folded quad (two triangles at 90 degrees sharing an edge) without NORMAL: each triangle gets
  // its own face normal (glTF 2.0 3.7.2.1), not a smoothed average at the shared vertices.
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const int idx = g.indices(std::vector<uint16_t>{0, 1, 2, 0, 3, 1}, kU16);
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
  g.node({{"mesh", 0}});
  const Scene s = load(write("fold.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 6u);
  for (int k = 0; k < 3; ++k) expectVec(m.normals[m.indices[static_cast<size_t>(k)]], {0, 0, 1});
  for (int k = 3; k < 6; ++k) expectVec(m.normals[m.indices[static_cast<size_t>(k)]], {0, 1, 0});
}

TEST_F(GltfLoader, NonIndexedPrimitive) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
  g.node({{"mesh", 0}});
  const Scene s = load(write("soup.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
}

TEST_F(GltfLoader, StripsAndFansBecomeTriangleLists) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}});
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"mode", 5}},    // strip
                      {{"attributes", {{"POSITION", pos}}}, {"mode", 6}}}));  // fan
  g.node({{"mesh", 0}});
  const Scene s = load(write("strip.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 2u);
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  // Strip: odd triangles swap their last two vertices, keeping one winding (glTF 2.0, 3.7.2.1).
  EXPECT_EQ(corners(s.meshes[0]), corners(p, {0, 1, 2, 1, 3, 2, 2, 3, 4}));
  // Fan: triangle i is (i + 1, i + 2, 0).
  EXPECT_EQ(corners(s.meshes[1]), corners(p, {1, 2, 0, 2, 3, 0, 3, 4, 0}));
  EXPECT_EQ(s.instances.size(), 2u);
}

TEST_F(GltfLoader, PointsAndLinesAreSkippedAndCounted) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"mode", 1}},
                      {{"attributes", {{"POSITION", pos}}}, {"mode", 4}},
                      {{"attributes", {{"POSITION", pos}}}, {"mode", 0}}}));
  g.node({{"mesh", 0}});
  GltfLoadStats stats;
  Result<Scene> r = loadGltf(write("mixed.gltf", g.text()), {}, stats);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(r->meshes.size(), 1u);
  EXPECT_EQ(r->instances.size(), 1u);
  EXPECT_EQ(stats.skippedPrimitives, 2);
}

TEST_F(GltfLoader, InterleavedAttributesAndNormalizedTexcoords) {
  // 3 vertices of 24 bytes: position (12), normal (12 is too many: use u16 uv (4) + u8 uv (2) + pad).
  struct Vertex {
    float p[3];
    uint16_t uv16[2];
    uint8_t uv8[2];
    uint8_t pad[2];
  };
  static_assert(sizeof(Vertex) == 20);
  const Vertex v[3] = {{{0, 0, 0}, {0, 65535}, {0, 255}, {}},
                       {{1, 0, 0}, {65535, 0}, {255, 0}, {}},
                       {{0, 1, 0}, {32768, 16384}, {51, 102}, {}}};
  Gltf g;
  const int view = g.view(v, sizeof(v), sizeof(Vertex));
  const int pos = g.accessor(view, kFloat, 3, "VEC3");
  const int uv16 = g.accessor(view, kU16, 3, "VEC2", 12, true);
  const int uv8 = g.accessor(view, kU8, 3, "VEC2", 16, true);
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv16}}}},
                      {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv8}}}}}));
  g.node({{"mesh", 0}});
  const Scene s = load(write("interleaved.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 2u);
  const Mesh& a = s.meshes[0];
  ASSERT_EQ(a.texcoords.size(), 3u);
  expectVec(a.positions[2], {0, 1, 0});
  EXPECT_NEAR(a.texcoords[0].y, 1.0f, 1e-7f);
  EXPECT_NEAR(a.texcoords[2].x, 32768.0f / 65535.0f, 1e-7f);
  EXPECT_NEAR(a.texcoords[2].y, 16384.0f / 65535.0f, 1e-7f);
  const Mesh& b = s.meshes[1];
  ASSERT_EQ(b.texcoords.size(), 3u);
  EXPECT_NEAR(b.texcoords[2].x, 0.2f, 1e-7f);
  EXPECT_NEAR(b.texcoords[2].y, 0.4f, 1e-7f);
  EXPECT_NEAR(b.texcoords[1].x, 1.0f, 1e-7f);
}

TEST_F(GltfLoader, NormalsFromTheFileAreKept) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int nrm = g.positions({{0, 0, 2}, {1, 0, 0}, {0, 1, 0}});  // not unit: normalized on load
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}}}));
  g.node({{"mesh", 0}});
  const Scene s = load(write("normals.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 1u);
  expectVec(s.meshes[0].normals[0], {0, 0, 1});
  expectVec(s.meshes[0].normals[1], {1, 0, 0});
}

TEST_F(GltfLoader, NodeHierarchyWithTrsAndMatrix) {
  Gltf g = triangle();
  g.doc["nodes"] = json::array();
  const double h = std::sqrt(0.5);
  // root: translate (1, 2, 3), rotate 90 degrees about +y, scale 2; child: matrix translating (1, 0, 0).
  g.node({{"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}, {"scale", {2, 2, 2}}, {"children", {1, 2}}});
  g.node({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}, {"mesh", 0}, {"name", "child"}});
  g.node({{"mesh", 0}, {"translation", {0, 0, 1}}});  // a second instance of the same mesh
  g.scene({0});
  const Scene s = load(write("hierarchy.gltf", g.text()));
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[0].name, "child");
  // T R S (1, 0, 0) = (1, 2, 3) + R_y(90)(2, 0, 0) = (1, 2, 3) + (0, 0, -2).
  expectVec(worldOf(s, 0, {0, 0, 0}), {1, 2, 1});
  expectVec(worldOf(s, 0, {0, 1, 0}), {1, 4, 1});
  expectVec(worldOf(s, 0, {1, 0, 0}), {1, 2, -1});
  // T R S (0, 0, 1) = (1, 2, 3) + R_y(90)(0, 0, 2) = (1, 2, 3) + (2, 0, 0).
  expectVec(worldOf(s, 1, {0, 0, 0}), {3, 2, 3});
  EXPECT_EQ(s.instances[0].mesh, s.instances[1].mesh);
  glm::vec3 lo, hi;
  ASSERT_TRUE(s.worldBounds(lo, hi));
  expectVec(lo, {1, 2, -1});
}

TEST_F(GltfLoader, DefaultSceneAndRootNodes) {
  Gltf g = triangle();
  g.doc["nodes"] = json::array();
  g.node({{"mesh", 0}, {"translation", {5, 0, 0}}});
  g.node({{"mesh", 0}, {"translation", {7, 0, 0}}});
  g.doc["scenes"] = json::array({{{"nodes", {0}}}, {{"nodes", {1}}}});
  g.doc["scene"] = 1;
  Scene s = load(write("default.gltf", g.text()));
  ASSERT_EQ(s.instances.size(), 1u);
  expectVec(worldOf(s, 0, {0, 0, 0}), {7, 0, 0});
  // No "scene": scene 0.
  g.doc.erase("scene");
  s = load(write("first.gltf", g.text()));
  ASSERT_EQ(s.instances.size(), 1u);
  expectVec(worldOf(s, 0, {0, 0, 0}), {5, 0, 0});
  // No scenes at all: every root node.
  g.doc.erase("scenes");
  g.node({{"children", {0}}, {"translation", {0, 1, 0}}});
  s = load(write("roots.gltf", g.text()));
  ASSERT_EQ(s.instances.size(), 2u);
  expectVec(worldOf(s, 0, {0, 0, 0}), {7, 0, 0});
  expectVec(worldOf(s, 1, {0, 0, 0}), {5, 1, 0});
}

TEST_F(GltfLoader, FirstPerspectiveCameraBecomesTheSceneCamera) {
  Gltf g = triangle();
  const double h = std::sqrt(0.5);
  g.doc["cameras"] = json::array({{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                                  {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}},
                                  {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 1}, {"zfar", 50}}}}});
  g.node({{"camera", 0}});                                                              // orthographic: skipped
  g.node({{"camera", 1}, {"translation", {0, 1, 5}}, {"rotation", {0, h, 0, h}}});  // looks down -x
  g.node({{"camera", 2}});
  g.scene({0, 1, 2, 3});
  const Scene s = load(write("camera.gltf", g.text()));
  ASSERT_TRUE(s.camera.has_value());
  expectVec(s.camera->eye, {0, 1, 5});
  expectVec(glm::normalize(s.camera->target - s.camera->eye), {-1, 0, 0});
  expectVec(s.camera->up, {0, 1, 0});
  EXPECT_NEAR(s.camera->fovYDegrees, 0.8 * 180.0 / std::numbers::pi, 1e-4);
  EXPECT_NEAR(s.camera->znear, 0.1f, 1e-7f);
  EXPECT_EQ(s.camera->zfar, 0.0f);  // infinite
}

raster::ImageRgba8 checker() {
  raster::ImageRgba8 img(2, 2);
  img.at(0, 0) = {255, 0, 0, 255};
  img.at(1, 0) = {0, 255, 0, 255};
  img.at(0, 1) = {0, 0, 255, 255};
  img.at(1, 1) = {255, 255, 255, 0};
  return img;
}

std::vector<unsigned char> fileBytes(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A triangle with texcoords and two materials on two primitives, both using image 0 through
// textures 0 and 1.
Gltf texturedTriangles(const json& image) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const std::vector<float> uv = {0, 0, 1, 0, 0, 1};
  const int tc = g.accessor(g.view(uv), kFloat, 3, "VEC2");
  g.doc["images"] = json::array({image});
  g.doc["textures"] = json::array({{{"source", 0}}, {{"source", 0}}});
  g.doc["materials"] = json::array(
      {{{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 0.25, 1}}, {"baseColorTexture", {{"index", 0}}}}}},
       {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}});
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", tc}}}, {"material", 0}},
                      {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", tc}}}, {"material", 1}}}));
  g.node({{"mesh", 0}});
  return g;
}

void expectTextured(const Scene& s) {
  ASSERT_EQ(s.materials.size(), 2u);
  ASSERT_EQ(s.textures.size(), 1u);  // one image, shared
  EXPECT_EQ(s.materials[0].name, "red");
  EXPECT_EQ(s.materials[0].baseColorFactor, glm::vec4(1, 0.5f, 0.25f, 1));
  EXPECT_EQ(s.materials[0].baseColorTexture, 0);
  EXPECT_EQ(s.materials[1].baseColorTexture, 0);
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].material, 0);
  EXPECT_EQ(s.meshes[1].material, 1);
  ASSERT_EQ(s.meshes[0].texcoords.size(), 3u);
  const Texture& t = s.textures[0];
  ASSERT_EQ(t.mips.size(), 2u);
  const raster::ImageRgba8 expected = checker();
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) EXPECT_EQ(t.mips[0].at(x, y), expected.at(x, y));
  EXPECT_EQ(t.mips[1].width(), 1);
  // Mip 1 is the linear-space average: red, green, blue, white -> (2, 2, 2) / 4 per channel = 0.5.
  EXPECT_EQ(t.mips[1].at(0, 0), (raster::Rgba8{188, 188, 188, 191}));
}

TEST_F(GltfLoader, TexturedMaterialWithExternalPng) {
  ASSERT_TRUE(writeImage(path("checker.png"), checker()).ok());
  const Scene s = load(write("textured.gltf", texturedTriangles({{"uri", "checker.png"}}).text()));
  expectTextured(s);
}

TEST_F(GltfLoader, TexturedMaterialWithDataUriPng) {
  ASSERT_TRUE(writeImage(path("checker.png"), checker()).ok());
  const std::string uri = "data:image/png;base64," + base64(fileBytes(path("checker.png")));
  fs::remove(path("checker.png"));
  const Scene s = load(write("embedded.gltf", texturedTriangles({{"uri", uri}}).text()));
  expectTextured(s);
}

TEST_F(GltfLoader, GlbWithImageInBufferView) {
  ASSERT_TRUE(writeImage(path("checker.png"), checker()).ok());
  const std::vector<unsigned char> png = fileBytes(path("checker.png"));
  fs::remove(path("checker.png"));
  Gltf g = texturedTriangles(json::object());
  const int view = g.view(png);
  g.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
  const Scene s = load(write("textured.glb", g.glb()));
  expectTextured(s);
}

// --- Malformed input ------------------------------------------------------------------------------

TEST_F(GltfLoader, MissingFile) { expectError(path("nothing.gltf"), "cannot open"); }

TEST_F(GltfLoader, NotJson) {
  expectError(write("garbage.gltf", "this is not { json"), "not a glTF file");
  expectError(write("empty.gltf", ""), "not a glTF file");
  expectError(write("array.gltf", "[1, 2, 3]"), "not a glTF file");
  const std::vector<unsigned char> noise = {0x00, 0xff, 0x13, 0x37, 0x80, 0x7f, 0x01, 0x02};
  expectError(write("noise.glb", noise), "not a glTF file");
}

TEST_F(GltfLoader, TruncatedGlb) {
  const std::vector<unsigned char> glb = triangle().glb();
  expectError(write("cut.glb", std::vector<unsigned char>(glb.begin(), glb.begin() + 10)), "invalid glTF binary");
  expectError(write("half.glb", std::vector<unsigned char>(glb.begin(), glb.begin() + static_cast<long>(glb.size() / 2))),
              "invalid glTF binary");
  expectError(write("short.glb", std::vector<unsigned char>(glb.begin(), glb.end() - 4)), "invalid glTF binary");
}

TEST_F(GltfLoader, BufferNamingAFifoIsAnErrorNotAHang) {
  // Opening a FIFO for reading blocks until a writer appears: the loader must not open it.
  ASSERT_EQ(::mkfifo(path("pipe.bin").c_str(), 0600), 0);
  expectError(write("fifo.gltf", triangle().textWithExternalBuffer("pipe.bin")), "pipe.bin");
  ASSERT_EQ(::mkfifo(path("pipe.gltf").c_str(), 0600), 0);
  expectError(path("pipe.gltf"), "cannot open file");
}

TEST_F(GltfLoader, DeeplyNestedJsonIsAnErrorNotACrash) {
  // tinygltf converts extras recursively: 100000 levels would overflow the stack.
  Gltf g = triangle();
  std::string text = g.text();
  const std::string nest = std::string(100000, '[') + std::string(100000, ']');
  text.insert(text.find('{') + 1, "\"extras\":" + nest + ",");
  expectError(write("deep.gltf", text), "nested deeper than");
}

TEST_F(GltfLoader, AccessorPastTheEndOfItsBufferView) {
  Gltf g = triangle();
  g.doc["accessors"][0]["count"] = 4;  // the view holds 3 positions
  expectError(write("count.gltf", g.text()), "accessor 0 reads past the end of buffer view 0");
  g = triangle();
  g.doc["accessors"][0]["byteOffset"] = 4;
  expectError(write("offset.gltf", g.text()), "accessor 0 reads past the end of buffer view 0");
  g = triangle();
  g.doc["accessors"][0]["count"] = 1ull << 62;  // would overflow a naive size computation
  expectError(write("huge.gltf", g.text()), "more than 2^26");
  // A huge accessor without a buffer view (all zeros) must not allocate gigabytes either.
  g = triangle();
  g.doc["accessors"][0].erase("bufferView");
  g.doc["accessors"][0]["count"] = 1ull << 31;
  expectError(write("zeros.gltf", g.text()), "more than 2^26");
  g = triangle();
  g.doc["bufferViews"][0]["byteStride"] = 8;  // less than a VEC3 of floats
  expectError(write("stride.gltf", g.text()), "byteStride");
}

TEST_F(GltfLoader, BufferViewPastTheEndOfItsBuffer) {
  Gltf g = triangle();
  g.doc["bufferViews"][1]["byteLength"] = 4000;
  expectError(write("view.gltf", g.text()), "buffer view 1 reads past the end of buffer 0");
  g = triangle();
  g.doc["bufferViews"][0]["buffer"] = 3;
  expectError(write("buffer.gltf", g.text()), "buffer view 0 refers to buffer 3");
}

TEST_F(GltfLoader, IndexOutOfRange) {
  Gltf g;
  const int pos = g.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int idx = g.indices(std::vector<uint16_t>{0, 1, 7}, kU16);
  g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
  g.node({{"mesh", 0}});
  expectError(write("index.gltf", g.text()), "index 7 out of range");
}

TEST_F(GltfLoader, UnsupportedRequiredExtension) {
  Gltf g = triangle();
  g.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expectError(write("draco.gltf", g.text()), "required extension KHR_draco_mesh_compression is not supported");
  // Used but not required: ignored. Required and implemented: accepted.
  g.doc.erase("extensionsRequired");
  load(write("used.gltf", g.text()));
  g.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  g.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  load(write("quantized.gltf", g.text()));
}

TEST_F(GltfLoader, OtherStructuralErrors) {
  Gltf g = triangle();
  g.doc["accessors"][0]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", 1}, {"componentType", kU16}}},
                                     {"values", {{"bufferView", 0}}}};
  expectError(write("sparse.gltf", g.text()), "sparse");

  g = triangle();
  g.doc["meshes"][0]["primitives"][0]["attributes"] = {{"NORMAL", 0}};
  expectError(write("noposition.gltf", g.text()), "no POSITION");

  g = triangle();
  g.doc["meshes"][0]["primitives"][0]["material"] = 3;
  expectError(write("material.gltf", g.text()), "material 3");

  g = triangle();
  g.doc["meshes"][0]["primitives"][0]["mode"] = 9;
  expectError(write("mode.gltf", g.text()), "invalid mode 9");

  g = triangle();
  g.doc["nodes"] = json::array({{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}});
  expectError(write("cycle.gltf", g.text()), "appears twice");

  g = triangle();
  g.doc["nodes"][0]["children"] = {5};
  expectError(write("child.gltf", g.text()), "node 5 does not exist");

  g = triangle();
  g.doc["nodes"][0]["mesh"] = 4;
  expectError(write("mesh.gltf", g.text()), "mesh 4");

  g = triangle();
  g.doc["accessors"][0]["type"] = "VEC2";
  expectError(write("type.gltf", g.text()), "must be VEC3");

  g = triangle();
  g.doc["asset"]["version"] = "1.0";
  expectError(write("old.gltf", g.text()), "version");

  g = triangle();
  g.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
  expectError(write("rotation.gltf", g.text()), "zero quaternion");

  g = triangle();
  g.doc["scene"] = 2;
  expectError(write("scene.gltf", g.text()), "scene 2");
}

TEST_F(GltfLoader, MissingOrUndecodableImage) {
  expectError(write("missing.gltf", texturedTriangles({{"uri", "missing.png"}}).text()), "image 0 ('missing.png')");
  const std::string garbage = "data:image/png;base64," + base64(std::vector<unsigned char>(64, 7));
  expectError(write("garbage.gltf", texturedTriangles({{"uri", garbage}}).text()), "image 0: not a PNG or JPEG image");
  // An image in a buffer view that runs past its buffer.
  Gltf g = texturedTriangles(json::object());
  const int view = g.view(std::vector<unsigned char>(16, 1));
  g.doc["bufferViews"][static_cast<size_t>(view)]["byteLength"] = 1 << 20;
  g.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
  expectError(write("imageview.glb", g.glb()), "reads past the end");
}

TEST_F(GltfLoader, UnusedBrokenImageIsNotAnError) {
  Gltf g = triangle();
  g.doc["images"] = json::array({{{"uri", "missing.png"}}});
  const Scene s = load(write("unused.gltf", g.text()));
  EXPECT_TRUE(s.textures.empty());
}

// Every prefix and many single-byte corruptions of a valid GLB: each load returns (an error naming
// the file, or a valid scene), none crashes or hangs.
TEST_F(GltfLoader, CorruptedGlbNeverCrashes) {
  ASSERT_TRUE(writeImage(path("checker.png"), checker()).ok());
  const std::vector<unsigned char> png = fileBytes(path("checker.png"));
  Gltf g = texturedTriangles(json::object());
  const int view = g.view(png);
  g.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
  const std::vector<unsigned char> glb = g.glb();
  const std::string file = path("fuzz.glb");
  int loaded = 0, failed = 0;
  auto attempt = [&](const std::vector<unsigned char>& bytes) {
    write("fuzz.glb", bytes);
    Result<Scene> r = loadGltf(file);
    if (r.ok()) {
      ++loaded;
      for (const Mesh& m : r->meshes)
        for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
    } else {
      ++failed;
      ASSERT_EQ(r.error().where, file);
      ASSERT_EQ(r.error().line().find('\n'), std::string::npos);
    }
  };
  for (size_t cut = 0; cut < glb.size(); cut += 5) attempt(std::vector<unsigned char>(glb.begin(), glb.begin() + static_cast<long>(cut)));
  // Every byte once: a digit (changes counts, offsets and indices in the JSON) or flipped bits.
  for (size_t i = 0; i < glb.size(); ++i) {
    std::vector<unsigned char> bytes = glb;
    bytes[i] = i % 2 == 0 ? static_cast<unsigned char>('9') : static_cast<unsigned char>(glb[i] ^ 0x81);
    attempt(bytes);
  }
  EXPECT_GT(failed, 0);
  EXPECT_GT(loaded, 0);
}

}  // namespace
}  // namespace penumbra::engine

namespace penumbra::engine {
namespace {

// The model's folder bounds what it may read: buffers and images named outside it (climbing out,
// absolute, through a link, or only in the current folder) are refused before anything is read,
// unless allowed; sizes are checked before reading; buffers nothing uses are never read.
class GltfFiles : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("penumbra-gltf-files-" + std::to_string(::getpid()) + "-" +
                                         testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "model");
    fs::create_directories(root_ / "elsewhere");
  }
  void TearDown() override { fs::remove_all(root_); }
  // The triangle with its buffer in bin file `uri` (relative to model/), written at `where`.
  std::string model(const std::string& uri, const fs::path& where) {
    const Gltf g = triangle();
    std::ofstream(where, std::ios::binary).write(reinterpret_cast<const char*>(g.bin.data()),
                                                 static_cast<std::streamsize>(g.bin.size()));
    const std::string file = (root_ / "model" / "m.gltf").string();
    std::ofstream(file) << g.textWithExternalBuffer(uri);
    return file;
  }
  fs::path root_;
};

TEST_F(GltfFiles, BuffersOutsideTheFolderAreRefusedUnlessAllowed) {
  const std::string climb = model("../elsewhere/b.bin", root_ / "elsewhere" / "b.bin");
  Result<Scene> r = loadGltf(climb);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("buffer 0 ('../elsewhere/b.bin') resolves outside the file's folder"), std::string::npos)
      << r.error().line();
  EXPECT_EQ(r.error().what.find("bytes"), std::string::npos) << "reveals the file's size: " << r.error().line();
  EXPECT_TRUE(loadGltf(climb, {.allowOutsidePaths = true}).ok());
  // Absolute.
  const std::string absolute = model((root_ / "elsewhere" / "b.bin").string(), root_ / "elsewhere" / "b.bin");
  r = loadGltf(absolute);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("is an absolute path"), std::string::npos) << r.error().line();
  // A link inside the folder that leads out.
  fs::create_symlink(root_ / "elsewhere" / "b.bin", root_ / "model" / "link.bin");
  r = loadGltf(model("link.bin", root_ / "elsewhere" / "b.bin"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("outside the file's folder"), std::string::npos) << r.error().line();
  // A scheme.
  r = loadGltf(model("file:///etc/passwd", root_ / "elsewhere" / "b.bin"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("URI scheme 'file' is not supported"), std::string::npos) << r.error().line();
  // Inside: fine, and listed among the scene's files.
  const std::string inside = model("sub%20dir/b.bin", root_ / "model" / "sub dir" / "b.bin");
  fs::create_directories(root_ / "model" / "sub dir");
  model("sub%20dir/b.bin", root_ / "model" / "sub dir" / "b.bin");
  Result<Scene> ok = loadGltf(inside);
  ASSERT_TRUE(ok.ok()) << ok.error().line();
  ASSERT_EQ(ok->sourceFiles.size(), 2u);
  EXPECT_EQ(fs::path(ok->sourceFiles[1]).filename(), "b.bin");
}

TEST_F(GltfFiles, NotLookedForInTheCurrentFolder) {
  // tinygltf looks for a URI in the current folder when the model's folder lacks it.
  const fs::path cwd = fs::current_path();
  fs::current_path(root_ / "elsewhere");
  const std::string file = model("only-here.bin", root_ / "elsewhere" / "only-here.bin");
  const Result<Scene> r = loadGltf(file);
  fs::current_path(cwd);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("missing or not a regular file"), std::string::npos) << r.error().line();
}

TEST_F(GltfFiles, SizesAreCheckedBeforeReadingAndUnusedBuffersAreNotRead) {
  // A 3 GiB sparse file: reading it would take seconds and gigabytes.
  const fs::path huge = root_ / "model" / "huge.bin";
  std::ofstream(huge).close();
  fs::resize_file(huge, uint64_t{3} << 30);
  Gltf g = triangle();
  {
    std::ofstream(root_ / "model" / "b.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(g.bin.data()), static_cast<std::streamsize>(g.bin.size()));
  }
  // Used, with the wrong size: reported from the file's size, not read.
  json d = g.doc;
  d["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", "huge.bin"}}});
  const std::string wrong = (root_ / "model" / "wrong.gltf").string();
  std::ofstream(wrong) << d.dump();
  const auto t0 = std::chrono::steady_clock::now();
  Result<Scene> r = loadGltf(wrong);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("the file holds 3221225472 bytes, the buffer's byteLength is " + std::to_string(g.bin.size())),
            std::string::npos)
      << r.error().line();
  // Unused: never read, and counted.
  d["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", "b.bin"}}, {{"byteLength", uint64_t{3} << 30}, {"uri", "huge.bin"}}});
  const std::string unused = (root_ / "model" / "unused.gltf").string();
  std::ofstream(unused) << d.dump();
  GltfLoadStats stats;
  r = loadGltf(unused, {}, stats);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(stats.buffersSkipped, 1);
  EXPECT_EQ(r->sourceFiles.size(), 2u);  // the model and b.bin: not huge.bin
  // The same in a .glb, whose JSON chunk is rewritten around the BIN chunk.
  json gd = g.doc;
  gd["buffers"] = json::array({{{"byteLength", g.bin.size()}}, {{"byteLength", uint64_t{3} << 30}, {"uri", "huge.bin"}}});
  Gltf h = g;
  h.doc = gd;
  std::vector<unsigned char> glb = h.glb();  // glb() sets buffer 0 to the BIN chunk; add buffer 1 back
  {
    json j = gd;
    std::string js = j.dump();
    while (js.size() % 4) js += ' ';
    std::vector<unsigned char> bin = g.bin;
    while (bin.size() % 4) bin.push_back(0);
    glb.clear();
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) glb.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    for (char c : {'g', 'l', 'T', 'F'}) glb.push_back(static_cast<unsigned char>(c));
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + js.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(js.size()));
    u32(0x4E4F534Au);
    glb.insert(glb.end(), js.begin(), js.end());
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942u);
    glb.insert(glb.end(), bin.begin(), bin.end());
  }
  const std::string glbFile = (root_ / "model" / "unused.glb").string();
  std::ofstream(glbFile, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), static_cast<std::streamsize>(glb.size()));
  r = loadGltf(glbFile, {}, stats);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(stats.buffersSkipped, 1);
  ASSERT_EQ(r->meshes.size(), 1u);
  EXPECT_EQ(r->meshes[0].indices.size(), 3u);
  // All of it without reading 3 GiB (seconds per GiB): a generous bound, not a timing.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0);
}

TEST_F(GltfFiles, ImagesOutsideTheFolderFailOnlyWhenUsed) {
  std::ofstream(root_ / "elsewhere" / "t.png") << "x";
  Gltf g = texturedTriangles({{"uri", "../elsewhere/t.png"}});
  const std::string used = (root_ / "model" / "used.gltf").string();
  std::ofstream(used) << g.text();
  const Result<Scene> r = loadGltf(used);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().what.find("image 0 ('../elsewhere/t.png') resolves outside"), std::string::npos) << r.error().line();
  Gltf u = triangle();
  u.doc["images"] = json::array({{{"uri", "../elsewhere/t.png"}}});
  const std::string unused = (root_ / "model" / "unused.gltf").string();
  std::ofstream(unused) << u.text();
  EXPECT_TRUE(loadGltf(unused).ok());
}

}  // namespace
}  // namespace penumbra::engine

namespace penumbra::engine {
namespace {

// KHR_lights_punctual: directional, point and spot lights on nodes, placed and aimed by the node,
// photometric intensities divided by pi; a required extension we now support.
TEST_F(GltfLoader, LightsPunctual) {
  Gltf g = triangle();
  g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  g.doc["extensionsRequired"] = {"KHR_lights_punctual"};
  g.doc["extensions"] = {{"KHR_lights_punctual",
                          {{"lights",
                            {{{"type", "directional"}, {"intensity", 3.14159265}},
                             {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 6.2831853}, {"range", 10}},
                             {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}}}}}}};
  g.node({{"translation", {0, 5, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  g.node({{"translation", {0, 4, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  g.scene({0, 1, 2, 3});
  const Scene s = load(write("lights.gltf", g.text()));
  ASSERT_EQ(s.directionalLights.size(), 1u);
  ASSERT_EQ(s.pointLights.size(), 1u);
  ASSERT_EQ(s.spotLights.size(), 1u);
  // -z turned a quarter around x points down.
  EXPECT_NEAR(s.directionalLights[0].direction.y, -1.0f, 1e-5f);
  EXPECT_NEAR(s.directionalLights[0].intensity, 1.0f, 1e-5f);
  EXPECT_NEAR(s.pointLights[0].position.z, 3.0f, 1e-6f);
  EXPECT_NEAR(s.pointLights[0].intensity, 2.0f, 1e-5f);
  EXPECT_EQ(s.pointLights[0].range, 10.0f);
  EXPECT_EQ(s.pointLights[0].color.y, 0.5f);
  EXPECT_NEAR(s.spotLights[0].direction.y, -1.0f, 1e-5f);
  EXPECT_NEAR(s.spotLights[0].outerCone, 0.5f, 1e-6f);
  // A light index that does not exist, and a bad cone, are errors.
  g.doc["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 7;
  expectError(write("badlight.gltf", g.text()), "uses light 7, which does not exist");
  g.doc["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 2;
  g.doc["extensions"]["KHR_lights_punctual"]["lights"][2]["spot"]["innerConeAngle"] = 0.6;
  expectError(write("badcone.gltf", g.text()), "spot cones");
}

}  // namespace
}  // namespace penumbra::engine
