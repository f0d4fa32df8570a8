#include "engine/builtin_scenes.h"

#include <glm/ext/matrix_transform.hpp>
#include <numbers>

#include "engine/shapes.h"
#include "engine/synth.h"
#include "engine/texture.h"

namespace penumbra::engine {

namespace {

constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

int addMaterial(Scene& s, const std::string& name, glm::vec3 color, float specular = 0.0f, float shininess = 32.0f,
                int texture = -1) {
  Material m;
  m.name = name;
  m.baseColorFactor = glm::vec4(color, 1.0f);
  m.specular = specular;
  m.shininess = shininess;
  m.baseColorTexture = texture;
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size()) - 1;
}

void addObject(Scene& s, const std::string& name, Mesh mesh, int material, const glm::mat4& transform) {
  mesh.name = name;
  mesh.material = material;
  s.meshes.push_back(std::move(mesh));
  Instance inst;
  inst.name = name;
  inst.mesh = static_cast<int>(s.meshes.size()) - 1;
  inst.transform = transform;
  s.instances.push_back(inst);
}

// A two-tone checkerboard, sRGB texels, with mips.
int addChecker(Scene& s, int size, int squares, raster::Rgba8 a, raster::Rgba8 b) {
  Texture t;
  t.name = "checker";
  raster::ImageRgba8 img(size, size);
  const int cell = size / squares;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) img.at(x, y) = ((x / cell + y / cell) % 2) ? a : b;
  t.mips.push_back(std::move(img));
  buildMips(t);
  s.textures.push_back(std::move(t));
  return static_cast<int>(s.textures.size()) - 1;
}

glm::mat4 at(glm::vec3 p, float yawDeg = 0.0f, float scale = 1.0f) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), p);
  m = glm::rotate(m, yawDeg * kDeg, glm::vec3(0, 1, 0));
  return glm::scale(m, glm::vec3(scale));
}

Scene makeDefault() {
  Scene s;
  s.name = kDefaultScene;
  const int checker = addChecker(s, 512, 16, {190, 188, 180, 255}, {96, 100, 110, 255});
  Mesh ground = makePlane(14.0f, 14.0f, 8);
  for (glm::vec2& uv : ground.texcoords) uv *= 2.0f;
  addObject(s, "ground", std::move(ground), addMaterial(s, "ground", glm::vec3(1.0f), 0.05f, 16.0f, checker), glm::mat4(1.0f));
  addObject(s, "sphere", makeSphere(1.0f, 48, 96), addMaterial(s, "red plastic", {0.75f, 0.12f, 0.10f}, 0.5f, 64.0f),
            at({-2.2f, 1.0f, 0.4f}));
  addObject(s, "box", makeBox({1.6f, 1.6f, 1.6f}), addMaterial(s, "blue paint", {0.15f, 0.3f, 0.75f}, 0.2f, 32.0f),
            at({0.6f, 0.8f, -1.6f}, 28.0f));
  glm::mat4 torus = glm::translate(glm::mat4(1.0f), {2.4f, 0.95f, 0.9f});
  torus = glm::rotate(torus, 65.0f * kDeg, glm::vec3(1, 0, 0.3f));
  addObject(s, "torus", makeTorus(0.75f, 0.28f, 64, 32), addMaterial(s, "gold", {0.85f, 0.62f, 0.18f}, 0.8f, 96.0f), torus);
  addObject(s, "cylinder", makeCylinder(0.45f, 2.4f, 64), addMaterial(s, "green", {0.2f, 0.6f, 0.28f}, 0.1f, 16.0f),
            at({-0.6f, 1.2f, 2.1f}));
  addObject(s, "small sphere", makeSphere(0.45f, 32, 64), addMaterial(s, "white", {0.9f, 0.9f, 0.88f}, 0.6f, 128.0f),
            at({0.9f, 0.45f, 1.3f}));
  Camera cam;
  cam.eye = {5.2f, 3.6f, 6.9f};
  cam.target = {0.0f, 0.8f, 0.0f};
  cam.fovYDegrees = 40.0f;
  s.camera = cam;
  s.directionalLights.push_back({glm::normalize(glm::vec3(-0.45f, -1.0f, -0.35f)), {1.0f, 0.95f, 0.88f}, 1.1f});
  s.pointLights.push_back({{-3.0f, 3.0f, 3.5f}, {0.55f, 0.7f, 1.0f}, 3.0f});
  s.ambient = glm::vec3(0.07f, 0.08f, 0.1f);
  s.background = glm::vec3(0.32f, 0.42f, 0.55f);
  return s;
}

Scene makeSynth(long tris) {
  Scene s;
  s.name = "synth" + std::to_string(tris / 1000000) + "m";
  addObject(s, "synth", makeSynthMesh(tris), addMaterial(s, "albedo", {0.85f, 0.75f, 0.6f}), glm::mat4(1.0f));
  s.directionalLights.push_back({glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f)), glm::vec3(1.0f), 1.0f});
  s.ambient = glm::vec3(0.15f);
  return s;
}

}  // namespace

std::vector<BuiltinInfo> builtinScenes() {
  return {{kDefaultScene, "objects (sphere, box, torus, cylinder) on a textured ground plane, sun and point light"},
          {"synth1m", "the synthetic benchmark mesh of WORKLOADS.md: 8x8 UV spheres, 999,936 triangles"},
          {"synth4m", "the synthetic benchmark mesh of WORKLOADS.md: 8x8 UV spheres, 3,968,000 triangles"}};
}

Result<Scene> makeBuiltinScene(const std::string& name) {
  Scene s;
  if (name == kDefaultScene) s = makeDefault();
  else if (name == "synth1m") s = makeSynth(1000000);
  else if (name == "synth4m") s = makeSynth(4000000);
  else {
    std::string names;
    for (const BuiltinInfo& b : builtinScenes()) {
      if (!names.empty()) names += ", ";
      names += b.name;
    }
    return Error{"--builtin " + name, "unknown built-in scene (valid: " + names + ")"};
  }
  Status st = validateScene(s, "built-in scene " + name);
  if (!st) return st.error();
  return s;
}

}  // namespace penumbra::engine
