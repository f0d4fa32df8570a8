#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "apps/cli.h"
#include "apps/commands.h"
#include "engine/aov.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/memory.h"
#include "engine/renderer.h"
#include "engine/result_cache.h"
#include "engine/scene_file.h"
#include "raster/conventions.h"
#include "shadows/technique.h"
#include "stochastic/rasterizer.h"

namespace penumbra::apps {

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

namespace {

// "T" or "T,L": whole numbers, nothing else (the engine checks their ranges).
void parseStrata(const std::string& text, std::optional<int>& timeStrata, std::optional<int>& lensStrata) {
  auto whole = [&](const std::string& part, std::optional<int>& out) {
    int v = 0;
    const auto r = std::from_chars(part.data(), part.data() + part.size(), v);
    if (part.empty() || r.ec != std::errc() || r.ptr != part.data() + part.size())
      fail("option --strata", "must be T or T,L (whole numbers), got '" + text + "'");
    out = v;
  };
  const size_t comma = text.find(',');
  whole(text.substr(0, comma), timeStrata);
  if (comma != std::string::npos) whole(text.substr(comma + 1), lensStrata);
}

void checkOutputs(const RenderArgs& a) {
  auto checkExt = [](const std::string& option, const std::string& path, const std::vector<std::string>& exts) {
    const auto dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const std::string& e : exts)
      if (ext == e) return;
    fail(path, "unsupported output type for " + option + " (expected " + exts[0] + ")");
  };
  // Output folders must exist before any work is done.
  auto checkFolder = [](const std::string& path) {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) fail(path, "output folder does not exist");
  };
  if (a.output) {
    if (a.output->empty()) fail("option --output", "is empty (give a .png path)");
    checkExt("--output", *a.output, {".png"});
    checkFolder(*a.output);
  }
  if (!a.exr.empty()) {
    checkExt("--exr", a.exr, {".exr"});
    checkFolder(a.exr);
  }
  if (a.aov.empty() != a.aovOut.empty()) fail(a.aov.empty() ? "option --aov-out" : "option --aov",
                                              "give --aov LIST and --aov-out PREFIX together");
  if (!a.aov.empty()) {
    if (a.points) fail("option --aov", "the buffers are those of a triangle render, not of --points");
    if (engine::Result<std::vector<engine::Aov>> list = engine::parseAovList(a.aov); !list) fail(list.error());
    checkFolder(a.aovOut + ".exr");
  }
}

// The options the engine takes, from the arguments; the camera overrides are applied once the
// scene is known (applyCamera).
engine::RenderOptions renderOptions(const RenderArgs& a) {
  engine::RenderOptions options;
  options.width = a.width;
  options.height = a.height;
  options.shadow = a.shadow;
  for (const std::string& p : a.params) {
    if (p.find(',') != std::string::npos) fail("option --param", "give one name=value per --param, not '" + p + "'");
    options.shadowParams.push_back(p);
  }
  if (!a.cache.empty()) options.cache = std::make_shared<engine::FileResultCache>(a.cache);
  options.spp = a.spp;
  options.msaa = a.msaa;
  options.linearImage = !a.exr.empty();  // the radiance is written only to the EXR
  if (!stochastic::parseBoundMethod(a.bounds, options.bounds)) fail("option --bounds", "must be box, interval or dual");
  if (!a.strata.empty()) parseStrata(a.strata, options.timeStrata, options.lensStrata);
  options.frame = a.frame;
  options.staticPath = !a.noStaticPath;
  options.dualBlock = a.dualBlock;
  options.exposure = a.exposure;
  if (!engine::parseToneMap(a.toneMap, options.toneMap)) fail("option --tonemap", "must be none or aces, not '" + a.toneMap + "'");
  return options;
}

void applyCamera(const RenderArgs& a, const engine::Scene& scene, std::optional<glm::vec3> eye,
                 std::optional<glm::vec3> target, engine::RenderOptions& options) {
  if (!eye && !target && !a.fov && !a.aperture && !a.focus) return;
  engine::Camera cam = engine::chooseCamera(scene, options);
  if (eye) cam.eye = *eye;
  if (target) cam.target = *target;
  if (a.fov) cam.fovYDegrees = static_cast<float>(*a.fov);
  if (a.aperture) cam.apertureRadius = static_cast<float>(*a.aperture);
  if (a.focus) cam.focusDistance = static_cast<float>(*a.focus);
  options.camera = cam;
}

}  // namespace

int runRender(const RenderArgs& a) {
  if (a.listBuiltins) {
    for (const engine::BuiltinInfo& b : engine::builtinScenes()) std::printf("%-10s %s\n", b.name.c_str(), b.description.c_str());
    return 0;
  }
  if (a.listShadows) {
    listShadowTechniques();
    return 0;
  }
  // Validate every option before any work or output: the engine's checks (render_options.h).
  if (!a.scene.empty() && !a.builtin.empty()) fail("render", "give a scene file or --builtin, not both");
  require(engine::kThreadsOption, a.threads);
  if (a.fov) require(engine::kFovOption, *a.fov);
  if (a.aperture) require(engine::kApertureOption, *a.aperture);
  if (a.focus) require(engine::kFocusOption, *a.focus);
  std::optional<glm::vec3> eye, target;
  if (!a.eye.empty()) eye = parseVec3("--eye", a.eye);
  if (!a.target.empty()) target = parseVec3("--target", a.target);
  engine::RenderOptions options = renderOptions(a);
  resolveOrFail(options);
  if (!a.cache.empty()) require(engine::checkCacheFolder(a.cache, "option --cache"));
  checkOutputs(a);
  checkPointOptions(a);

  // The memory limit: given, or what the machine has available now.
  uint64_t memoryLimit = 0;
  std::string limitSource = "the memory available";
  if (!a.maxMemory.empty()) {
    engine::Result<uint64_t> m = engine::parseBytes(a.maxMemory, "--max-memory");
    if (!m) fail(m.error());
    memoryLimit = *m;
    limitSource = "--max-memory";
  } else {
    memoryLimit = engine::availableMemoryBytes();
  }

  const ThreadLimit threads(a.threads);
  Progress progress("render", 2.0);
  engine::Result<engine::Scene> scene =
      a.scene.empty() ? engine::makeBuiltinScene(a.builtin.empty() ? engine::kDefaultScene : a.builtin)
                      : engine::loadScene(a.scene, {.allowOutsidePaths = a.allowOutsidePaths, .maxBytes = memoryLimit});
  if (!scene) fail(scene.error());
  if (!a.noDefaultLight && !a.points) engine::addDefaultLighting(*scene);
  // Default output: <scene file stem or built-in name>.png in the current folder, in safe characters.
  std::string path = a.output.value_or("");
  if (!a.output) {
    std::string stem = a.scene.empty() ? (a.builtin.empty() ? std::string(engine::kDefaultScene) : a.builtin)
                                       : std::filesystem::path(a.scene).stem().string();
    for (char& ch : stem)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
    path = (stem.empty() ? std::string("penumbra") : stem) + ".png";
  }
  {
    std::vector<std::string> inputs = scene->sourceFiles;
    if (!a.pointsFile.empty()) inputs.push_back(a.pointsFile);
    if (!a.cache.empty()) inputs.push_back(a.cache);
    std::vector<std::string> outputs = {path, a.exr};
    if (!a.aov.empty())
      for (const std::string& p : engine::aovPaths(a.aovOut, *engine::parseAovList(a.aov), scene->areaLights.size()))
        outputs.push_back(p);
    refuseOverwritingInputs(outputs, inputs);
  }
  if (a.points) return renderPoints(a, *scene, eye, target, path, memoryLimit, limitSource);

  applyCamera(a, *scene, eye, target, options);
  const engine::ResolvedOptions resolved = resolveOrFail(options);
  engine::MemoryEstimate memory = engine::estimateFrameMemory(*scene, resolved);
  if (!a.aov.empty()) {  // the AOV files are written one at a time from a packed float buffer (3 channels at most)
    const uint64_t aovBytes = static_cast<uint64_t>(a.width) * static_cast<uint64_t>(a.height) * 3 * sizeof(float);
    memory.bytes += aovBytes;
    memory.parts.emplace_back("AOV buffer", aovBytes);
    std::stable_sort(memory.parts.begin(), memory.parts.end(),
                     [](const auto& x, const auto& y) { return x.second > y.second; });  // largest first
  }
  require(engine::checkMemory(memory, memoryLimit, "render", limitSource));
  engine::Renderer renderer(a.threads);
  progress.step(1, 2, "rendering " + std::to_string(scene->triangleCount()) + " triangles");
  const engine::Frame frame = renderer.render(*scene, resolved);
  progress.step(2, 2, "writing " + path);
  // Every file or none: the AOVs, the EXR, then the PNG; a failure removes what was written.
  std::vector<engine::Aov> aovs;
  if (!a.aov.empty()) aovs = *engine::parseAovList(a.aov);
  const std::vector<std::string> aovFiles = engine::aovPaths(a.aovOut, aovs, frame.visibility.size());
  const auto removeWritten = [&](bool exr) {
    std::error_code ec;
    for (const std::string& f : aovFiles) std::filesystem::remove(f, ec);
    if (exr && !a.exr.empty()) std::filesystem::remove(a.exr, ec);
  };
  if (!aovs.empty())
    if (engine::Status st = engine::writeAovs(frame, aovs, a.aovOut); !st) fail(st.error());
  if (!a.exr.empty()) {
    if (engine::Status st = engine::writeImage(a.exr, frame.linear); !st) {
      removeWritten(false);
      fail(st.error());
    }
  }
  if (engine::Status st = engine::writeImage(path, frame.color); !st) {
    removeWritten(true);
    fail(st.error());
  }
  progress.done();
  if (a.stats) {
    std::printf("scene '%s': %zu meshes, %zu instances, %zu triangles, %d threads\n", scene->name.c_str(),
                scene->meshes.size(), scene->instances.size(), scene->triangleCount(), renderer.rasterizer().threads());
    std::printf("memory: about %s estimated, limit %s (%s)\n", memory.text().c_str(),
                memoryLimit ? engine::formatBytes(memoryLimit).c_str() : "none", limitSource.c_str());
    std::printf("%s", frame.stats.report().c_str());
  }
  std::printf("wrote %s (%dx%d)%s%s", path.c_str(), a.width, a.height, a.exr.empty() ? "" : " and ", a.exr.c_str());
  if (!aovFiles.empty()) std::printf(" and %zu buffers (%s ...)", aovFiles.size(), aovFiles.front().c_str());
  std::printf("\n");
  return 0;
}

}  // namespace penumbra::apps
