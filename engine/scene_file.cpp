#include "engine/scene_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/file_access.h"
#include "engine/gltf_loader.h"
#include "engine/shapes.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Thrown inside the parser with the message of the first problem; turned into an Error naming the
// file at the boundary (parseSceneFile). Never escapes this file.
struct Invalid {
  std::string what;
};

[[noreturn]] void invalid(std::string what) { throw Invalid{std::move(what)}; }

std::string member(const std::string& at, std::string_view key) {
  return at.empty() ? std::string(key) : at + "." + std::string(key);
}
std::string element(const std::string& at, size_t i) { return at + "[" + std::to_string(i) + "]"; }

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void requireObject(const json& j, const std::string& at) {
  if (!j.is_object()) invalid((at.empty() ? std::string("the scene") : at) + " must be a JSON object");
}

// Every key of `obj` must be one of `valid`: catches typos, which would otherwise be ignored.
void checkKeys(const json& obj, const std::string& at, std::initializer_list<std::string_view> valid,
               const std::string& context = "") {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (std::find(valid.begin(), valid.end(), it.key()) != valid.end()) continue;
    std::string list;
    for (std::string_view v : valid) list += (list.empty() ? "" : ", ") + std::string(v);
    invalid((at.empty() ? std::string() : at + ": ") + "unknown key '" + it.key() + "' (valid keys" + context + ": " + list + ")");
  }
}

const json* find(const json& obj, std::string_view key) {
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

const json& required(const json& obj, std::string_view key, const std::string& at) {
  const json* j = find(obj, key);
  if (j == nullptr) invalid(member(at, key) + " is required");
  return *j;
}

float toFloat(const json& j, const std::string& path) {
  if (!j.is_number()) invalid(path + " must be a number");
  const auto v = static_cast<float>(j.get<double>());
  if (!std::isfinite(v)) invalid(path + " is too large");
  return v;
}

// Allowed values of a number: [lo, hi] with either bound open or absent.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool loOpen = false, hiOpen = false;
  bool holds(double v) const { return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi); }
  std::string text() const {
    if (hi == HUGE_VAL) return (loOpen ? "> " : ">= ") + formatNumber(lo);
    if (lo == -HUGE_VAL) return (hiOpen ? "< " : "<= ") + formatNumber(hi);
    return std::string("in ") + (loOpen ? "(" : "[") + formatNumber(lo) + ", " + formatNumber(hi) + (hiOpen ? ")" : "]");
  }
};
const Range kAny{};
const Range kPositive{0.0, HUGE_VAL, true, false};
const Range kNonNegative{0.0, HUGE_VAL, false, false};
const Range kUnit{0.0, 1.0, false, false};

float checked(const json& j, const std::string& path, const Range& range) {
  const float v = toFloat(j, path);
  if (!range.holds(static_cast<double>(v))) invalid(path + " must be " + range.text());
  return v;
}

float number(const json& obj, std::string_view key, const std::string& at, float fallback, const Range& range) {
  const json* j = find(obj, key);
  return j == nullptr ? fallback : checked(*j, member(at, key), range);
}

int integer(const json& obj, std::string_view key, const std::string& at, int fallback, int lo, int hi) {
  const json* j = find(obj, key);
  if (j == nullptr) return fallback;
  const std::string path = member(at, key);
  const std::string expected = path + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!j->is_number()) invalid(expected);
  const double v = j->get<double>();
  if (v != std::floor(v) || v < lo || v > hi) invalid(expected);
  return static_cast<int>(v);
}

std::string text(const json& obj, std::string_view key, const std::string& at, const std::string& fallback) {
  const json* j = find(obj, key);
  if (j == nullptr) return fallback;
  if (!j->is_string()) invalid(member(at, key) + " must be a string");
  return j->get<std::string>();
}

template <int N>
glm::vec<N, float> vector(const json& j, const std::string& path, const Range& range) {
  if (!j.is_array() || j.size() != static_cast<size_t>(N) ||
      !std::all_of(j.begin(), j.end(), [](const json& e) { return e.is_number(); }))
    invalid(path + " must be an array of " + std::to_string(N) + " numbers");
  glm::vec<N, float> v;
  for (int i = 0; i < N; ++i) v[i] = checked(j[static_cast<size_t>(i)], element(path, static_cast<size_t>(i)), range);
  return v;
}

glm::vec3 vec3(const json& obj, std::string_view key, const std::string& at, glm::vec3 fallback, const Range& range) {
  const json* j = find(obj, key);
  return j == nullptr ? fallback : vector<3>(*j, member(at, key), range);
}

// A size given as one number (all axes) or as N numbers, each > 0.
template <int N>
glm::vec<N, float> size(const json& obj, std::string_view key, const std::string& at, float fallback) {
  const json* j = find(obj, key);
  if (j == nullptr) return glm::vec<N, float>(fallback);
  const std::string path = member(at, key);
  if (j->is_number()) return glm::vec<N, float>(checked(*j, path, kPositive));
  if (!j->is_array()) invalid(path + " must be a number or an array of " + std::to_string(N) + " numbers");
  return vector<N>(*j, path, kPositive);
}

glm::vec3 direction(const json& obj, std::string_view key, const std::string& at) {
  const glm::vec3 d = vector<3>(required(obj, key, at), member(at, key), kAny);
  const float len = glm::length(d);
  if (!(len > 0.0f) || !std::isfinite(len)) invalid(member(at, key) + " must not be a zero vector");
  return d / len;
}

// transform: {"translate": [x, y, z], "rotate_deg": [x, y, z] | "rotate_axis_deg": [ax, ay, az, deg],
// "scale": s | [x, y, z]}; M = T R S. rotate_deg rotates about x, then y, then z (R = Rz Ry Rx).
glm::mat4 transform(const json& obj, const std::string& at) {
  const json* t = find(obj, "transform");
  if (t == nullptr) return glm::mat4(1.0f);
  const std::string path = member(at, "transform");
  requireObject(*t, path);
  checkKeys(*t, path, {"translate", "rotate_deg", "rotate_axis_deg", "scale"});
  const glm::vec3 translate = vec3(*t, "translate", path, glm::vec3(0.0f), kAny);
  glm::mat4 rotate(1.0f);
  const json* euler = find(*t, "rotate_deg");
  const json* axisAngle = find(*t, "rotate_axis_deg");
  if (euler != nullptr && axisAngle != nullptr) invalid(path + ": give rotate_deg or rotate_axis_deg, not both");
  if (euler != nullptr) {
    const glm::vec3 deg = vector<3>(*euler, member(path, "rotate_deg"), kAny);
    rotate = glm::rotate(glm::mat4(1.0f), glm::radians(deg.z), glm::vec3(0, 0, 1)) *
             glm::rotate(glm::mat4(1.0f), glm::radians(deg.y), glm::vec3(0, 1, 0)) *
             glm::rotate(glm::mat4(1.0f), glm::radians(deg.x), glm::vec3(1, 0, 0));
  }
  if (axisAngle != nullptr) {
    const std::string p = member(path, "rotate_axis_deg");
    const glm::vec4 aa = vector<4>(*axisAngle, p, kAny);
    const glm::vec3 axis(aa);
    const float len = glm::length(axis);
    if (!(len > 0.0f) || !std::isfinite(len)) invalid(p + ": the axis must not be a zero vector");
    rotate = glm::rotate(glm::mat4(1.0f), glm::radians(aa.w), axis / len);
  }
  const glm::vec3 scale = size<3>(*t, "scale", path, 1.0f);
  return glm::translate(glm::mat4(1.0f), translate) * rotate * glm::scale(glm::mat4(1.0f), scale);
}

class SceneParser {
 public:
  SceneParser(std::string path, const LoadOptions& options) : path_(std::move(path)), options_(options) {}

  Scene parse(const json& root) {
    requireObject(root, "");
    checkKeys(root, "", {"name", "gltf", "objects", "camera", "lights", "ambient", "background"});
    scene_.name = text(root, "name", "", fs::path(path_).stem().string());
    if (const json* g = find(root, "gltf")) forEach(*g, "gltf", [&](const json& e, const std::string& at) { gltf(e, at); });
    if (const json* o = find(root, "objects")) {
      // Twice: the shapes' triangles are counted (and capped) for all of them before any is built.
      counting_ = true;
      forEach(*o, "objects", [&](const json& e, const std::string& at) { object(e, at); });
      counting_ = false;
      forEach(*o, "objects", [&](const json& e, const std::string& at) { object(e, at); });
    }
    if (const json* c = find(root, "camera")) camera(*c, "camera");
    if (const json* l = find(root, "lights")) forEach(*l, "lights", [&](const json& e, const std::string& at) { light(e, at); });
    scene_.ambient = vec3(root, "ambient", "", scene_.ambient, kNonNegative);
    scene_.background = vec3(root, "background", "", scene_.background, kNonNegative);
    return std::move(scene_);
  }

 private:
  template <class F>
  void forEach(const json& array, const std::string& at, F&& f) {
    if (!array.is_array()) invalid(at + " must be an array");
    for (size_t i = 0; i < array.size(); ++i) f(array[i], element(at, i));
  }

  // {"file": "model.glb", "transform": {...}}: the glTF scene's instances placed by the transform.
  void gltf(const json& e, const std::string& at) {
    requireObject(e, at);
    checkKeys(e, at, {"file", "transform"});
    const json& file = required(e, "file", at);
    if (!file.is_string() || file.get<std::string>().empty()) invalid(member(at, "file") + " must be a non-empty string");
    const std::string name = file.get<std::string>();
    // Inside the scene file's folder (file_access.h).
    Result<fs::path> p = resolveReference(fs::path(path_).parent_path(), name, options_, path_,
                                          member(at, "file") + " ('" + name + "')");
    if (!p) invalid(p.error().what);
    const glm::mat4 m = transform(e, at);
    Result<Scene> loaded = loadGltf(p->string(), options_);
    if (!loaded) invalid(member(at, "file") + ": " + loaded.error().line());
    Scene& sub = *loaded;
    scene_.sourceFiles.insert(scene_.sourceFiles.end(), sub.sourceFiles.begin(), sub.sourceFiles.end());
    const int meshBase = static_cast<int>(scene_.meshes.size());
    const int materialBase = static_cast<int>(scene_.materials.size());
    const int textureBase = static_cast<int>(scene_.textures.size());
    for (Texture& t : sub.textures) scene_.textures.push_back(std::move(t));
    for (Material& mat : sub.materials) {
      if (mat.baseColorTexture >= 0) mat.baseColorTexture += textureBase;
      scene_.materials.push_back(std::move(mat));
    }
    for (Mesh& mesh : sub.meshes) {
      if (mesh.material >= 0) mesh.material += materialBase;
      scene_.meshes.push_back(std::move(mesh));
    }
    for (Instance& inst : sub.instances) {
      inst.mesh += meshBase;
      inst.transform = m * inst.transform;
      scene_.instances.push_back(std::move(inst));
    }
    // The first glTF camera is used unless the scene file sets one (parsed later, it replaces this).
    if (sub.camera && !scene_.camera) {
      Camera c = *sub.camera;
      c.eye = glm::vec3(m * glm::vec4(c.eye, 1.0f));
      c.target = glm::vec3(m * glm::vec4(c.target, 1.0f));
      c.up = glm::normalize(glm::vec3(m * glm::vec4(c.up, 0.0f)));
      scene_.camera = c;
    }
  }

  void material(const json& e, const std::string& at, Mesh& mesh) {
    requireObject(e, at);
    checkKeys(e, at, {"name", "color", "specular", "shininess"});
    Material mat;
    mat.name = text(e, "name", at, mesh.name);
    mat.baseColorFactor = glm::vec4(vec3(e, "color", at, glm::vec3(mat.baseColorFactor), kUnit), 1.0f);
    mat.specular = number(e, "specular", at, mat.specular, kUnit);
    mat.shininess = number(e, "shininess", at, mat.shininess, Range{1.0, 4096.0, false, false});
    scene_.materials.push_back(mat);
    mesh.material = static_cast<int>(scene_.materials.size()) - 1;
  }

  // {"shape": ..., shape parameters, "name", "material", "transform"}.
  void object(const json& e, const std::string& at) {
    requireObject(e, at);
    const json& shapeJson = required(e, "shape", at);
    const std::string shape = shapeJson.is_string() ? shapeJson.get<std::string>() : std::string();
    const std::string context = " for shape '" + shape + "'";
    constexpr int kMaxSteps = 4096;  // subdivisions per axis: 4096^2 quads is 33.5 M triangles
    // The shape's triangles are counted (and capped) in the counting pass; only then built.
    bool counted = false;
    auto reserve = [&](size_t triangles) {
      if (!counting_) return;
      triangles_ += triangles;
      const size_t cap = options_.maxTriangles > 0 ? std::min(options_.maxTriangles, kMaxSceneTriangles) : kMaxSceneTriangles;
      if (triangles_ > cap) invalid(at + ": the scene's shapes exceed " + std::to_string(cap) + " triangles");
      counted = true;
    };
    Mesh mesh;
    if (shape == "plane") {
      checkKeys(e, at, {"shape", "name", "material", "transform", "motion", "size", "divisions"}, context);
      const glm::vec2 s = size<2>(e, "size", at, 1.0f);
      const int div = integer(e, "divisions", at, 1, 1, kMaxSteps);
      reserve(planeTriangles(div));
      if (!counted) mesh = makePlane(s.x, s.y, div);
    } else if (shape == "box") {
      checkKeys(e, at, {"shape", "name", "material", "transform", "motion", "size"}, context);
      reserve(12);
      if (!counted) mesh = makeBox(size<3>(e, "size", at, 1.0f));
    } else if (shape == "sphere") {
      checkKeys(e, at, {"shape", "name", "material", "transform", "motion", "radius", "rings", "segments"}, context);
      const float radius = number(e, "radius", at, 0.5f, kPositive);
      const int rings = integer(e, "rings", at, 16, 2, kMaxSteps), segments = integer(e, "segments", at, 32, 3, kMaxSteps);
      reserve(sphereTriangles(rings, segments));
      if (!counted) mesh = makeSphere(radius, rings, segments);
    } else if (shape == "cylinder") {
      checkKeys(e, at, {"shape", "name", "material", "transform", "motion", "radius", "height", "segments"}, context);
      const float radius = number(e, "radius", at, 0.5f, kPositive), height = number(e, "height", at, 1.0f, kPositive);
      const int segments = integer(e, "segments", at, 32, 3, kMaxSteps);
      reserve(cylinderTriangles(segments));
      if (!counted) mesh = makeCylinder(radius, height, segments);
    } else if (shape == "torus") {
      checkKeys(e, at, {"shape", "name", "material", "transform", "motion", "major_radius", "minor_radius", "rings", "segments"},
                context);
      const float major = number(e, "major_radius", at, 0.5f, kPositive);
      const float minor = number(e, "minor_radius", at, 0.125f, kPositive);
      if (!(minor < major)) invalid(member(at, "minor_radius") + " must be < major_radius");
      const int rings = integer(e, "rings", at, 32, 3, kMaxSteps), segments = integer(e, "segments", at, 16, 3, kMaxSteps);
      reserve(torusTriangles(rings, segments));
      if (!counted) mesh = makeTorus(major, minor, rings, segments);
    } else {
      invalid(member(at, "shape") + " must be one of 'plane', 'box', 'sphere', 'cylinder', 'torus'");
    }
    if (counted) return;
    mesh.name = text(e, "name", at, shape + " " + std::to_string(scene_.meshes.size()));
    if (const json* m = find(e, "material")) material(*m, member(at, "material"), mesh);
    const glm::mat4 m = transform(e, at);
    Instance inst{mesh.name, static_cast<int>(scene_.meshes.size()), m, std::nullopt};
    // "motion": the transform at shutter close (same keys as "transform"); "transform" is at open.
    if (const json* mo = find(e, "motion")) {
      requireObject(*mo, member(at, "motion"));
      json wrapper = json::object();
      wrapper["transform"] = *mo;
      inst.transformClose = transform(wrapper, member(at, "motion"));
    }
    scene_.instances.push_back(std::move(inst));
    scene_.meshes.push_back(std::move(mesh));
  }

  void camera(const json& e, const std::string& at) {
    requireObject(e, at);
    checkKeys(e, at, {"eye", "target", "up", "fov_deg", "near", "far", "aperture", "focus_distance"});
    Camera c;
    c.eye = vec3(e, "eye", at, c.eye, kAny);
    c.target = vec3(e, "target", at, c.target, kAny);
    c.up = vec3(e, "up", at, c.up, kAny);
    c.fovYDegrees = number(e, "fov_deg", at, c.fovYDegrees, Range{0.0, 180.0, true, true});
    c.znear = number(e, "near", at, 0.0f, kNonNegative);
    c.zfar = number(e, "far", at, 0.0f, kNonNegative);
    c.apertureRadius = number(e, "aperture", at, 0.0f, kNonNegative);
    c.focusDistance = number(e, "focus_distance", at, 0.0f, kNonNegative);
    if (c.znear > 0.0f && c.zfar > 0.0f && !(c.zfar > c.znear)) invalid(member(at, "far") + " must be > near");
    const glm::vec3 view = c.target - c.eye;
    if (!(glm::length(view) > 0.0f)) invalid(member(at, "target") + " must differ from eye");
    if (!(glm::length(c.up) > 0.0f)) invalid(member(at, "up") + " must not be a zero vector");
    c.up = glm::normalize(c.up);
    if (!(glm::length(glm::cross(glm::normalize(view), c.up)) > 1e-6f))
      invalid(member(at, "up") + " must not be parallel to the view direction");
    scene_.camera = c;
  }

  void light(const json& e, const std::string& at) {
    requireObject(e, at);
    const json& typeJson = required(e, "type", at);
    const std::string type = typeJson.is_string() ? typeJson.get<std::string>() : std::string();
    if (type == "directional") {
      checkKeys(e, at, {"type", "direction", "color", "intensity"}, " for a directional light");
      DirectionalLight l;
      l.direction = direction(e, "direction", at);
      l.color = vec3(e, "color", at, l.color, kNonNegative);
      l.intensity = number(e, "intensity", at, l.intensity, kNonNegative);
      scene_.directionalLights.push_back(l);
    } else if (type == "point") {
      checkKeys(e, at, {"type", "position", "color", "intensity"}, " for a point light");
      PointLight l;
      l.position = vector<3>(required(e, "position", at), member(at, "position"), kAny);
      l.color = vec3(e, "color", at, l.color, kNonNegative);
      l.intensity = number(e, "intensity", at, l.intensity, kNonNegative);
      scene_.pointLights.push_back(l);
    } else if (type == "spot") {
      checkKeys(e, at, {"type", "position", "direction", "color", "intensity", "inner_deg", "outer_deg"}, " for a spot light");
      SpotLight l;
      l.position = vector<3>(required(e, "position", at), member(at, "position"), kAny);
      l.direction = direction(e, "direction", at);
      l.color = vec3(e, "color", at, l.color, kNonNegative);
      l.intensity = number(e, "intensity", at, l.intensity, kNonNegative);
      const float outer = number(e, "outer_deg", at, 45.0f, Range{0.0, 90.0, true, false});
      const float inner = number(e, "inner_deg", at, 0.0f, Range{0.0, static_cast<double>(outer), false, true});
      l.innerCone = glm::radians(inner);
      l.outerCone = glm::radians(outer);
      scene_.spotLights.push_back(l);
    } else if (type == "area") {
      checkKeys(e, at, {"type", "center", "normal", "width_axis", "width", "height", "color", "intensity"},
                " for an area light");
      const glm::vec3 center = vector<3>(required(e, "center", at), member(at, "center"), kAny);
      const glm::vec3 normal = direction(e, "normal", at);
      const glm::vec3 axis = vec3(e, "width_axis", at, glm::vec3(1, 0, 0), kAny);
      const float width = number(e, "width", at, 1.0f, Range{0.0, HUGE_VAL, true, false});
      const float height = number(e, "height", at, 1.0f, Range{0.0, HUGE_VAL, true, false});
      const glm::vec3 color = vec3(e, "color", at, glm::vec3(1.0f), kNonNegative);
      const float intensity = number(e, "intensity", at, 1.0f, kNonNegative);
      shadows::RectLight l;
      std::string why;
      if (!shadows::makeRectLight(center, normal, axis, width, height, color, intensity, l, &why)) invalid(at + ": " + why);
      scene_.areaLights.push_back(l);
    } else {
      invalid(member(at, "type") + " must be 'directional', 'point', 'spot' or 'area'");
    }
  }

  // Procedural shapes may hold at most this many triangles in all (a few lines of JSON could
  // otherwise ask for gigabytes).
  static constexpr size_t kMaxSceneTriangles = size_t{1} << 26;
  size_t triangles_ = 0;
  bool counting_ = false;
  std::string path_;
  LoadOptions options_;
  Scene scene_;
};

// "[json.exception.parse_error.101] parse error at line 2, column 8: syntax error ..." ->
// "invalid JSON at line 2, column 8: syntax error ...", on one line.
std::string describeParseError(const json::parse_error& e) {
  std::string what = e.what();
  std::replace_if(what.begin(), what.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
  const size_t at = what.find(" at line ");
  if (at != std::string::npos) return "invalid JSON" + what.substr(at);
  return "invalid JSON at byte " + std::to_string(e.byte) + ": " + what;
}

// Where in the text the first JSON error is, for the errors nlohmann reports without one (a number
// out of range: "number overflow parsing '1e400'"): its SAX parser hands the byte to parse_error.
struct ErrorPosition : nlohmann::json_sax<json> {
  size_t byte = 0;
  bool found = false;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception&) override {
    byte = position;
    found = true;
    return false;
  }
};

// "number overflow parsing '1e400'" -> "invalid JSON at line 1, column 14: number overflow parsing '1e400'".
std::string describeJsonError(const std::string& text, const json::exception& e) {
  std::string what = e.what();
  const size_t bracket = what.find("] ");
  if (what.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) what = what.substr(bracket + 2);
  ErrorPosition pos;
  try {
    json::sax_parse(text, &pos);
  } catch (const std::exception&) {
  }
  if (!pos.found) return "invalid JSON: " + what;
  size_t line = 1, column = 1;
  for (size_t i = 0; i + 1 < pos.byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what;
}

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

Result<Scene> parseSceneFile(const std::string& text, const std::string& path, const LoadOptions& options) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    return Error{path, describeParseError(e)};
  } catch (const json::exception& e) {  // a number out of range
    return Error{path, describeJsonError(text, e)};
  }
  Scene scene;
  try {
    scene = SceneParser(path, options).parse(root);
  } catch (const Invalid& e) {
    return Error{path, e.what};
  } catch (const json::exception& e) {
    return Error{path, std::string("invalid scene: ") + e.what()};
  } catch (const std::bad_alloc&) {
    return Error{path, "out of memory building the scene"};
  }
  if (Status s = validateScene(scene, path); !s) return s.error();
  return scene;
}

Result<Scene> loadSceneFile(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{path, "cannot open file"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path, "cannot open file"};
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Error{path, "cannot read file"};
  Result<Scene> scene = parseSceneFile(text.str(), path, options);
  if (scene) scene->sourceFiles.insert(scene->sourceFiles.begin(), fs::weakly_canonical(path, ec).string());
  return scene;
}

Result<Scene> loadScene(const std::string& path, const LoadOptions& options) {
  const std::string ext = lowerExtension(path);
  if (ext == ".gltf" || ext == ".glb") return loadGltf(path, options);
  if (ext == ".json") return loadSceneFile(path, options);
  return Error{path, "unknown scene file type (expected .gltf, .glb or .json)"};
}

}  // namespace penumbra::engine
