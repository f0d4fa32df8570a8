// `penumbra bench shadows`: every scene x technique x parameter setting, timed per stage (medians
// over runs) and compared with the ray-traced ground truth; a report (JSON, CSV, HTML with images,
// error heat maps and a Pareto plot per scene) in the output folder.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "apps/cli.h"
#include "raster/timing.h"
#include "apps/commands.h"
#include "engine/bench_report.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/metrics.h"
#include "engine/renderer.h"
#include "engine/result_cache.h"
#include "engine/scene_file.h"

namespace penumbra::apps {

namespace {

std::string safeName(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return s;
}

struct Timed {
  engine::Frame frame;
  double msMaps = 0, msFilter = 0, msEvaluate = 0, msPrepare = 0, msTotal = 0, msPoints = 0, msSplat = 0;
  double msMapsMin = 0, msMapsMax = 0, msEvaluateMin = 0, msEvaluateMax = 0, msTotalMin = 0, msTotalMax = 0;
};

// Renders `runs` times; stage times are medians (and the fastest and slowest run), the frame is the
// last run's (they are identical: rendering is deterministic).
Timed timedRender(engine::Renderer& renderer, const engine::Scene& scene, const engine::RenderOptions& options,
                  int runs) {
  const engine::ResolvedOptions resolved = resolveOrFail(options);
  std::vector<double> maps, filter, eval, prep, total, points, splat;
  Timed t;
  for (int r = 0; r < runs; ++r) {
    t.frame = renderer.render(scene, resolved);
    const engine::LightShadowStats& s = t.frame.stats.shadows.at(0);
    maps.push_back(s.times.msMaps);
    filter.push_back(s.times.msFilter);
    eval.push_back(s.times.msEvaluate);
    prep.push_back(s.times.prepare());
    total.push_back(s.times.total());
    points.push_back(s.times.msPoints);
    splat.push_back(s.times.msSplat);
  }
  t.msMaps = raster::median(maps);
  t.msFilter = raster::median(filter);
  t.msEvaluate = raster::median(eval);
  t.msPrepare = raster::median(prep);
  t.msTotal = raster::median(total);
  t.msPoints = raster::median(points);
  t.msSplat = raster::median(splat);
  const auto [mapsLo, mapsHi] = std::minmax_element(maps.begin(), maps.end());
  const auto [evalLo, evalHi] = std::minmax_element(eval.begin(), eval.end());
  const auto [totalLo, totalHi] = std::minmax_element(total.begin(), total.end());
  t.msMapsMin = *mapsLo, t.msMapsMax = *mapsHi;
  t.msEvaluateMin = *evalLo, t.msEvaluateMax = *evalHi;
  t.msTotalMin = *totalLo, t.msTotalMax = *totalHi;
  return t;
}

// A row's times and errors: V against the reference over every compared receiver and per class
// (NaN where the scene has none), the image's RMSE.
engine::ShadowBenchRow measuredRow(const Timed& t, const engine::Frame& ref, const raster::Image<uint8_t>& mask) {
  const raster::ImageFloat& vis = t.frame.visibility.at(0);
  const raster::ImageFloat& refVis = ref.visibility.at(0);
  const auto split = [&](uint8_t select, double& rmse, double& bias) {
    const engine::VisibilityError e = engine::compareVisibility(vis, refVis, mask, select);
    rmse = e.pixels > 0 ? e.rmse : std::nan("");
    bias = e.pixels > 0 ? e.bias : std::nan("");
  };
  engine::ShadowBenchRow row;
  row.msMaps = t.msMaps;
  row.msFilter = t.msFilter;
  row.msPrepare = t.msPrepare;
  row.msEvaluate = t.msEvaluate;
  row.msTotal = t.msTotal;
  row.msMapsMin = t.msMapsMin, row.msMapsMax = t.msMapsMax;
  row.msEvaluateMin = t.msEvaluateMin, row.msEvaluateMax = t.msEvaluateMax;
  row.msTotalMin = t.msTotalMin, row.msTotalMax = t.msTotalMax;
  row.msPoints = t.msPoints, row.msSplat = t.msSplat;
  const engine::VisibilityError e = engine::compareVisibility(vis, refVis, mask);
  row.rmseV = e.rmse;
  row.biasV = e.bias;
  row.maxErrV = e.maxErr;
  row.fracErrGt005 = e.fracOver005;
  split(engine::kGroundReceiver, row.rmseGround, row.biasGround);
  split(engine::kObjectReceiver, row.rmseObject, row.biasObject);
  split(engine::kContactReceiver, row.rmseContact, row.biasContact);
  row.rmseImage = engine::imageRmse(t.frame.color, ref.color);
  return row;
}

// "  points X splat Y" where the technique makes its maps in those two steps.
std::string splitLine(const engine::ShadowBenchRow& row) {
  if (row.msPoints == 0 && row.msSplat == 0) return "";
  char buf[80];
  std::snprintf(buf, sizeof buf, "  points %.2f splat %.2f", row.msPoints, row.msSplat);
  return buf;
}

void printRow(const engine::ShadowBenchRow& row, bool json) {
  if (json) {
    std::printf("%s\n", engine::toJson(row).c_str());
  } else {
    std::printf("%-9s %-6s %-40s maps %8.2f filter %7.2f eval %8.2f total %8.2f ms  rmse_v %.4f bias %+.4f max %.3f "
                ">0.05 %5.1f%%  ground %.4f %+.4f  object %.4f %+.4f  contact %.4f %+.4f  rmse_img %.4f  "
                "runs: maps %.2f-%.2f eval %.2f-%.2f total %.2f-%.2f%s\n",
                row.scene.c_str(), row.technique.c_str(), row.params.empty() ? "(defaults)" : row.params.c_str(),
                row.msMaps, row.msFilter, row.msEvaluate, row.msTotal, row.rmseV, row.biasV, row.maxErrV,
                100.0 * row.fracErrGt005, row.rmseGround, row.biasGround, row.rmseObject, row.biasObject, row.rmseContact,
                row.biasContact, row.rmseImage, row.msMapsMin, row.msMapsMax, row.msEvaluateMin, row.msEvaluateMax,
                row.msTotalMin, row.msTotalMax, splitLine(row).c_str());
  }
  std::fflush(stdout);
}

// What skipping saves: a setting again with caster culling off (same views): mvr with 24 maps
// when it runs (its cost grows with the triangles drawn), else the first setting. One line.
std::string cullingLine(engine::Renderer& renderer, const std::string& name, const engine::Scene& scene,
                        const engine::RenderOptions& base,
                        const std::vector<std::pair<const shadows::TechniqueInfo*, std::string>>& runs,
                        const raster::Image<uint8_t>& mask, int repeats) {
  size_t pick = 0;
  for (size_t i = 0; i < runs.size(); ++i)
    if (runs[i].first->name == "mvr" && runs[i].second == "views=24") pick = i;
  engine::RenderOptions on = base, off = base;
  on.shadow = off.shadow = runs[pick].first->name;
  on.shadowParams = off.shadowParams = {runs[pick].second};
  off.shadowCulling = false;
  const Timed tOn = timedRender(renderer, scene, on, repeats), tOff = timedRender(renderer, scene, off, repeats);
  const engine::LightShadowStats& s = tOn.frame.stats.shadows.at(0);
  const engine::VisibilityError d = engine::compareVisibility(tOn.frame.visibility.at(0), tOff.frame.visibility.at(0), mask);
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%s: %s %s: culling kept %zu of %zu triangles (%zu instances culled whole): %.2f ms, without culling "
                "%.2f ms; V max difference %.3g, %.3f%% of receivers off by more than 0.05",
                name.c_str(), runs[pick].first->name.c_str(), runs[pick].second.c_str(),
                s.trianglesFlattened - s.trianglesCulled, scene.triangleCount(), s.instancesCulled, tOn.msTotal,
                tOff.msTotal, d.maxErr, 100.0 * d.fracOver005);
  return buf;
}

}  // namespace

int runBenchShadows(const BenchShadowsArgs& a) {
  // Validate everything before any work.
  requireBenchBasics(a.width, a.height, a.runs, a.threads);
  require(kGtSamplesOption, a.gtSamples);
  if (!(a.lightScale > 0.0 && a.lightScale <= 64.0))
    fail("option --light-scale", "must be in (0, 64], got " + std::to_string(a.lightScale));
  std::vector<std::string> sceneNames = a.scenes;
  if (sceneNames.empty()) sceneNames = {"contact", "fusion", "thin", "complex", "biglight", "creature", "knot", "menagerie"};
  std::vector<std::pair<std::string, engine::Scene>> scenes;
  for (const std::string& name : sceneNames) {
    scenes.push_back(loadSceneArgument(name, {.allowOutsidePaths = a.allowOutsidePaths}));
    if (scenes.back().second.areaLights.empty()) fail(name, "the scene has no area light to benchmark");
    for (shadows::RectLight& l : scenes.back().second.areaLights) {
      l.width *= static_cast<float>(a.lightScale);
      l.height *= static_cast<float>(a.lightScale);
    }
  }
  // (technique, parameter list) pairs: the registry's bench settings, or the ones asked for.
  std::vector<std::pair<const shadows::TechniqueInfo*, std::string>> runs;
  for (const shadows::TechniqueInfo& t : shadows::registry()) {
    if (t.isReference) continue;
    if (!a.techniques.empty() && std::find(a.techniques.begin(), a.techniques.end(), t.name) == a.techniques.end())
      continue;
    for (const std::string& setting : t.benchSettings) runs.emplace_back(&t, setting);
  }
  for (const std::string& name : a.techniques) {
    const shadows::TechniqueInfo* t = shadows::findTechnique(name);
    if (!t) fail("option --technique", "unknown technique '" + name + "' (valid: " + shadows::techniqueNames() + ")");
    if (t->isReference) fail("option --technique", "'" + name + "' is the ground truth every technique is measured against");
  }
  for (const std::string& setting : a.settings) {  // "name:k=v,k=v"
    const size_t colon = setting.find(':');
    const shadows::TechniqueInfo* t = shadows::findTechnique(setting.substr(0, colon));
    if (!t || t->isReference)
      fail("option --setting", "expected technique:name=value,..., with a technique of: " + shadows::techniqueNames());
    const std::string params = colon == std::string::npos ? "" : setting.substr(colon + 1);
    shadows::ParamSet check(t->params);
    if (auto err = check.setAll(params)) fail("option --setting", *err);
    runs.emplace_back(t, params);
  }
  if (!a.settings.empty() && a.techniques.empty()) {  // only the settings asked for
    runs.erase(runs.begin(), runs.end() - static_cast<std::ptrdiff_t>(a.settings.size()));
  }
  if (runs.empty()) fail("bench shadows", "no technique to run");
  // One run per distinct (technique, effective parameters): image names must not collide.
  {
    std::vector<std::pair<const shadows::TechniqueInfo*, std::string>> unique;
    std::vector<std::string> seen;
    for (const auto& [info, params] : runs) {
      shadows::ParamSet ps(info->params);
      ps.setAll(params);
      const std::string key = info->name + ":" + ps.changed();
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      unique.emplace_back(info, params);
    }
    runs = std::move(unique);
  }
  for (size_t i = 0; i < scenes.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (scenes[i].first == scenes[j].first)
        fail("option --scene", "two scenes are named '" + scenes[i].first + "' (their images would collide)");
  const std::filesystem::path out(a.out);
  std::error_code ec;
  std::filesystem::create_directories(out / "images", ec);
  if (ec) fail(a.out, "cannot create the report folder: " + ec.message());
  const std::string cache = a.cache.empty() ? (out / "gt-cache").string() : a.cache;

  const ThreadLimit threadLimit(a.threads);
  engine::Renderer renderer(a.threads);
  Progress progress("bench shadows");
  const int steps = static_cast<int>(scenes.size() * (runs.size() + 2));
  int step = 0;
  std::vector<engine::ShadowBenchScene> reportScenes;
  std::vector<engine::ShadowBenchRow> rows;
  std::vector<std::string> cullingLines;
  for (const auto& [name, scene] : scenes) {
    engine::RenderOptions base;
    base.width = a.width;
    base.height = a.height;
    base.cache = std::make_shared<engine::FileResultCache>(cache);
    // Ground truth.
    progress.step(++step, steps, name + ": ground truth, " + std::to_string(a.gtSamples) + " rays per pixel");
    engine::RenderOptions refOpt = base;
    refOpt.shadow = "reference";
    refOpt.shadowParams = {"samples=" + std::to_string(a.gtSamples)};
    const engine::Frame ref = renderer.render(scene, resolveOrFail(refOpt));
    const raster::Image<uint8_t> mask = engine::receiverClasses(scene, ref, scene.areaLights[0]);
    engine::ShadowBenchScene rs;
    rs.name = name;
    for (const engine::BuiltinInfo& b : engine::builtinScenes())
      if (b.name == name) rs.description = b.description;
    rs.width = a.width;
    rs.height = a.height;
    rs.referenceImage = "images/" + safeName(name) + "-reference.png";
    const engine::LightShadowStats& refStats = ref.stats.shadows.at(0);
    for (const std::string& n : refStats.notes) rs.referenceNote += (rs.referenceNote.empty() ? "" : "; ") + n;
    if (engine::Status st = engine::writeImage((out / rs.referenceImage).string(), ref.color); !st) fail(st.error());
    if (engine::Status st = engine::writeImage((out / ("images/" + safeName(name) + "-reference-v.png")).string(),
                                               engine::visibilityImage(ref.visibility.at(0)));
        !st)
      fail(st.error());
    reportScenes.push_back(rs);

    for (const auto& [info, params] : runs) {
      progress.step(++step, steps, name + ": " + info->name + (params.empty() ? "" : " " + params));
      engine::RenderOptions opt = base;
      opt.shadow = info->name;
      opt.shadowParams = {params};
      const Timed t = timedRender(renderer, scene, opt, a.runs);
      engine::ShadowBenchRow row = measuredRow(t, ref, mask);
      row.scene = name;
      row.technique = info->name;
      shadows::ParamSet ps(info->params);
      ps.setAll(params);
      row.params = ps.changed();
      for (const shadows::ParamSpec& spec : info->params)
        if (spec.name == "views") row.views = ps.integer("views");
      const std::string stem = "images/" + safeName(name + "-" + info->name + (params.empty() ? "" : "-" + params));
      row.image = stem + ".png";
      row.heatMap = stem + "-err.png";
      if (engine::Status st = engine::writeImage((out / row.image).string(), t.frame.color); !st) fail(st.error());
      if (engine::Status st = engine::writeImage((out / row.heatMap).string(),
                                                 engine::errorHeatMap(t.frame.visibility.at(0), ref.visibility.at(0), mask));
          !st)
        fail(st.error());
      rows.push_back(row);
      printRow(row, a.json);
    }

    progress.step(++step, steps, name + ": caster culling off");
    cullingLines.push_back(cullingLine(renderer, name, scene, base, runs, mask, a.runs));
    if (!a.json) std::printf("%s\n", cullingLines.back().c_str());
  }
  progress.done();
  std::string machine = std::to_string(renderer.rasterizer().threads()) + " threads, " + std::to_string(a.width) + "x" +
                        std::to_string(a.height) + ", medians of " + std::to_string(a.runs) + " runs; ground truth " +
                        std::to_string(a.gtSamples) + " rays per receiver.";
  for (const std::string& l : cullingLines) machine += " " + l + ".";
  if (engine::Status st = engine::writeShadowReport(out.string(), reportScenes, rows, "penumbra bench shadows", machine); !st)
    fail(st.error());
  if (!a.json) std::printf("wrote %s/index.html\n", out.string().c_str());
  return 0;
}

}  // namespace penumbra::apps
