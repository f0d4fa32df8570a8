// `penumbra bench stochastic`: per scene (motion, defocus, both) every bounding method at several
// sample counts: time of the stochastic pass (median of runs), exact tests, hits, sample test
// efficiency, and the error against the accumulation-buffer reference; plus, where the scene has
// static instances, the frame without the ordinary path to show what it saves. Writes JSON, CSV,
// an HTML page with the images, test heat maps and one run-time-against-error Pareto plot (SVG)
// per scene.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/cli.h"
#include "apps/commands.h"
#include "raster/timing.h"
#include "engine/atomic_file.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/metrics.h"
#include "engine/renderer.h"
#include "engine/report.h"
#include "engine/scene_file.h"
#include "engine/texture.h"

namespace penumbra::apps {

namespace {

using engine::report::Json;

struct Row {
  std::string scene, method;
  int spp = 0;
  bool staticPath = true;
  double ms = 0, msFrame = 0;
  uint64_t tests = 0, hits = 0, scanned = 0;
  double ste = 0, steP10 = 0, steMedian = 0, steP90 = 0, rmse = 0;
  std::string image, heat;
};

Json rowJson(const Row& r) {
  Json j;
  j["scene"] = r.scene;
  j["method"] = r.method;
  j["spp"] = r.spp;
  j["ms"] = r.ms;
  j["tests"] = r.tests;
  j["hits"] = r.hits;
  j["ste"] = r.ste;
  j["rmse"] = r.rmse;
  j["ms_frame"] = r.msFrame;
  j["scanned"] = r.scanned;
  j["ste_triangle_p10"] = r.steP10;
  j["ste_triangle_median"] = r.steMedian;
  j["ste_triangle_p90"] = r.steP90;
  j["static_path"] = r.staticPath;
  return j;
}

raster::ImageRgba8 srgb(const raster::ImageFloat4& linear) {
  raster::ImageRgba8 out(linear.width(), linear.height());
  for (int y = 0; y < linear.height(); ++y)
    for (int x = 0; x < linear.width(); ++x) {
      const raster::Float4& c = linear.at(x, y);
      out.at(x, y) = {engine::linearToSrgb(c.r), engine::linearToSrgb(c.g), engine::linearToSrgb(c.b), 255};
    }
  return out;
}

// Tests per pixel on a log scale, black (none) through blue and yellow to white (>= 4096).
raster::ImageRgba8 testsHeatMap(const std::vector<uint32_t>& tests, int w, int h) {
  raster::ImageRgba8 out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t n = tests[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)];
      const float t = n == 0 ? 0.0f : std::min(1.0f, std::log2(static_cast<float>(n) + 1.0f) / 12.0f);
      const float r = std::clamp(3.0f * t - 1.0f, 0.0f, 1.0f), g = std::clamp(3.0f * t - 1.5f, 0.0f, 1.0f) * 0.9f + std::clamp(2.0f * t - 1.0f, 0.0f, 0.1f),
                  b = t < 0.5f ? 2.0f * t : std::clamp(3.0f * t - 2.0f, 0.0f, 1.0f) + (1.0f - t) * 0.6f;
      out.at(x, y) = {static_cast<uint8_t>(255.0f * r), static_cast<uint8_t>(255.0f * std::min(g, 1.0f)),
                      static_cast<uint8_t>(255.0f * std::min(b, 1.0f)), 255};
    }
  return out;
}

// Run time against RMSE for one scene's rows, the Pareto front joined (engine/report.h).
std::string paretoSvg(const std::string& scene, const std::vector<Row>& rows) {
  engine::report::PlotSpec spec;
  spec.title = scene + ": stochastic pass time against RMSE vs the accumulation reference";
  spec.xLabel = "stochastic pass (ms)";
  spec.yLabel = "RMSE (linear radiance)";
  spec.seriesOrder = {"box", "interval", "dual"};
  spec.labelAll = true;
  spec.note = "labels: samples per pixel; faded: without the ordinary path for static objects";
  std::vector<engine::report::PlotPoint> points;
  for (const Row& r : rows)
    points.push_back({r.ms, r.rmse, r.method, std::to_string(r.spp) + (r.staticPath ? "" : " (no static path)"),
                      !r.staticPath});
  return engine::report::paretoSvg(spec, points);
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  if (engine::Status st = engine::writeFileAtomically(path, text); !st) fail(st.error());
}

std::string csvRow(const Row& r) {
  using engine::report::csvField;
  using engine::report::number;
  std::string s = csvField(r.scene) + "," + csvField(r.method) + "," + std::to_string(r.spp);
  for (double v : {r.ms, static_cast<double>(r.tests), static_cast<double>(r.hits), r.ste, r.rmse, r.msFrame,
                   static_cast<double>(r.scanned), r.steP10, r.steMedian, r.steP90}) {
    s += ',';
    s += number(v);
  }
  s += r.staticPath ? ",1" : ",0";
  return s;
}

// One scene's section of the page: reference, plot, the table with images.
std::string sceneHtml(const std::string& name, int refFrames, double refMs, const std::string& refImage,
                      const std::vector<Row>& rows) {
  using engine::report::escapeXml;
  using engine::report::thumb;
  using engine::report::urlAttr;
  char buf[256];
  std::string s = "<h2>" + escapeXml(name) + "</h2>\n";
  std::snprintf(buf, sizeof buf, "<p>Reference: %d pinhole frames accumulated (%.0f ms).</p>\n", refFrames, refMs);
  s += buf;
  s += "<p>" + thumb(refImage, "reference: " + name) + " <img class=\"plot\" src=\"" + urlAttr("pareto-" + name + ".svg") +
       "\" alt=\"" + escapeXml("time against error, " + name) + "\"></p>\n";
  s += "<table>\n<tr><th>method</th><th>spp</th><th>ms</th><th>frame ms</th><th>tests</th><th>hits</th><th>STE</th>"
       "<th>RMSE</th><th>image</th><th>tests per pixel</th></tr>\n";
  for (const Row& r : rows) {
    std::snprintf(buf, sizeof buf,
                  "<td class=\"num\">%d</td><td class=\"num\">%.1f</td><td class=\"num\">%.1f</td>"
                  "<td class=\"num\">%llu</td><td class=\"num\">%llu</td><td class=\"num\">%.3f</td>"
                  "<td class=\"num\">%.5f</td>",
                  r.spp, r.ms, r.msFrame, static_cast<unsigned long long>(r.tests),
                  static_cast<unsigned long long>(r.hits), r.ste, r.rmse);
    s += "<tr><td>" + escapeXml(r.method + (r.staticPath ? "" : " (no static path)")) + "</td>" + buf + "<td>" +
         thumb(r.image, r.method + " " + std::to_string(r.spp)) + "</td><td>" +
         thumb(r.heat, "tests per pixel, " + r.method + " " + std::to_string(r.spp)) + "</td></tr>\n";
  }
  return s + "</table>\n";
}

}  // namespace

int runBenchStochastic(const BenchStochasticArgs& a) {
  requireBenchBasics(a.width, a.height, a.runs, a.threads);
  require(kRefFramesOption, a.refFrames);
  std::vector<int> spps = a.spp.empty() ? std::vector<int>{4, 16, 64} : a.spp;
  for (int s : spps) require(engine::kSppOption, s);
  std::vector<stochastic::BoundMethod> methods;
  for (const std::string& m : a.methods.empty() ? std::vector<std::string>{"box", "interval", "dual"} : a.methods) {
    stochastic::BoundMethod b;
    if (!stochastic::parseBoundMethod(m, b)) fail("option --method", "'" + m + "' is not box, interval or dual");
    methods.push_back(b);
  }
  engine::RenderOptions base;
  base.width = a.width;
  base.height = a.height;
  base.shadow = a.shadow;
  resolveOrFail(base);
  std::vector<std::pair<std::string, engine::Scene>> scenes;
  for (const std::string& name : a.scenes.empty() ? std::vector<std::string>{"motion", "defocus", "motion-defocus"} : a.scenes)
    scenes.push_back(loadSceneArgument(name, {.allowOutsidePaths = a.allowOutsidePaths}));
  const std::filesystem::path out(a.out);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) fail(a.out, "cannot create the report folder: " + ec.message());

  const ThreadLimit threadLimit(a.threads);
  Progress progress("bench stochastic");
  int step = 0;
  engine::Renderer renderer(a.threads);
  std::vector<Row> rows;
  Json scenesJson = Json::array();
  std::string html;
  for (auto& [name, scene] : scenes) {
    progress.step(++step, static_cast<int>(scenes.size()), name + ": accumulation reference (" + std::to_string(a.refFrames) + " frames), then the runs");
    const auto t0 = std::chrono::steady_clock::now();
    engine::Result<raster::ImageFloat4> refFrame = engine::accumulationReference(renderer, scene, base, a.refFrames);
    if (!refFrame) fail(refFrame.error());
    const raster::ImageFloat4& ref = *refFrame;
    const double refMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::string refName = name + "-reference.png";
    if (engine::Status st = engine::writeImage((out / refName).string(), srgb(ref)); !st) fail(st.error());
    Json sj;
    sj["name"] = name;
    sj["reference_frames"] = a.refFrames;
    sj["reference_ms"] = refMs;
    scenesJson.push_back(sj);
    std::vector<Row> sceneRows;
    auto run = [&](stochastic::BoundMethod m, int spp, bool staticPath) {
      engine::RenderOptions o = base;
      o.spp = spp;
      o.bounds = m;
      o.staticPath = staticPath;
      o.staticShortcut = staticPath;
      std::vector<uint32_t> testsPerPixel;
      o.debug.testsPerPixel = &testsPerPixel;
      std::vector<double> ms, msFrame;
      engine::Frame f;
      const engine::ResolvedOptions resolved = resolveOrFail(o);
      for (int r = 0; r < a.runs; ++r) {
        f = renderer.render(scene, resolved);
        ms.push_back(f.stats.msStochastic);
        msFrame.push_back(f.stats.msTotal);
      }
      if (!f.stats.stochastic) fail(name, "the scene has no motion and no lens: nothing for the stochastic pass");
      Row row;
      row.scene = name;
      row.method = stochastic::boundMethodName(m);
      row.spp = spp;
      row.staticPath = staticPath;
      row.ms = raster::median(ms);
      row.msFrame = raster::median(msFrame);
      const stochastic::StochasticStats& s = f.stats.stoch;
      row.tests = s.tests, row.hits = s.hits, row.scanned = s.samplesScanned, row.ste = s.ste();
      row.steP10 = s.steTriangleP10, row.steMedian = s.steTriangleMedian, row.steP90 = s.steTriangleP90;
      row.rmse = engine::imageRmse(f.linear, ref);
      const std::string tag = name + "-" + row.method + "-" + std::to_string(spp) + (staticPath ? "" : "-nostatic");
      row.image = tag + ".png";
      row.heat = tag + "-tests.png";
      if (engine::Status st = engine::writeImage((out / row.image).string(), f.color); !st) fail(st.error());
      if (engine::Status st = engine::writeImage((out / row.heat).string(), testsHeatMap(testsPerPixel, a.width, a.height)); !st)
        fail(st.error());
      if (a.json) std::printf("%s\n", engine::report::jsonLine(rowJson(row)).c_str());
      else
        std::printf("%-15s %-9s %2d spp%s: %9.2f ms  tests %11llu  hits %10llu  STE %.3f  RMSE %.5f\n", name.c_str(),
                    row.method.c_str(), spp, staticPath ? "" : " (no static path)", row.ms,
                    static_cast<unsigned long long>(row.tests), static_cast<unsigned long long>(row.hits), row.ste, row.rmse);
      std::fflush(stdout);
      sceneRows.push_back(row);
      return f.stats.instancesOrdinary;
    };
    size_t ordinary = 0;
    for (int spp : spps)
      for (stochastic::BoundMethod m : methods) ordinary = std::max(ordinary, run(m, spp, true));
    // What the ordinary path saves: the same frame with every static triangle tested per sample.
    if (ordinary > 0) run(methods.back(), 16, false);
    writeText(out / ("pareto-" + name + ".svg"), paretoSvg(name, sceneRows));
    html += sceneHtml(name, a.refFrames, refMs, refName, sceneRows);
    rows.insert(rows.end(), sceneRows.begin(), sceneRows.end());
  }
  Json all;
  all["title"] = "penumbra bench stochastic";
  all["width"] = a.width;
  all["height"] = a.height;
  all["runs"] = a.runs;
  all["threads"] = renderer.rasterizer().threads();
  all["scenes"] = scenesJson;
  Json rj = Json::array();
  std::string csv = "scene,method,spp,ms,tests,hits,ste,rmse,ms_frame,scanned,ste_triangle_p10,ste_triangle_median,"
                    "ste_triangle_p90,static_path\n";
  for (const Row& r : rows) {
    rj.push_back(rowJson(r));
    csv += csvRow(r) + "\n";
  }
  all["rows"] = rj;
  writeText(out / "results.json", engine::report::jsonFile(all));
  writeText(out / "results.csv", csv);
  writeText(out / "index.html",
            engine::report::htmlPage("Stochastic rasterization: run time against error",
                                     "<p>Data: <a href=\"results.json\">results.json</a>, "
                                     "<a href=\"results.csv\">results.csv</a>.</p>\n" + html));
  progress.done();
  if (!a.json) std::printf("wrote %s/index.html\n", a.out.c_str());
  return 0;
}

}  // namespace penumbra::apps
