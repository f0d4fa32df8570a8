#include "engine/builtin_scenes.h"

#include <glm/ext/matrix_transform.hpp>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
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

void addAreaLight(Scene& s, glm::vec3 centre, glm::vec3 facing, float width, float height, glm::vec3 color,
                  float intensity) {
  shadows::RectLight l;
  [[maybe_unused]] const bool ok = makeRectLight(centre, facing, {1, 0, 0}, width, height, color, intensity, l);
  assert(ok);
  s.areaLights.push_back(l);
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
  addObject(s, "torus", makeTorus(0.75f, 0.28f, 128, 64), addMaterial(s, "gold", {0.85f, 0.62f, 0.18f}, 0.8f, 96.0f), torus);
  addObject(s, "cylinder", makeCylinder(0.45f, 2.4f, 128), addMaterial(s, "green", {0.2f, 0.6f, 0.28f}, 0.1f, 16.0f),
            at({-0.6f, 1.2f, 2.1f}));
  addObject(s, "small sphere", makeSphere(0.45f, 32, 64), addMaterial(s, "white", {0.9f, 0.9f, 0.88f}, 0.6f, 128.0f),
            at({0.9f, 0.45f, 1.3f}));
  Camera cam;
  cam.eye = {5.2f, 3.6f, 6.9f};
  cam.target = {0.0f, 0.8f, 0.0f};
  cam.fovYDegrees = 40.0f;
  s.camera = cam;
  addAreaLight(s, {-2.0f, 6.0f, 1.0f}, {0.35f, -1.0f, -0.15f}, 2.5f, 2.5f, {1.0f, 0.95f, 0.88f}, 16.0f);
  s.pointLights.push_back({{-3.0f, 3.0f, 3.5f}, {0.55f, 0.7f, 1.0f}, 2.0f});
  s.ambient = glm::vec3(0.07f, 0.08f, 0.1f);
  s.background = glm::vec3(0.32f, 0.42f, 0.55f);
  return s;
}

// --- Shadow benchmark scenes -------------------------------------------------------------------
// Each separates the techniques on one known failure (docs/performance.md, "Soft shadows"): grey
// Lambertian surfaces on a ground plane, one area light, no other light, a camera looking down at
// the penumbrae.

Scene shadowStage(const std::string& name, glm::vec3 eye, glm::vec3 target) {
  Scene s;
  s.name = name;
  addObject(s, "ground", makePlane(16.0f, 16.0f, 4), addMaterial(s, "ground", glm::vec3(0.8f)), glm::mat4(1.0f));
  Camera cam;
  cam.eye = eye;
  cam.target = target;
  cam.fovYDegrees = 45.0f;
  s.camera = cam;
  s.ambient = glm::vec3(0.03f);
  s.background = glm::vec3(0.2f, 0.22f, 0.25f);
  return s;
}

glm::mat4 boxAt(glm::vec3 centre, glm::vec3 size, float yawDeg = 0.0f) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), centre);
  m = glm::rotate(m, yawDeg * kDeg, glm::vec3(0, 1, 0));
  return glm::scale(m, size);
}

// (a) Contact hardening: objects touching the ground and others at several heights above it.
Scene makeContact() {
  Scene s = shadowStage("contact", {0.0f, 6.5f, 7.5f}, {0.0f, 0.4f, 0.0f});
  const int m = addMaterial(s, "clay", {0.75f, 0.7f, 0.62f});
  addObject(s, "pillar", makeBox(glm::vec3(1.0f)), m, boxAt({-2.6f, 1.0f, 0.0f}, {0.5f, 2.0f, 0.5f}, 20.0f));
  addObject(s, "sphere 0", makeSphere(0.5f, 32, 64), m, at({-1.0f, 0.5f, 0.6f}));
  addObject(s, "sphere 1", makeSphere(0.5f, 32, 64), m, at({0.4f, 1.2f, 0.6f}));
  addObject(s, "sphere 2", makeSphere(0.5f, 32, 64), m, at({1.8f, 2.2f, 0.6f}));
  addObject(s, "slab", makeBox(glm::vec3(1.0f)), m, boxAt({1.2f, 0.6f, -1.8f}, {2.2f, 0.08f, 0.8f}, -10.0f));
  addAreaLight(s, {0.0f, 6.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 1.6f, 1.6f, glm::vec3(1.0f), 40.0f);
  return s;
}

// (b) Occluder fusion: overlapping occluders at very different depths under a large light; the
// average blocker depth of PCSS lies between them and matches neither.
Scene makeFusion() {
  Scene s = shadowStage("fusion", {0.0f, 7.0f, 7.0f}, {0.0f, 0.3f, 0.0f});
  const int m = addMaterial(s, "clay", {0.7f, 0.72f, 0.75f});
  addObject(s, "high plate", makeBox(glm::vec3(1.0f)), m, boxAt({-0.6f, 3.6f, 0.0f}, {2.4f, 0.06f, 1.6f}));
  addObject(s, "low plate", makeBox(glm::vec3(1.0f)), m, boxAt({0.9f, 0.35f, 0.3f}, {1.8f, 0.06f, 1.4f}, 15.0f));
  addObject(s, "low bar", makeBox(glm::vec3(1.0f)), m, boxAt({-1.2f, 0.6f, 1.3f}, {2.6f, 0.12f, 0.25f}, -25.0f));
  addObject(s, "mid ball", makeSphere(0.45f, 32, 64), m, at({1.6f, 1.8f, -1.2f}));
  addAreaLight(s, {0.0f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 3.0f, 3.0f, glm::vec3(1.0f), 14.0f);
  return s;
}

// (c) Thin geometry: poles and a fence of slats a few texels wide in a shadow map, which a sparse
// blocker search steps over.
Scene makeThin() {
  Scene s = shadowStage("thin", {0.5f, 6.0f, 7.0f}, {0.0f, 0.6f, 0.0f});
  const int m = addMaterial(s, "wood", {0.62f, 0.5f, 0.38f});
  for (int i = 0; i < 14; ++i)  // fence slats
    addObject(s, "slat " + std::to_string(i), makeBox(glm::vec3(1.0f)), m,
              boxAt({-2.6f + 0.3f * static_cast<float>(i), 0.8f, -0.8f}, {0.05f, 1.6f, 0.05f}));
  addObject(s, "rail", makeBox(glm::vec3(1.0f)), m, boxAt({-0.65f, 1.45f, -0.8f}, {4.2f, 0.05f, 0.05f}));
  for (int i = 0; i < 5; ++i)  // poles
    addObject(s, "pole " + std::to_string(i), makeCylinder(0.03f, 2.6f + 0.3f * static_cast<float>(i), 16), m,
              at({-1.8f + 0.9f * static_cast<float>(i), 1.3f + 0.15f * static_cast<float>(i), 1.2f}));
  addObject(s, "wire", makeBox(glm::vec3(1.0f)), m, boxAt({0.0f, 2.9f, 1.2f}, {4.0f, 0.03f, 0.03f}));
  addAreaLight(s, {0.5f, 5.5f, 0.5f}, {0.0f, -1.0f, 0.0f}, 1.2f, 1.2f, glm::vec3(1.0f), 60.0f);
  return s;
}

// (d) A complex mesh: a displaced sphere of 128,000 triangles with self-shadowing folds.
Scene makeComplex() {
  Scene s = shadowStage("complex", {0.0f, 5.5f, 6.5f}, {0.0f, 1.0f, 0.0f});
  Mesh blob = makeSphere(1.0f, 200, 320);
  for (glm::vec3& p : blob.positions) {
    const float r = 1.0f + 0.22f * std::sin(7.0f * p.x + 1.3f) * std::sin(6.0f * p.y) * std::sin(7.0f * p.z + 0.4f) +
                    0.08f * std::sin(23.0f * p.y + 5.0f * p.x);
    p *= r;
  }
  computeNormals(blob);
  const int stone = addMaterial(s, "stone", {0.68f, 0.66f, 0.6f});
  Mesh fixture = blob;
  addObject(s, "blob", std::move(blob), stone, at({0.0f, 1.6f, 0.0f}, 0.0f, 1.3f));
  // A second one above the light (a fixture): it cannot shadow anything the camera sees, and the
  // light's region culls it whole before its 128,000 triangles are flattened (bench shadows shows
  // the time this saves).
  addObject(s, "fixture", std::move(fixture), stone, at({-1.0f, 7.6f, 1.0f}, 30.0f, 0.8f));
  addAreaLight(s, {-1.0f, 6.0f, 1.0f}, {0.15f, -1.0f, -0.1f}, 2.0f, 2.0f, glm::vec3(1.0f), 30.0f);
  return s;
}

// (e) A large light close to the objects: wide penumbrae, umbrae that vanish.
Scene makeBigLight() {
  Scene s = shadowStage("biglight", {0.0f, 5.0f, 6.0f}, {0.0f, 0.3f, 0.0f});
  const int m = addMaterial(s, "clay", {0.72f, 0.7f, 0.68f});
  addObject(s, "cube", makeBox(glm::vec3(1.0f)), m, boxAt({-1.3f, 0.5f, 0.0f}, glm::vec3(1.0f), 30.0f));
  addObject(s, "ball", makeSphere(0.45f, 32, 64), m, at({0.6f, 0.9f, 0.7f}));
  addObject(s, "post", makeCylinder(0.15f, 1.6f, 32), m, at({1.6f, 0.8f, -0.8f}));
  addAreaLight(s, {0.0f, 2.4f, 0.0f}, {0.0f, -1.0f, 0.0f}, 4.0f, 3.0f, glm::vec3(1.0f), 3.0f);
  return s;
}

// --- Curved meshes (docs/performance.md, "Soft shadows on curved meshes") ------------------------
// What scanned and modelled content looks like to the shadow techniques: fine closed meshes with
// self-shadowing concavities, thin protrusions, surfaces turning away from the light (the
// terminator) and feet resting on the ground (contact).

// A lobe of a radial surface: length `len` along unit `axis`, angular width ~sqrt(w) radians.
float lobe(glm::vec3 d, glm::vec3 axis, float len, float w) { return len * std::exp((glm::dot(d, axis) - 1.0f) / w); }

// A four-legged creature: an ellipsoid body, legs splayed down, two thin ears, a head, a thin tail
// and ripples on its back.
float creatureRadius(glm::vec3 d) {
  const float body = 1.0f / std::sqrt(d.x * d.x / (1.25f * 1.25f) + d.y * d.y / (0.75f * 0.75f) + d.z * d.z / (0.8f * 0.8f));
  float r = body;
  for (const float sx : {-1.0f, 1.0f})
    for (const float sz : {-1.0f, 1.0f}) r += lobe(d, glm::normalize(glm::vec3(0.55f * sx, -1.0f, 0.45f * sz)), 1.05f, 0.008f);
  for (const float sz : {-1.0f, 1.0f}) r += lobe(d, glm::normalize(glm::vec3(0.5f, 1.0f, 0.3f * sz)), 0.75f, 0.003f);
  r += lobe(d, glm::normalize(glm::vec3(1.0f, 0.35f, 0.0f)), 0.45f, 0.06f);
  r += lobe(d, glm::normalize(glm::vec3(-1.0f, 0.25f, 0.0f)), 0.9f, 0.003f);
  if (d.y > 0.0f) r += 0.03f * d.y * std::sin(14.0f * d.x) * std::sin(11.0f * d.z);
  return r;
}

// A sphere with deep folds (the "complex" blob's displacement).
float foldsRadius(glm::vec3 d) {
  return 1.0f + 0.22f * std::sin(7.0f * d.x + 1.3f) * std::sin(6.0f * d.y) * std::sin(7.0f * d.z + 0.4f) +
         0.08f * std::sin(23.0f * d.y + 5.0f * d.x);
}

// Stands a mesh on the ground y = 0: the parts lower than `sink` above its lowest point are
// flattened onto it (feet and a flat base with real contact), then it is moved down onto y = 0.
Mesh standOnGround(Mesh m, float sink) {
  float lo = INFINITY;
  for (const glm::vec3& p : m.positions) lo = std::min(lo, p.y);
  const float floor = lo + sink;
  for (glm::vec3& p : m.positions) p.y = std::max(p.y, floor) - floor;
  computeWeldedNormals(m);
  computeBounds(m);
  return m;
}

Mesh creature(int div) { return standOnGround(makeRadialSurface(div, creatureRadius), 0.04f); }
Mesh folds(int div) { return standOnGround(makeRadialSurface(div, foldsRadius), 0.05f); }
// A trefoil lying on the ground: its three lowest strands touch it.
Mesh knot(int segments, int sides) { return standOnGround(makeTorusKnot(2, 3, 1.0f, 0.42f, 0.16f, segments, sides), 0.0f); }

Scene makeCreature() {
  Scene s = shadowStage("creature", {2.6f, 2.8f, 5.2f}, {0.0f, 0.8f, 0.0f});
  addObject(s, "creature", creature(130), addMaterial(s, "clay", {0.74f, 0.66f, 0.56f}), at({0.0f, 0.0f, 0.0f}, 20.0f));
  addAreaLight(s, {-2.4f, 4.6f, 1.8f}, {2.4f, -3.8f, -1.8f}, 1.6f, 1.1f, glm::vec3(1.0f), 30.0f);
  return s;
}

// The growing-light study of the VWSS paper (Marrs et al. 2018, Fig. 8: a character under a light
// that grows to 64 times its area): the creature under a light straight above it, high enough that
// `bench shadows --light-scale 8` keeps it clear of everything (scripts/growing-light.sh).
Scene makeGrowing() {
  Scene s = shadowStage("growing", {2.6f, 2.8f, 5.2f}, {0.0f, 0.8f, 0.0f});
  addObject(s, "creature", creature(130), addMaterial(s, "clay", {0.74f, 0.66f, 0.56f}), at({0.0f, 0.0f, 0.0f}, 20.0f));
  addAreaLight(s, {-0.4f, 4.2f, 0.3f}, {0.0f, -1.0f, 0.0f}, 1.0f, 0.8f, glm::vec3(1.0f), 30.0f);
  return s;
}

Scene makeKnot() {
  Scene s = shadowStage("knot", {0.8f, 3.6f, 5.6f}, {0.3f, 0.6f, 0.0f});
  const int m = addMaterial(s, "stone", {0.7f, 0.68f, 0.64f});
  addObject(s, "knot", knot(1536, 48), m, at({-0.9f, 0.0f, 0.1f}, 15.0f, 1.1f));
  addObject(s, "folds", folds(100), m, at({1.9f, 0.0f, -0.6f}, 0.0f, 0.75f));
  addAreaLight(s, {2.8f, 4.4f, 1.2f}, {-2.8f, -4.2f, -1.2f}, 1.4f, 1.4f, glm::vec3(1.0f), 30.0f);
  return s;
}

// Many objects: creatures, knots and folded blobs of several sizes on one ground (instances of
// three meshes), shadows falling on each other.
Scene makeMenagerie() {
  Scene s = shadowStage("menagerie", {0.0f, 6.5f, 8.5f}, {0.0f, 0.5f, 0.0f});
  const int m = addMaterial(s, "clay", {0.72f, 0.68f, 0.62f});
  const int first = static_cast<int>(s.meshes.size());  // after the ground
  const auto add = [&](const std::string& name, Mesh mesh) {
    mesh.name = name;
    mesh.material = m;
    s.meshes.push_back(std::move(mesh));
  };
  add("creature", creature(60));
  add("knot", knot(768, 24));
  add("folds", folds(60));
  const struct {
    int mesh;
    glm::vec3 p;
    float yaw, scale;
  } placed[] = {{0, {-3.0f, 0, -1.6f}, 30, 0.8f}, {1, {-0.2f, 0, -2.0f}, 10, 0.8f}, {2, {2.6f, 0, -1.8f}, 0, 0.7f},
                {2, {-2.6f, 0, 1.0f}, 40, 0.5f},  {0, {0.4f, 0, 1.0f}, -50, 0.7f}, {1, {2.8f, 0, 0.8f}, 70, 0.6f},
                {1, {-1.2f, 0, 2.6f}, -20, 0.5f}, {0, {1.4f, 0, 2.6f}, 160, 0.5f}, {2, {0.9f, 0, -0.6f}, 0, 0.35f}};
  for (size_t i = 0; i < std::size(placed); ++i) {
    Instance inst;
    inst.mesh = first + placed[i].mesh;
    inst.name = s.meshes[static_cast<size_t>(inst.mesh)].name + " " + std::to_string(i);
    inst.transform = at(placed[i].p, placed[i].yaw, placed[i].scale);
    s.instances.push_back(inst);
  }
  addAreaLight(s, {-2.0f, 6.0f, 2.5f}, {2.0f, -6.0f, -2.5f}, 2.2f, 1.6f, glm::vec3(1.0f), 22.0f);
  return s;
}

// --- Stochastic rasterization scenes ----------------------------------------------------------
// Motion blur, depth of field and both (docs/stochastic.md). A textured ground and static props
// stay on the ordinary path; what moves (or, with a lens, everything) takes the stochastic pass.

Scene stochasticStage(const std::string& name, glm::vec3 eye, glm::vec3 target) {
  Scene s;
  s.name = name;
  const int checker = addChecker(s, 256, 16, {200, 198, 190, 255}, {70, 74, 84, 255});
  Mesh ground = makePlane(24.0f, 24.0f, 8);
  for (glm::vec2& uv : ground.texcoords) uv *= 3.0f;
  addObject(s, "ground", std::move(ground), addMaterial(s, "ground", glm::vec3(1.0f), 0.05f, 16.0f, checker),
            glm::mat4(1.0f));
  Camera cam;
  cam.eye = eye;
  cam.target = target;
  cam.fovYDegrees = 40.0f;
  s.camera = cam;
  s.ambient = glm::vec3(0.08f, 0.085f, 0.1f);
  s.background = glm::vec3(0.32f, 0.42f, 0.55f);
  addAreaLight(s, {-2.0f, 7.0f, 2.0f}, {0.3f, -1.0f, -0.3f}, 2.5f, 2.5f, {1.0f, 0.96f, 0.9f}, 18.0f);
  return s;
}

void moving(Scene& s, const glm::mat4& close) { s.instances.back().transformClose = close; }

// Objects moving fast across the view past static props: a box sliding a quarter of the screen, a
// ball flying towards the camera, a spinning wheel (a quarter turn); columns and a 32,000-triangle
// rock stay still.
void addMovers(Scene& s, float dx) {
  addObject(s, "sliding box", makeBox({1.2f, 0.8f, 0.8f}), addMaterial(s, "red paint", {0.8f, 0.15f, 0.1f}, 0.4f, 64.0f),
            at({-2.4f + dx, 0.4f, 0.8f}, 10.0f));
  moving(s, at({0.4f + dx, 0.4f, 0.8f}, 10.0f));
  addObject(s, "flying ball", makeSphere(0.5f, 32, 64), addMaterial(s, "white", {0.9f, 0.9f, 0.86f}, 0.6f, 96.0f),
            at({1.6f + dx, 1.9f, -2.2f}));
  moving(s, at({0.9f + dx, 1.4f, 0.6f}));
  glm::mat4 wheel = glm::translate(glm::mat4(1.0f), {2.6f + dx, 1.3f, -0.6f});
  wheel = glm::rotate(wheel, 90.0f * kDeg, glm::vec3(1, 0, 0));
  addObject(s, "spinning wheel", makeTorus(0.8f, 0.18f, 64, 24), addMaterial(s, "gold", {0.85f, 0.62f, 0.18f}, 0.8f, 96.0f),
            wheel);
  moving(s, glm::rotate(wheel, 90.0f * kDeg, glm::vec3(0, 1, 0)));
  addObject(s, "spokes", makeBox({1.5f, 0.08f, 0.12f}), s.meshes.back().material, wheel);
  moving(s, glm::rotate(wheel, 90.0f * kDeg, glm::vec3(0, 1, 0)));
}

Scene makeMotion() {
  Scene s = stochasticStage("motion", {0.0f, 2.6f, 8.0f}, {0.0f, 0.9f, 0.0f});
  const int stone = addMaterial(s, "stone", {0.62f, 0.6f, 0.56f});
  for (int i = 0; i < 3; ++i)
    addObject(s, "column " + std::to_string(i), makeCylinder(0.3f, 2.8f, 48), stone,
              at({-3.6f + 3.6f * static_cast<float>(i), 1.4f, -2.0f}));
  Mesh rock = makeSphere(0.7f, 100, 160);
  for (glm::vec3& p : rock.positions) p *= 1.0f + 0.12f * std::sin(9.0f * p.x) * std::sin(8.0f * p.y + 1.0f) * std::sin(9.0f * p.z);
  computeNormals(rock);
  addObject(s, "rock", std::move(rock), stone, at({-2.8f, 0.6f, -0.6f}));
  addMovers(s, 0.0f);
  return s;
}

// A row of objects receding from the camera, focus on the middle one.
void addRow(Scene& s) {
  const int a = addMaterial(s, "teal", {0.1f, 0.55f, 0.6f}, 0.4f, 64.0f);
  const int b = addMaterial(s, "orange", {0.85f, 0.45f, 0.12f}, 0.4f, 64.0f);
  for (int i = 0; i < 9; ++i) {
    const glm::vec3 p(-1.6f + 0.55f * static_cast<float>(i), 0.5f, 3.0f - 2.2f * static_cast<float>(i));
    if (i % 2 == 0)
      addObject(s, "ball " + std::to_string(i), makeSphere(0.5f, 32, 64), a, at(p));
    else
      addObject(s, "box " + std::to_string(i), makeBox(glm::vec3(0.8f)), b, at(p + glm::vec3(0.0f, -0.1f, 0.0f), 30.0f));
  }
}

Scene makeDefocus() {
  Scene s = stochasticStage("defocus", {-1.2f, 1.5f, 7.0f}, {0.6f, 0.6f, -5.8f});
  addRow(s);
  // Focus on ball 4 (the middle of the row).
  const glm::vec3 focus(-1.6f + 0.55f * 4.0f, 0.5f, 3.0f - 2.2f * 4.0f);
  const glm::vec3 view = glm::normalize(s.camera->target - s.camera->eye);
  s.camera->focusDistance = glm::dot(focus - s.camera->eye, view);
  s.camera->apertureRadius = 0.12f;
  return s;
}

Scene makeMotionDefocus() {
  Scene s = makeDefocus();
  s.name = "motion-defocus";
  addMovers(s, 0.6f);
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
  return {{kDefaultScene, "objects (sphere, box, torus, cylinder) on a textured ground plane, an area light and a fill light"},
          {"contact", "shadow bench (a): objects on a plane and at several heights above it (contact hardening)"},
          {"fusion", "shadow bench (b): overlapping occluders at very different depths under a large light"},
          {"thin", "shadow bench (c): a fence of thin slats, poles and a wire"},
          {"complex", "shadow bench (d): a displaced sphere of 128,000 triangles with self-shadowing (and one above the light)"},
          {"biglight", "shadow bench (e): a large light close to the objects"},
          {"creature", "curved meshes: a 202,800-triangle creature with legs, thin ears and a tail standing on the ground"},
          {"knot", "curved meshes: a 147,456-triangle trefoil knot lying on the ground and a 120,000-triangle folded blob"},
          {"menagerie", "curved meshes: nine creatures, knots and folded blobs on one ground (instances of three meshes, 369,792 triangles)"},
          {"growing", "the creature under an overhead light, for the growing-light study (bench shadows --light-scale)"},
          {"motion", "motion blur: a box, a ball and a wheel moving fast past static columns and a rock"},
          {"defocus", "depth of field: a row of objects receding from the camera, focus on the middle one"},
          {"motion-defocus", "both: the defocus row with the moving objects of 'motion' (5D)"},
          {"synth1m", "the synthetic benchmark mesh of WORKLOADS.md: 8x8 UV spheres, 999,936 triangles"},
          {"synth4m", "the synthetic benchmark mesh of WORKLOADS.md: 8x8 UV spheres, 3,968,000 triangles"}};
}

Result<Scene> makeBuiltinScene(const std::string& name) {
  Scene s;
  if (name == kDefaultScene) s = makeDefault();
  else if (name == "contact") s = makeContact();
  else if (name == "fusion") s = makeFusion();
  else if (name == "thin") s = makeThin();
  else if (name == "complex") s = makeComplex();
  else if (name == "biglight") s = makeBigLight();
  else if (name == "creature") s = makeCreature();
  else if (name == "knot") s = makeKnot();
  else if (name == "menagerie") s = makeMenagerie();
  else if (name == "growing") s = makeGrowing();
  else if (name == "motion") s = makeMotion();
  else if (name == "defocus") s = makeDefocus();
  else if (name == "motion-defocus") s = makeMotionDefocus();
  else if (name == "synth1m") s = makeSynth(1000000);
  else if (name == "synth4m") s = makeSynth(4000000);
  else {
    std::string names;
    for (const BuiltinInfo& b : builtinScenes()) {
      if (!names.empty()) names += ", ";
      names += b.name;
    }
    return Error{"built-in scene '" + name + "'", "unknown (valid: " + names + ")"};
  }
  Status st = validateScene(s, "built-in scene " + name);
  if (!st) return st.error();
  return s;
}

}  // namespace penumbra::engine
