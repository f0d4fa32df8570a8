#include <tbb/global_control.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "apps/cli.h"
#include "apps/commands.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/renderer.h"
#include "engine/scene_file.h"
#include "raster/conventions.h"
#include "shadows/technique.h"
#include "stochastic/rasterizer.h"

namespace penumbra::apps {

void allowThreads(int threads) {
  static std::unique_ptr<tbb::global_control> control;
  if (threads > 0)
    control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<size_t>(threads));
}

namespace {

void checkSize(const char* option, int v) {
  if (v < 1 || v > raster::kMaxTargetSize)
    fail(std::string("option ") + option, "must be in [1, " + std::to_string(raster::kMaxTargetSize) + "], got " + std::to_string(v));
}

void checkThreads(int threads) {
  if (threads < 0 || threads > 1024) fail("option --threads", "must be in [0, 1024], got " + std::to_string(threads));
}

}  // namespace

std::string checkShadowOptions(const std::string& shadow, const std::vector<std::string>& params) {
  if (shadow == "none") {
    if (!params.empty()) fail("option --param", "the shadow technique 'none' has no parameters");
    return {};
  }
  const shadows::TechniqueInfo* info = shadows::findTechnique(shadow);
  if (!info) fail("option --shadow", "unknown technique '" + shadow + "' (valid: none, " + shadows::techniqueNames() + ")");
  shadows::ParamSet set(info->params);
  std::string joined;
  for (const std::string& p : params) {
    if (p.find(',') != std::string::npos) fail("option --param", "give one name=value per --param, not '" + p + "'");
    if (auto err = set.set(p)) fail("option --param", *err + " for technique '" + shadow + "'");
    joined += (joined.empty() ? "" : ",") + p;
  }
  return joined;
}

void listShadowTechniques() {
  for (const shadows::TechniqueInfo& t : shadows::registry()) {
    std::printf("%-10s %s\n", t.name.c_str(), t.summary.c_str());
    for (const shadows::ParamSpec& p : t.params) {
      std::string range;
      if (p.kind == shadows::ParamKind::Choice) {
        for (const std::string& c : p.choices) range += (range.empty() ? "" : "|") + c;
        range += ", default " + p.choices[static_cast<size_t>(p.defaultValue)];
      } else {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s in [%g, %g], default %g", p.kind == shadows::ParamKind::Int ? "int" : "float",
                      p.minValue, p.maxValue, p.defaultValue);
        range = buf;
      }
      std::printf("    %-16s %s (%s)\n", p.name.c_str(), p.help.c_str(), range.c_str());
    }
  }
  std::printf("%-10s no shadows (V = 1)\n", "none");
}

int runRender(const RenderArgs& a) {
  if (a.listBuiltins) {
    for (const engine::BuiltinInfo& b : engine::builtinScenes()) std::printf("%-10s %s\n", b.name.c_str(), b.description.c_str());
    return 0;
  }
  if (a.listShadows) {
    listShadowTechniques();
    return 0;
  }
  // Validate every option before any work or output.
  checkSize("--width", a.width);
  checkSize("--height", a.height);
  checkThreads(a.threads);
  if (!a.scene.empty() && !a.builtin.empty()) fail("render", "give a scene file or --builtin, not both");
  if (a.fov != 0.0 && !(a.fov > 0.0 && a.fov < 180.0)) fail("option --fov", "must be in (0, 180) degrees");
  std::optional<glm::vec3> eye, target;
  if (!a.eye.empty()) eye = parseVec3("--eye", a.eye);
  if (!a.target.empty()) target = parseVec3("--target", a.target);
  const std::string shadowParams = checkShadowOptions(a.shadow, a.params);
  const std::string output = a.output;
  auto checkExt = [](const std::string& option, const std::string& path, const std::vector<std::string>& exts) {
    const auto dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const std::string& e : exts)
      if (ext == e) return;
    fail(path, "unsupported output type for " + option + " (expected " + exts[0] + ")");
  };
  if (!output.empty()) checkExt("--output", output, {".png"});
  if (!a.exr.empty()) checkExt("--exr", a.exr, {".exr"});
  // Output folders must exist before any work is done.
  auto checkFolder = [](const std::string& path) {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) fail(path, "output folder does not exist");
  };
  if (!output.empty()) checkFolder(output);
  if (!a.exr.empty()) checkFolder(a.exr);
  checkPointOptions(a);
  if (a.spp < 1 || a.spp > stochastic::kMaxSpp) fail("option --spp", "must be in [1, 64]");
  stochastic::BoundMethod bounds;
  if (!stochastic::parseBoundMethod(a.bounds, bounds)) fail("option --bounds", "must be box, interval or dual");
  int timeStrata = 0, lensStrata = 0;
  if (!a.strata.empty()) {
    char extra = 0;
    const int n = std::sscanf(a.strata.c_str(), "%d,%d%c", &timeStrata, &lensStrata, &extra);
    if (n < 1 || n > 2 || timeStrata < 1 || timeStrata > 64 || (n == 2 && (lensStrata < 1 || lensStrata > 8)))
      fail("option --strata", "must be T or T,L with T in [1, 64] and L in [1, 8]");
  }
  if (a.frame < 0 || a.frame > 0xFFFFFFFFll) fail("option --frame", "must be in [0, 2^32)");
  if (a.dualBlock < 1 || a.dualBlock > 64 || (a.dualBlock & (a.dualBlock - 1)) != 0)
    fail("option --dual-block", "must be a power of 2 in [1, 64]");
  if (a.aperture != -1.0 && !(a.aperture >= 0.0 && a.aperture < 1e6)) fail("option --aperture", "must be in [0, 1e6)");
  if (a.focus != -1.0 && !(a.focus > 0.0 && a.focus < 1e9)) fail("option --focus", "must be in (0, 1e9)");

  allowThreads(a.threads);
  Progress progress("render", 2.0);
  engine::Result<engine::Scene> scene = a.scene.empty()
                                            ? engine::makeBuiltinScene(a.builtin.empty() ? engine::kDefaultScene : a.builtin)
                                            : engine::loadScene(a.scene);
  if (!scene) fail(scene.error());
  // Default output: <scene file stem or built-in name>.png in the current folder, in safe characters.
  std::string path = output;
  if (path.empty()) {
    std::string stem = a.scene.empty() ? (a.builtin.empty() ? std::string(engine::kDefaultScene) : a.builtin)
                                       : std::filesystem::path(a.scene).stem().string();
    for (char& ch : stem)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
    path = (stem.empty() ? std::string("penumbra") : stem) + ".png";
  }
  if (a.points) return renderPoints(a, *scene, eye, target, path);

  engine::RenderOptions options;
  options.width = a.width;
  options.height = a.height;
  options.shadow = a.shadow;
  options.shadowParams = shadowParams;
  options.cacheDir = a.cache;
  options.spp = a.spp;
  options.bounds = bounds;
  options.timeStrata = timeStrata;
  options.lensStrata = lensStrata;
  options.frame = static_cast<uint32_t>(a.frame);
  options.staticPath = !a.noStaticPath;
  options.dualBlock = a.dualBlock;
  if (eye || target || a.fov != 0.0 || a.aperture >= 0.0 || a.focus > 0.0) {
    engine::RenderOptions base = options;
    engine::Camera cam = engine::chooseCamera(*scene, base);
    if (eye) cam.eye = *eye;
    if (target) cam.target = *target;
    if (a.fov != 0.0) cam.fovYDegrees = static_cast<float>(a.fov);
    if (a.aperture >= 0.0) cam.apertureRadius = static_cast<float>(a.aperture);
    if (a.focus > 0.0) cam.focusDistance = static_cast<float>(a.focus);
    if (cam.eye == cam.target) fail("option --eye", "camera eye and target coincide");
    options.camera = cam;
  }
  engine::Renderer renderer(a.threads);
  progress.step(1, 2, "rendering " + std::to_string(scene->triangleCount()) + " triangles");
  const engine::Frame frame = renderer.render(*scene, options);
  progress.step(2, 2, "writing " + (output.empty() ? std::string("the image") : output));
  // Both files or neither: the EXR first, then the PNG; if the PNG fails the EXR is removed.
  if (!a.exr.empty()) {
    if (engine::Status st = engine::writeImage(a.exr, frame.linear); !st) fail(st.error());
  }
  if (engine::Status st = engine::writeImage(path, frame.color); !st) {
    if (!a.exr.empty()) std::filesystem::remove(a.exr);
    fail(st.error());
  }
  progress.done();
  if (a.stats) {
    std::printf("scene '%s': %zu meshes, %zu instances, %zu triangles, %d threads\n", scene->name.c_str(),
                scene->meshes.size(), scene->instances.size(), scene->triangleCount(), renderer.rasterizer().threads());
    std::printf("%s", frame.stats.report().c_str());
  }
  std::printf("wrote %s (%dx%d)%s%s\n", path.c_str(), a.width, a.height, a.exr.empty() ? "" : " and ", a.exr.c_str());
  return 0;
}

}  // namespace penumbra::apps
