// The Python module penumbra._penumbra (re-exported by penumbra/__init__.py): scenes from NumPy
// arrays or files, render() and rasterize() returning dicts of arrays. Bindings only; the work is
// in render.cpp and the argument checks in convert.cpp.
#include <pybind11/stl.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "convert.h"
#include "engine/builtin_scenes.h"
#include "engine/scene_file.h"
#include "engine/version.h"
#include "render.h"
#include "shadows/technique.h"

namespace penumbra::python {
namespace {

using namespace pybind11::literals;

std::shared_ptr<PyScene> wrap(engine::Result<engine::Scene> r) {
  if (!r) raise(r.error());
  auto s = std::make_shared<PyScene>();
  s->scene = std::move(*r);
  s->validated = true;  // the loaders validate
  return s;
}

int addMesh(PyScene& s, py::handle vertices, py::handle triangles, py::handle normals, py::handle uvs,
            py::handle colors, py::handle color, py::handle transform, const std::string& name, bool place) {
  engine::Mesh m;
  m.name = name;
  m.positions = vec3Rows(vertices, "vertices");
  m.indices = triangleRows(triangles, m.positions.size(), "triangles");
  const auto sameCount = [&](size_t n, const char* what) {
    if (n != m.positions.size())
      raise(std::string(what) + ": " + std::to_string(n) + " rows, expected one per vertex (" +
            std::to_string(m.positions.size()) + ")");
  };
  if (!normals.is_none()) sameCount((m.normals = vec3Rows(normals, "normals")).size(), "normals");
  if (!uvs.is_none()) sameCount((m.texcoords = vec2Rows(uvs, "uvs")).size(), "uvs");
  if (!colors.is_none()) sameCount((m.colors = vec3Rows(colors, "colors")).size(), "colors");
  engine::Material mat;
  mat.name = name;
  mat.baseColorFactor = colorValue(color, "color");
  const glm::mat4 t = transform.is_none() ? glm::mat4(1.0f) : matrix4(transform, "transform");
  s.beginChange("add_mesh");
  m.material = static_cast<int>(s.scene.materials.size());
  s.scene.materials.push_back(mat);
  s.scene.meshes.push_back(std::move(m));
  const int mesh = static_cast<int>(s.scene.meshes.size()) - 1;
  if (place) s.scene.instances.push_back({.name = name, .mesh = mesh, .transform = t});
  return mesh;
}

int addInstance(PyScene& s, int mesh, py::handle transform, py::handle transformClose,
                const std::string& name) {
  if (mesh < 0 || mesh >= static_cast<int>(s.scene.meshes.size()))
    raise("add_instance: mesh " + std::to_string(mesh) + " out of range (" +
          std::to_string(s.scene.meshes.size()) + " meshes)");
  engine::Instance inst{.name = name, .mesh = mesh};
  if (!transform.is_none()) inst.transform = matrix4(transform, "transform");
  if (!transformClose.is_none()) inst.transformClose = matrix4(transformClose, "transform_close");
  s.beginChange("add_instance");
  s.scene.instances.push_back(inst);
  return static_cast<int>(s.scene.instances.size()) - 1;
}

// A camera from 4 x 4 view and projection matrices (NumPy's row convention, OpenGL's camera
// looking down -z): eye, direction and up from the inverse view; fov, near and far from a
// symmetric perspective projection with depth range "gl" ([-1, 1]) or "zero_to_one".
void setCameraMatrices(PyScene& s, py::handle view, py::handle projection, const std::string& depth) {
  const glm::mat4 v = matrix4(view, "view"), p = matrix4(projection, "projection");
  if (depth != "gl" && depth != "zero_to_one")
    raise("depth: expected 'gl' or 'zero_to_one', got '" + depth + "'");
  const glm::mat3 r(v);
  if (v[0][3] != 0.0f || v[1][3] != 0.0f || v[2][3] != 0.0f || v[3][3] != 1.0f ||
      std::abs(glm::determinant(r) - 1.0f) > 1e-3f)
    raise("view: expected a rigid transform (rotation and translation)");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(glm::dot(r[i], r[j]) - (i == j ? 1.0f : 0.0f)) > 1e-3f)
        raise("view: expected a rigid transform (rotation and translation)");
  // glm's p[c][r]: a symmetric perspective has only (0,0), (1,1), (2,2), (2,3) = -1 and (3,2) set.
  const bool perspective = p[0][1] == 0 && p[0][2] == 0 && p[0][3] == 0 && p[1][0] == 0 && p[1][2] == 0 &&
                           p[1][3] == 0 && p[2][0] == 0 && p[2][1] == 0 && p[2][3] == -1.0f && p[3][0] == 0 &&
                           p[3][1] == 0 && p[3][3] == 0 && p[0][0] > 0 && p[1][1] > 0;
  if (!perspective)
    raise(
        "projection: expected a symmetric perspective projection (no skew, no off-centre, not orthographic)");
  const glm::mat4 c = glm::inverse(v);
  engine::Camera cam;
  cam.eye = glm::vec3(c[3]);
  cam.target = cam.eye - glm::vec3(c[2]);
  cam.up = glm::vec3(c[1]);
  cam.fovYDegrees = static_cast<float>(2.0 * std::atan(1.0 / static_cast<double>(p[1][1])) * 180.0 / M_PI);
  const double a = p[2][2], b = p[3][2];
  // A finite far plane gives a < -1 in both conventions; a = -1 is the infinite far plane.
  const double n = depth == "gl" ? b / (a - 1.0) : b / a;
  const double f = a < -1.0 ? b / (a + 1.0) : INFINITY;
  if (!(n > 0.0) || !std::isfinite(n) || !(f > n))
    raise("projection: its near and far planes are not 0 < near < far");
  cam.znear = static_cast<float>(n);
  cam.zfar = std::isfinite(f) ? static_cast<float>(f) : 0.0f;
  s.beginChange("set_camera_matrices");
  s.scene.camera = cam;
  s.cameraAspect = p[1][1] / p[0][0];
}

py::list techniqueList() {
  py::list out;
  for (const shadows::TechniqueInfo& t : shadows::registry()) {
    py::list params;
    for (const shadows::ParamSpec& p : t.params) {
      const char* kind = p.kind == shadows::ParamKind::Int     ? "int"
                         : p.kind == shadows::ParamKind::Float ? "float"
                                                               : "choice";
      py::dict d("name"_a = p.name, "kind"_a = kind, "help"_a = p.help);
      if (p.kind == shadows::ParamKind::Choice) {
        d["choices"] = p.choices;
        d["default"] = p.choices.at(static_cast<size_t>(p.defaultValue));
      } else {
        d["default"] = p.defaultValue, d["min"] = p.minValue, d["max"] = p.maxValue;
      }
      params.append(d);
    }
    out.append(py::dict("name"_a = t.name, "summary"_a = t.summary, "params"_a = params));
  }
  return out;
}

std::vector<std::string> paramList(py::handle params) {
  std::vector<std::string> out;
  if (params.is_none()) return out;
  if (py::isinstance<py::str>(params)) return {params.cast<std::string>()};
  if (py::isinstance<py::dict>(params)) {
    for (auto [k, v] : params.cast<py::dict>()) {
      const std::string value =
          py::isinstance<py::bool_>(v) ? (v.cast<bool>() ? "1" : "0") : std::string(py::str(v));
      out.push_back(std::string(py::str(k)) + "=" + value);
    }
    return out;
  }
  raise("params: expected a dict {name: value} or a string 'name=value,...'");
}

void bindScene(py::module_& m) {
  py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene",
                                                "A scene: meshes placed by instances, lights, a camera.")
      .def(py::init([](const std::string& name) {
             auto s = std::make_shared<PyScene>();
             s->scene.name = name;
             return s;
           }),
           "name"_a = "")
      .def("add_mesh", &addMesh, "vertices"_a, "triangles"_a, "normals"_a = py::none(), "uvs"_a = py::none(),
           "colors"_a = py::none(), "color"_a = py::make_tuple(0.8, 0.8, 0.8), "transform"_a = py::none(),
           "name"_a = "", "place"_a = true,
           "Adds a mesh (vertices N x 3, triangles M x 3 integer; optional per-vertex normals N x 3, uvs N x "
           "2,\n"
           "linear RGB colors N x 3 multiplying `color`) and, unless place=False, one instance of it at\n"
           "`transform` (4 x 4, object to world). Returns the mesh index.")
      .def("add_instance", &addInstance, "mesh"_a, "transform"_a = py::none(),
           "transform_close"_a = py::none(), "name"_a = "",
           "Places mesh `mesh` at `transform`; with `transform_close` it moves to that transform over the "
           "shutter\n"
           "(motion blur). Returns the instance index.")
      .def(
          "set_camera",
          [](PyScene& s, py::handle eye, py::handle target, float fov, py::handle up, float znear, float zfar,
             float aperture, float focus) {
            engine::Camera c{.eye = vec3Value(eye, "eye"),
                             .target = vec3Value(target, "target"),
                             .up = vec3Value(up, "up"),
                             .fovYDegrees = fov,
                             .znear = znear,
                             .zfar = zfar,
                             .apertureRadius = aperture,
                             .focusDistance = focus};
            s.beginChange("set_camera");
            s.scene.camera = c;
            s.cameraAspect.reset();
          },
          "eye"_a, "target"_a, "fov"_a = 45.0f, "up"_a = py::make_tuple(0, 1, 0), "near"_a = 0.0f,
          "far"_a = 0.0f, "aperture"_a = 0.0f, "focus"_a = 0.0f,
          "A perspective camera: vertical fov in degrees; near/far 0 fit the scene; aperture > 0 a thin "
          "lens.")
      .def("set_camera_matrices", &setCameraMatrices, "view"_a, "projection"_a, "depth"_a = "gl",
           "A camera from 4 x 4 view and projection matrices (symmetric perspective; depth 'gl' or "
           "'zero_to_one').")
      .def(
          "add_area_light",
          [](PyScene& s, py::handle center, py::handle facing, float width, float height, py::handle color,
             float intensity, py::handle widthHint) {
            shadows::RectLight l;
            std::string why;
            if (!shadows::makeRectLight(vec3Value(center, "center"), vec3Value(facing, "facing"),
                                        vec3Value(widthHint, "width_hint"), width, height,
                                        glm::vec3(colorValue(color, "color")), intensity, l, &why))
              raise("add_area_light: " + why);
            s.beginChange("add_area_light");
            s.scene.areaLights.push_back(l);
            return s.scene.areaLights.size() - 1;
          },
          "center"_a, "facing"_a, "width"_a = 1.0f, "height"_a = 1.0f, "color"_a = py::make_tuple(1, 1, 1),
          "intensity"_a = 1.0f, "width_hint"_a = py::make_tuple(1, 0, 0),
          "A rectangular area light (casts the soft shadows) emitting towards `facing`.")
      .def(
          "add_directional_light",
          [](PyScene& s, py::handle direction, py::handle color, float intensity) {
            const glm::vec3 d = vec3Value(direction, "direction");
            if (!(glm::length(d) > 0.0f)) raise("add_directional_light: direction is zero");
            if (!(intensity >= 0.0f) || !std::isfinite(intensity))
              raise("add_directional_light: intensity must be >= 0");
            s.beginChange("add_directional_light");
            s.scene.directionalLights.push_back(
                {glm::normalize(d), glm::vec3(colorValue(color, "color")), intensity});
          },
          "direction"_a, "color"_a = py::make_tuple(1, 1, 1), "intensity"_a = 1.0f,
          "An unshadowed directional light.")
      .def(
          "add_point_light",
          [](PyScene& s, py::handle position, py::handle color, float intensity, float range) {
            if (!(intensity >= 0.0f) || !std::isfinite(intensity))
              raise("add_point_light: intensity must be >= 0");
            if (!(range >= 0.0f) || !std::isfinite(range)) raise("add_point_light: range must be >= 0");
            s.beginChange("add_point_light");
            s.scene.pointLights.push_back(
                {vec3Value(position, "position"), glm::vec3(colorValue(color, "color")), intensity, range});
          },
          "position"_a, "color"_a = py::make_tuple(1, 1, 1), "intensity"_a = 1.0f, "range"_a = 0.0f,
          "An unshadowed point light (1 / d^2 falloff).")
      .def(
          "set_sky",
          [](PyScene& s, py::handle sky, py::handle ground) {
            engine::SkyLight l{glm::vec3(colorValue(sky, "sky")), glm::vec3(colorValue(ground, "ground"))};
            s.beginChange("set_sky");
            s.scene.sky = l;
          },
          "sky"_a, "ground"_a, "Ambient light from above (sky) and below (ground), linear RGB.")
      .def_property_readonly("triangle_count", [](const PyScene& s) { return s.scene.triangleCount(); })
      .def_property_readonly("mesh_count", [](const PyScene& s) { return s.scene.meshes.size(); })
      .def_property_readonly("instance_count", [](const PyScene& s) { return s.scene.instances.size(); })
      .def_property_readonly(
          "area_light_count",
          [](const PyScene& s) { return s.scene.defaultLighting ? size_t{0} : s.scene.areaLights.size(); })
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def("__repr__", [](const PyScene& s) {
        return "<penumbra.Scene '" + s.scene.name + "': " + std::to_string(s.scene.meshes.size()) +
               " meshes, " + std::to_string(s.scene.instances.size()) + " instances, " +
               std::to_string(s.scene.triangleCount()) + " triangles>";
      });
}

}  // namespace
}  // namespace penumbra::python

PYBIND11_MODULE(_penumbra, m) {
  namespace pp = penumbra::python;
  namespace py = pybind11;
  using namespace pybind11::literals;
  m.doc() = "Penumbra's native module; use the package `penumbra`.";
  m.attr("__version__") = penumbra::kVersion;
  py::register_exception<pp::PenumbraError>(m, "Error", PyExc_ValueError);
  pp::bindScene(m);
  m.def(
      "load",
      [](const std::string& path, bool allowOutsidePaths) {
        return pp::wrap(penumbra::engine::loadScene(path, {.allowOutsidePaths = allowOutsidePaths}));
      },
      "path"_a, "allow_outside_paths"_a = false,
      "Loads a glTF 2.0 file (.gltf, .glb) or a scene file (.json). Files it names must lie in its folder.");
  m.def(
      "builtin", [](const std::string& name) { return pp::wrap(penumbra::engine::makeBuiltinScene(name)); },
      "name"_a, "A built-in scene (builtins() lists them).");
  m.def(
      "builtins",
      [] {
        py::list out;
        for (const auto& b : penumbra::engine::builtinScenes())
          out.append(py::dict("name"_a = b.name, "description"_a = b.description));
        return out;
      },
      "The built-in scenes: a list of {name, description}.");
  m.def("techniques", &pp::techniqueList, "The shadow techniques and their parameters (ranges, defaults).");
  m.def("aov_names", &pp::aovNames, "The buffers render() can return besides color and linear.");
  m.def(
      "render",
      [](pp::PyScene& s, int width, int height, const std::string& shadow, py::handle params, int spp,
         int msaa, int threads, std::vector<std::string> aov, double exposure, const std::string& tonemap,
         int64_t frame, bool stats, bool defaultLight, uint64_t maxMemory) {
        if (aov.size() == 1 && aov[0] == "all") aov = pp::aovNames();
        return pp::render(s, {width, height, shadow, pp::paramList(params), spp, msaa, threads,
                              std::move(aov), exposure, tonemap, frame, stats, defaultLight, maxMemory});
      },
      "scene"_a, "width"_a = 640, "height"_a = 360, "shadow"_a = "pcss", "params"_a = py::none(),
      "spp"_a = 16, "msaa"_a = 1, "threads"_a = 0, "aov"_a = std::vector<std::string>{}, "exposure"_a = 0.0,
      "tonemap"_a = "none", "frame"_a = 0, "stats"_a = false, "default_light"_a = true, "max_memory"_a = 0,
      "Renders `scene` (the GIL released meanwhile) and returns a dict of arrays, rows top to bottom:\n"
      "  color  H x W x 4 uint8 (sRGB), linear  H x W x 4 float32 (radiance, alpha = coverage),\n"
      "  and each buffer named in `aov` (aov_names(); ['all'] for every one): visibility (and visibility_1, "
      "...\n"
      "  for more area lights), depth (view distance), position, normal, geometric_normal, albedo,\n"
      "  barycentrics as float32 H x W (x 3), NaN where nothing was hit; instance and triangle as int32\n"
      "  H x W, -1 there; with stats=True also 'stats', the frame plan as text.\n"
      "shadow: a technique of techniques(), 'reference' (ray traced) or 'none'; params: {name: value}.\n"
      "spp: samples per pixel of the stochastic pass (motion blur, depth of field). threads: 0 = all.\n"
      "msaa: 1, 2, 4 or 8 samples per pixel for the G-buffer (antialiased edges; the AOVs are those of\n"
      "  each pixel's largest surface).\n"
      "default_light: a scene without lights gets the key light and sky `penumbra render` gives it.\n"
      "max_memory: bytes the frame may take (0: what is available); more is refused before any work.");
  m.def("write_image", &pp::writeImageArray, "path"_a, "image"_a,
        "Writes uint8 H x W x 3/4 as PNG, float32 H x W (x 3/4) as OpenEXR (.exr); no partial file on "
        "failure.");
  m.def("reference_coverage", &pp::referenceCoverage, "triangle"_a, "width"_a, "height"_a,
        "The scalar reference rasterizer on one triangle (3 x 4 clip-space vertices, w > 0): per pixel how\n"
        "often its centre is covered (uint32 H x W), to check rasterize() against.");
  m.def("rasterize", &pp::rasterize, "vertices_clip"_a, "triangles"_a, "width"_a, "height"_a,
        "cull"_a = "none", "threads"_a = 0,
        "The bare pipeline: clip-space vertices (N x 4, [-1, 1] x [-1, 1] x [0, 1] visible, y up) and\n"
        "triangles (M x 3) into a width x height target, depth test less, exact and watertight. Returns\n"
        "triangle (int32 H x W, -1 where none), depth (z / w, float32, NaN where none), barycentrics (H x W "
        "x 3,\n"
        "perspective-correct, NaN where none), front_facing (bool) and stats (triangles culled, clipped).");
}
