// Scene files: each feature of the format, glTF references relative to the file, and the errors
// (unknown keys with the valid ones listed, values out of range named by their JSON path, parse
// errors with a line and column), plus loadScene's dispatch by extension.
#include "engine/scene_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "engine/shapes.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class SceneFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra-scene-" + std::to_string(::getpid()) + "-" +
                                        testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  Scene parse(const json& j) {
    Result<Scene> r = parseSceneFile(j.dump(), (dir_ / "scene.json").string());
    EXPECT_TRUE(r.ok()) << r.error().line();
    return r.ok() ? std::move(*r) : Scene{};
  }
  // The error must be one line naming the scene file and contain `expected`.
  std::string errorText(const std::string& text, const std::string& expected) {
    const std::string file = (dir_ / "scene.json").string();
    Result<Scene> r = parseSceneFile(text, file);
    EXPECT_FALSE(r.ok()) << text;
    if (r.ok()) return {};
    EXPECT_EQ(r.error().where, file);
    EXPECT_EQ(r.error().line().find('\n'), std::string::npos) << r.error().line();
    EXPECT_NE(r.error().what.find(expected), std::string::npos) << "got: " << r.error().what;
    return r.error().what;
  }
  std::string error(const json& j, const std::string& expected) { return errorText(j.dump(), expected); }

  fs::path dir_;
};

void expectVec(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

// A one-triangle glTF with an embedded buffer (positions (0,0,0), (1,0,0), (0,1,0); u16 indices) and
// a camera node at (0, 0, 3).
std::string triangleGltf() {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint16_t idx[4] = {0, 1, 2, 0};
  std::string bin(reinterpret_cast<const char*>(pos), sizeof(pos));
  bin.append(reinterpret_cast<const char*>(idx), sizeof(idx));
  static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (size_t i = 0; i < bin.size(); i += 3) {  // 44 bytes: the last group has 2 bytes
    const auto byte = [&](size_t k) { return k < bin.size() ? static_cast<unsigned>(static_cast<unsigned char>(bin[k])) : 0u; };
    const unsigned v = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    b64 += alphabet[v >> 18 & 63];
    b64 += alphabet[v >> 12 & 63];
    b64 += i + 1 < bin.size() ? alphabet[v >> 6 & 63] : '=';
    b64 += i + 2 < bin.size() ? alphabet[v & 63] : '=';
  }
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + b64}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}}, {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}}},
      {"nodes", {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 3}}}}},
      {"scenes", {{{"nodes", {0, 1}}}}}};
  return doc.dump();
}

TEST_F(SceneFile, EveryShape) {
  const Scene s = parse({{"name", "shapes"},
                         {"objects",
                          {{{"shape", "plane"}, {"size", {10, 4}}, {"divisions", 2}},
                           {{"shape", "box"}, {"size", {1, 2, 3}}},
                           {{"shape", "sphere"}, {"radius", 0.5}, {"rings", 8}, {"segments", 12}, {"name", "ball"}},
                           {{"shape", "cylinder"}, {"radius", 0.25}, {"height", 2}, {"segments", 10}},
                           {{"shape", "torus"}, {"major_radius", 1}, {"minor_radius", 0.2}, {"rings", 12}, {"segments", 6}}}}});
  EXPECT_EQ(s.name, "shapes");
  ASSERT_EQ(s.meshes.size(), 5u);
  ASSERT_EQ(s.instances.size(), 5u);
  EXPECT_EQ(s.meshes[0].indices, makePlane(10, 4, 2).indices);
  expectVec(s.meshes[0].boundsMax, {5, 0, 2});
  expectVec(s.meshes[1].boundsMax, {0.5f, 1, 1.5f});
  EXPECT_EQ(s.meshes[2].indices.size(), makeSphere(0.5f, 8, 12).indices.size());
  EXPECT_EQ(s.meshes[2].name, "ball");
  EXPECT_EQ(s.instances[2].name, "ball");
  EXPECT_EQ(s.meshes[3].indices.size() / 3, 40u);
  // 10 segments from +z: the widest vertex in x is at 72 degrees.
  expectVec(s.meshes[3].boundsMax, {0.25f * std::sin(0.4f * std::numbers::pi_v<float>), 1, 0.25f});
  EXPECT_EQ(s.meshes[4].indices.size() / 3, 2u * 12u * 6u);
  for (const Mesh& m : s.meshes) EXPECT_EQ(m.material, -1);
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(s.instances[i].mesh, static_cast<int>(i));
}

TEST_F(SceneFile, DefaultsWhenParametersAreOmitted) {
  const Scene s = parse({{"objects", {{{"shape", "sphere"}}, {{"shape", "box"}, {"size", 2}}}}});
  EXPECT_EQ(s.name, "scene");  // the file's stem
  ASSERT_EQ(s.meshes.size(), 2u);
  expectVec(s.meshes[0].boundsMax, {0.5f, 0.5f, 0.5f});
  expectVec(s.meshes[1].boundsMax, {1, 1, 1});
  EXPECT_FALSE(s.camera.has_value());
  EXPECT_TRUE(s.directionalLights.empty());
}

TEST_F(SceneFile, Material) {
  const Scene s = parse({{"objects", {{{"shape", "box"}, {"material", {{"color", {0.8, 0.1, 0.2}}, {"specular", 0.5}, {"shininess", 64}}}}}}});
  ASSERT_EQ(s.materials.size(), 1u);
  ASSERT_EQ(s.meshes[0].material, 0);
  EXPECT_EQ(s.materials[0].baseColorFactor, glm::vec4(0.8f, 0.1f, 0.2f, 1.0f));
  EXPECT_EQ(s.materials[0].specular, 0.5f);
  EXPECT_EQ(s.materials[0].shininess, 64.0f);
  EXPECT_EQ(s.materials[0].baseColorTexture, -1);
}

TEST_F(SceneFile, Transforms) {
  const Scene s = parse(
      {{"objects",
        {{{"shape", "box"}, {"transform", {{"translate", {1, 2, 3}}}}},
         {{"shape", "box"}, {"transform", {{"rotate_deg", {0, 90, 0}}}}},
         {{"shape", "box"}, {"transform", {{"rotate_axis_deg", {0, 0, 2, 90}}}}},
         {{"shape", "box"}, {"transform", {{"scale", 2}}}},
         {{"shape", "box"}, {"transform", {{"scale", {1, 2, 3}}, {"rotate_deg", {90, 0, 90}}, {"translate", {0, 0, 5}}}}}}}});
  ASSERT_EQ(s.instances.size(), 5u);
  expectVec(apply(s.instances[0].transform, {0, 0, 0}), {1, 2, 3});
  expectVec(apply(s.instances[1].transform, {1, 0, 0}), {0, 0, -1});  // 90 degrees about +y
  expectVec(apply(s.instances[2].transform, {1, 0, 0}), {0, 1, 0});   // 90 degrees about +z
  expectVec(apply(s.instances[3].transform, {1, 1, 1}), {2, 2, 2});
  // T Rz Ry Rx S: (1, 0, 0) -> scale (1, 0, 0) -> Rx(90) (1, 0, 0) -> Rz(90) (0, 1, 0) -> + (0, 0, 5).
  expectVec(apply(s.instances[4].transform, {1, 0, 0}), {0, 1, 5});
  // (0, 1, 0) -> (0, 2, 0) -> Rx(90) (0, 0, 2) -> Rz(90) (0, 0, 2) -> (0, 0, 7).
  expectVec(apply(s.instances[4].transform, {0, 1, 0}), {0, 0, 7});
}

TEST_F(SceneFile, CameraLightsAmbientBackground) {
  const Scene s = parse({{"camera", {{"eye", {0, 2, 8}}, {"target", {0, 1, 0}}, {"up", {0, 2, 0}}, {"fov_deg", 35}, {"near", 0.5}, {"far", 100}}},
                         {"lights",
                          {{{"type", "directional"}, {"direction", {0, -2, 0}}, {"color", {1, 0.9, 0.8}}, {"intensity", 3}},
                           {{"type", "point"}, {"position", {1, 4, 1}}, {"intensity", 20}}}},
                         {"ambient", {0.1, 0.2, 0.3}},
                         {"background", {0, 0, 0}}});
  ASSERT_TRUE(s.camera.has_value());
  expectVec(s.camera->eye, {0, 2, 8});
  expectVec(s.camera->target, {0, 1, 0});
  expectVec(s.camera->up, {0, 1, 0});
  EXPECT_EQ(s.camera->fovYDegrees, 35.0f);
  EXPECT_EQ(s.camera->znear, 0.5f);
  EXPECT_EQ(s.camera->zfar, 100.0f);
  ASSERT_EQ(s.directionalLights.size(), 1u);
  expectVec(s.directionalLights[0].direction, {0, -1, 0});
  expectVec(s.directionalLights[0].color, {1, 0.9f, 0.8f});
  EXPECT_EQ(s.directionalLights[0].intensity, 3.0f);
  ASSERT_EQ(s.pointLights.size(), 1u);
  expectVec(s.pointLights[0].position, {1, 4, 1});
  expectVec(s.pointLights[0].color, {1, 1, 1});
  EXPECT_EQ(s.pointLights[0].intensity, 20.0f);
  expectVec(s.ambient, {0.1f, 0.2f, 0.3f});
  expectVec(s.background, {0, 0, 0});
}

TEST_F(SceneFile, AreaLight) {
  const Scene s = parse({{"lights",
                          {{{"type", "area"}, {"center", {1, 5, 2}}, {"normal", {0, -3, 0}}, {"width_axis", {0, 0, 2}},
                            {"width", 2}, {"height", 0.5}, {"color", {1, 0.5, 0.25}}, {"intensity", 12}},
                           {{"type", "area"}, {"center", {0, 3, 0}}, {"normal", {1, -1, 0}}}}}});
  ASSERT_EQ(s.areaLights.size(), 2u);
  const shadows::RectLight& l = s.areaLights[0];
  expectVec(l.center, {1, 5, 2});
  expectVec(l.normal(), {0, -1, 0});
  expectVec(l.right, {0, 0, 1});
  EXPECT_EQ(l.width, 2.0f);
  EXPECT_EQ(l.height, 0.5f);
  expectVec(l.color, {1, 0.5f, 0.25f});
  EXPECT_EQ(l.intensity, 12.0f);
  // Defaults: 1 x 1, white, intensity 1; the width axis is x projected onto the light's plane.
  const shadows::RectLight& d = s.areaLights[1];
  EXPECT_EQ(d.width, 1.0f);
  EXPECT_EQ(d.height, 1.0f);
  EXPECT_EQ(d.intensity, 1.0f);
  EXPECT_NEAR(glm::dot(d.right, d.normal()), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(d.right), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(d.normal() - glm::normalize(glm::vec3(1, -1, 0))), 0.0f, 1e-6f);
}

TEST_F(SceneFile, RelativeGltfReferenceWithTransform) {
  write("models/tri.gltf", triangleGltf());
  const std::string scene = write("scenes/main.json", json({{"gltf", {{{"file", "../models/tri.gltf"}, {"transform", {{"translate", {0, 1, 0}}, {"scale", 2}}}}}},
                                                            {"objects", {{{"shape", "box"}, {"material", {{"color", {1, 0, 0}}}}}}}})
                                                           .dump());
  // Outside the scene file's folder: refused unless allowed.
  const Result<Scene> refused = loadScene(scene);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().what.find("outside the file's folder"), std::string::npos) << refused.error().line();
  Result<Scene> r = loadScene(scene, {.allowOutsidePaths = true});
  ASSERT_TRUE(r.ok()) << r.error().line();
  const Scene& s = *r;
  EXPECT_EQ(s.name, "main");
  // Every file read is listed (outputs must not overwrite them).
  ASSERT_EQ(s.sourceFiles.size(), 2u);
  EXPECT_EQ(fs::path(s.sourceFiles[0]).filename(), "main.json");
  EXPECT_EQ(fs::path(s.sourceFiles[1]).filename(), "tri.gltf");
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.materials.size(), 2u);
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.meshes[0].material, 0);  // the glTF's material
  EXPECT_EQ(s.meshes[1].material, 1);  // the box's, after it
  EXPECT_NEAR(s.materials[0].baseColorFactor.z, 0.6f, 1e-6f);
  expectVec(apply(s.instances[0].transform, {1, 0, 0}), {2, 1, 0});
  // The glTF camera, placed by the same transform, since the scene file sets none.
  ASSERT_TRUE(s.camera.has_value());
  expectVec(s.camera->eye, {0, 1, 6});
  expectVec(glm::normalize(s.camera->target - s.camera->eye), {0, 0, -1});
  // An absolute path is refused too, unless allowed; a camera in the scene file wins over the
  // glTF one.
  const json withAbsolute = {{"gltf", {{{"file", (dir_ / "models" / "tri.gltf").string()}}}}, {"camera", {{"eye", {9, 9, 9}}}}};
  error(withAbsolute, "is an absolute path");
  Result<Scene> t = parseSceneFile(withAbsolute.dump(), (dir_ / "scene.json").string(), {.allowOutsidePaths = true});
  ASSERT_TRUE(t.ok()) << t.error().line();
  ASSERT_EQ(t->meshes.size(), 1u);
  expectVec(t->camera->eye, {9, 9, 9});
}

TEST_F(SceneFile, BrokenGltfReferenceNamesBothFiles) {
  const std::string what = error(json({{"gltf", {{{"file", "nowhere.glb"}}}}}), "gltf[0].file");
  EXPECT_NE(what.find("nowhere.glb"), std::string::npos);
  EXPECT_NE(what.find("missing or not a regular file"), std::string::npos);
  write("bad.gltf", "{ nope");
  error(json({{"gltf", {{{"file", "bad.gltf"}}}}}), "not a glTF file");
  error(json({{"gltf", {{{"transform", {{"scale", 1}}}}}}}), "gltf[0].file is required");
}

TEST_F(SceneFile, UnknownKeysListTheValidOnes) {
  std::string what = error(json({{"objets", json::array()}}), "unknown key 'objets'");
  EXPECT_NE(what.find("objects"), std::string::npos);
  what = error(json({{"objects", {{{"shape", "sphere"}, {"radiuss", 1}}}}}), "objects[0]: unknown key 'radiuss'");
  EXPECT_NE(what.find("radius, rings, segments"), std::string::npos) << what;
  error(json({{"objects", {{{"shape", "box"}, {"radius", 1}}}}}), "unknown key 'radius' (valid keys for shape 'box'");
  error(json({{"objects", {{{"shape", "box"}, {"material", {{"colour", {1, 1, 1}}}}}}}}), "objects[0].material: unknown key 'colour'");
  error(json({{"objects", {{{"shape", "box"}, {"transform", {{"rotate", {1, 1, 1}}}}}}}}), "objects[0].transform: unknown key 'rotate'");
  error(json({{"camera", {{"fov", 40}}}}), "camera: unknown key 'fov'");
  error(json({{"lights", {{{"type", "point"}, {"position", {0, 1, 0}}, {"direction", {0, 1, 0}}}}}}), "lights[0]: unknown key 'direction'");
}

TEST_F(SceneFile, BadValuesNameTheirJsonPath) {
  auto sphere = [](json extra) {
    json o = {{"shape", "sphere"}};
    o.update(extra);
    return json({{"objects", {{{"shape", "box"}}, o}}});
  };
  error(sphere({{"radius", -1}}), "objects[1].radius must be > 0");
  error(sphere({{"radius", 0}}), "objects[1].radius must be > 0");
  error(sphere({{"radius", "big"}}), "objects[1].radius must be a number");
  error(sphere({{"segments", 2}}), "objects[1].segments must be an integer in [3, 4096]");
  error(sphere({{"segments", 5000}}), "objects[1].segments must be an integer in [3, 4096]");
  error(sphere({{"rings", 4.5}}), "objects[1].rings must be an integer");
  error(json({{"objects", {{{"shape", "cone"}}}}}), "objects[0].shape must be one of");
  error(json({{"objects", {{{"radius", 1}}}}}), "objects[0].shape is required");
  error(json({{"objects", {{{"shape", "box"}, {"size", {1, -2, 3}}}}}}), "objects[0].size[1] must be > 0");
  error(json({{"objects", {{{"shape", "box"}, {"size", {1, 2}}}}}}), "objects[0].size must be an array of 3 numbers");
  error(json({{"objects", {{{"shape", "torus"}, {"major_radius", 1}, {"minor_radius", 1}}}}}), "objects[0].minor_radius must be < major_radius");
  error(json({{"objects", {{{"shape", "box"}, {"material", {{"color", {1, 2, 0}}}}}}}}), "objects[0].material.color[1] must be in [0, 1]");
  error(json({{"objects", {{{"shape", "box"}, {"material", {{"shininess", 0.5}}}}}}}), "objects[0].material.shininess must be in [1, 4096]");
  error(json({{"objects", {{{"shape", "box"}, {"transform", {{"scale", 0}}}}}}}), "objects[0].transform.scale must be > 0");
  error(json({{"objects", {{{"shape", "box"}, {"transform", {{"rotate_deg", {0, 0, 1}}, {"rotate_axis_deg", {0, 1, 0, 4}}}}}}}}),
        "not both");
  error(json({{"objects", {{{"shape", "box"}, {"transform", {{"rotate_axis_deg", {0, 0, 0, 4}}}}}}}}), "axis must not be a zero vector");
  error(json({{"camera", {{"fov_deg", 180}}}}), "camera.fov_deg must be in (0, 180)");
  error(json({{"camera", {{"fov_deg", 0}}}}), "camera.fov_deg must be in (0, 180)");
  error(json({{"camera", {{"eye", {1, 1, 1}}, {"target", {1, 1, 1}}}}}), "camera.target must differ from eye");
  error(json({{"camera", {{"eye", {0, 5, 0}}, {"target", {0, 0, 0}}}}}), "camera.up must not be parallel");
  error(json({{"camera", {{"near", 10}, {"far", 1}}}}), "camera.far must be > near");
  error(json({{"lights", {{{"type", "lamp"}}}}}), "lights[0].type must be 'directional', 'point', 'spot' or 'area'");
  error(json({{"lights", {{{"type", "spot"}, {"position", {0, 1, 0}}, {"direction", {0, -1, 0}}, {"inner_deg", 50}, {"outer_deg", 40}}}}}), "lights[0].inner_deg must be");
  error(json({{"lights", {{{"type", "area"}, {"center", {0, 4, 0}}}}}}), "lights[0].normal is required");
  error(json({{"lights", {{{"type", "area"}, {"center", {0, 4, 0}}, {"normal", {0, -1, 0}}, {"width", 0}}}}}),
        "lights[0].width must be > 0");
  error(json({{"lights", {{{"type", "area"}, {"center", {0, 4, 0}}, {"normal", {0, -1, 0}}, {"height", -2}}}}}),
        "lights[0].height must be > 0");
  error(json({{"lights", {{{"type", "area"}, {"center", {0, 4, 0}}, {"normal", {0, -1, 0}}, {"radius", 2}}}}}),
        "radius");
  error(json({{"lights", {{{"type", "directional"}, {"direction", {0, 0, 0}}}}}}), "lights[0].direction must not be a zero vector");
  error(json({{"lights", {{{"type", "directional"}}}}}), "lights[0].direction is required");
  error(json({{"lights", {{{"type", "point"}, {"position", {0, 0, 0}}, {"intensity", -1}}}}}), "lights[0].intensity must be >= 0");
  error(json({{"ambient", {0.1, -0.1, 0}}}), "ambient[1] must be >= 0");
  error(json({{"objects", {{"shape", "box"}}}}), "objects must be an array");  // an object, not an array of objects
  error(json({{"objects", json::array({1})}}), "objects[0] must be a JSON object");
  error(json::array({1, 2}), "must be a JSON object");
  error(json({{"objects", {{{"shape", "sphere"}, {"radius", 1e39}}}}}), "objects[0].radius is too large");
}

TEST_F(SceneFile, JsonSyntaxErrorsGiveLineAndColumn) {
  const std::string what = errorText("{\n  \"objects\": [\n    {\"shape\": \"box\",}\n  ]\n}\n", "invalid JSON at line 3, column");
  EXPECT_EQ(what.find("[json.exception"), std::string::npos);
  errorText("", "invalid JSON at line 1, column 1");
}

TEST_F(SceneFile, LoadSceneDispatchesByExtension) {
  Result<Scene> r = loadScene((dir_ / "scene.obj").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().what, "unknown scene file type (expected .gltf, .glb or .json)");
  r = loadScene((dir_ / "missing.json").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where, (dir_ / "missing.json").string());
  EXPECT_EQ(r.error().what, "cannot open file");
  r = loadScene((dir_ / "missing.glb").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().what, "cannot open file");
  const std::string gltf = write("TRI.GLTF", triangleGltf());
  r = loadScene(gltf);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(r->meshes.size(), 1u);
  const std::string scene = write("s.JSON", R"({"objects": [{"shape": "torus"}]})");
  r = loadScene(scene);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(r->meshes.size(), 1u);
}

// The examples in docs/scene-format.md parse (glTF files they name do not exist here: that, and
// only that, may fail).
TEST_F(SceneFile, DocumentedExamplesAreValid) {
  const fs::path doc = fs::path(__FILE__).parent_path() / ".." / ".." / "docs" / "scene-format.md";
  std::ifstream in(doc);
  ASSERT_TRUE(in) << "cannot read " << doc;
  std::string line, block;
  bool inBlock = false;
  int checked = 0;
  while (std::getline(in, line)) {
    if (!inBlock && line == "```json") {
      inBlock = true;
      block.clear();
    } else if (inBlock && line == "```") {
      inBlock = false;
      if (block.find("...") != std::string::npos) continue;  // the outline, not an example
      Result<Scene> r = parseSceneFile(block, (dir_ / "example.json").string());
      if (!r.ok()) {
        EXPECT_NE(r.error().what.find("missing or not a regular file"), std::string::npos) << r.error().line() << "\n"
                                                                                          << block;
      }
      ++checked;
    } else if (inBlock) {
      block += line + "\n";
    }
  }
  EXPECT_GE(checked, 11);  // one per feature and the complete example
}

}  // namespace
}  // namespace penumbra::engine

namespace penumbra::engine {
namespace {

// A number JSON cannot hold in a double is an error naming the file and where the number is.
TEST(SceneFileNumbers, OutOfRangeNumberNamesFileAndPosition) {
  const Result<Scene> r = parseSceneFile("{\n  \"ambient\": [1e400, 0, 0]\n}", "s.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where, "s.json");
  EXPECT_NE(r.error().what.find("line 2, column"), std::string::npos) << r.error().line();
  EXPECT_NE(r.error().what.find("1e400"), std::string::npos) << r.error().line();
  EXPECT_EQ(r.error().what.find("json.exception"), std::string::npos) << r.error().line();
}

}  // namespace
}  // namespace penumbra::engine
