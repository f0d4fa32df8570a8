#include "engine/bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

#include "engine/atomic_file.h"
#include "engine/metrics.h"
#include "engine/report.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using report::Json;
using report::jsonNumber;

// ---- JSON and CSV -------------------------------------------------------------------------------

// The numeric columns of a row, in order (JSON keys and CSV header alike).
std::vector<std::pair<const char*, double>> numericColumns(const ShadowBenchRow& r) {
  return {{"ms_maps", r.msMaps},           {"ms_filter", r.msFilter},
          {"ms_prepare", r.msPrepare},     {"ms_evaluate", r.msEvaluate},
          {"ms_total", r.msTotal},         {"rmse_v", r.rmseV},
          {"bias_v", r.biasV},             {"max_err_v", r.maxErrV},
          {"frac_err_gt_005", r.fracErrGt005}, {"rmse_v_ground", r.rmseGround},
          {"bias_v_ground", r.biasGround}, {"rmse_v_object", r.rmseObject},
          {"bias_v_object", r.biasObject}, {"rmse_v_contact", r.rmseContact},
          {"bias_v_contact", r.biasContact}, {"rmse_image", r.rmseImage},
          {"ms_maps_min", r.msMapsMin},     {"ms_maps_max", r.msMapsMax},
          {"ms_evaluate_min", r.msEvaluateMin}, {"ms_evaluate_max", r.msEvaluateMax},
          {"ms_total_min", r.msTotalMin},   {"ms_total_max", r.msTotalMax},
          {"ms_points", r.msPoints},       {"ms_splat", r.msSplat}};
}

Json rowJson(const ShadowBenchRow& r) {
  Json j;
  j["scene"] = r.scene;
  j["technique"] = r.technique;
  j["params"] = r.params;
  for (const auto& [key, value] : numericColumns(r)) j[key] = jsonNumber(value);
  return j;
}

std::string resultsJson(const std::vector<ShadowBenchScene>& scenes, const std::vector<ShadowBenchRow>& rows,
                        const std::string& title, const std::string& machine) {
  std::string s = "{\n  \"title\": " + report::jsonLine(Json(title)) + ",\n  \"machine\": " + report::jsonLine(Json(machine)) +
                  ",\n  \"scenes\": [";
  for (size_t i = 0; i < scenes.size(); ++i) {
    const ShadowBenchScene& sc = scenes[i];
    Json j;
    j["name"] = sc.name;
    j["description"] = sc.description;
    j["reference_image"] = sc.referenceImage;
    j["reference_note"] = sc.referenceNote;
    j["width"] = sc.width;
    j["height"] = sc.height;
    s += (i ? ",\n    " : "\n    ") + report::jsonLine(j);
  }
  s += scenes.empty() ? "],\n  \"rows\": [" : "\n  ],\n  \"rows\": [";
  for (size_t i = 0; i < rows.size(); ++i) s += (i ? ",\n    " : "\n    ") + toJson(rows[i]);
  s += rows.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return s;
}

// ---- Pareto plot (SVG) --------------------------------------------------------------------------

std::string rowLabel(const ShadowBenchRow& r) {
  return r.params.empty() ? r.technique : r.technique + " " + r.params;
}

// Techniques in the order they first appear in all rows, so a technique looks the same in every
// scene's plot.
std::vector<std::string> techniqueOrder(const std::vector<ShadowBenchRow>& rows) {
  std::vector<std::string> order;
  for (const ShadowBenchRow& r : rows)
    if (std::find(order.begin(), order.end(), r.technique) == order.end()) order.push_back(r.technique);
  return order;
}

std::string paretoSvg(const ShadowBenchScene& scene, const std::vector<ShadowBenchRow>& rows,
                      const std::vector<std::string>& techniques) {
  report::PlotSpec spec;
  spec.title = scene.name + ": error against time";
  spec.xLabel = "total time per frame (ms)";
  spec.yLabel = "RMSE of V against the reference (fraction of light)";
  spec.seriesOrder = techniques;
  std::vector<report::PlotPoint> points;
  for (const ShadowBenchRow& r : rows) points.push_back({r.msTotal, r.rmseV, r.technique, rowLabel(r), false});
  return report::paretoSvg(spec, points);
}

// ---- HTML ---------------------------------------------------------------------------------------

using report::escapeXml;
using report::fmtBias;
using report::fmtErr;
using report::fmtMs;
using report::fmtPercent;
using report::thumb;
using report::urlAttr;

std::string swatch(raster::Rgba8 c) {
  return "<span class=\"swatch\" style=\"background: rgb(" + std::to_string(c.r) + "," + std::to_string(c.g) +
         "," + std::to_string(c.b) + ")\"></span>";
}

std::string sceneSection(size_t index, const ShadowBenchScene& scene, const std::vector<ShadowBenchRow>& rows,
                         const std::vector<bool>& front, const std::string& plotFile) {
  std::string s =
      "<section id=\"scene-" + std::to_string(index) + "\">\n<h2>" + escapeXml(scene.name) + "</h2>\n";
  if (!scene.description.empty()) s += "<p>" + escapeXml(scene.description) + "</p>\n";
  if (scene.width > 0 && scene.height > 0)
    s += "<p class=\"note\">" + std::to_string(scene.width) + " x " + std::to_string(scene.height) +
         " pixels</p>\n";
  if (!scene.referenceImage.empty() || !scene.referenceNote.empty()) {
    s += "<figure>";
    if (!scene.referenceImage.empty()) s += thumb(scene.referenceImage, "reference: " + scene.name);
    s += "<figcaption>Reference";
    if (!scene.referenceNote.empty()) s += ": " + escapeXml(scene.referenceNote);
    s += "</figcaption></figure>\n";
  }

  // A median's spread over the runs, and the two parts of a technique's maps (points, splat).
  const auto spread = [](double lo, double hi) {
    return lo == 0 && hi == 0 ? std::string() : "<br><small>" + fmtMs(lo) + "&ndash;" + fmtMs(hi) + "</small>";
  };
  const auto parts = [](const ShadowBenchRow& r) {
    return r.msPoints == 0 && r.msSplat == 0
               ? std::string()
               : "<br><small>points " + fmtMs(r.msPoints) + ", splat " + fmtMs(r.msSplat) + "</small>";
  };
  s += "<table>\n<tr><th>technique</th><th>params</th><th>views</th><th>maps ms</th><th>filter ms</th>"
       "<th>prepare ms</th><th>evaluate ms</th><th>total ms</th><th>RMSE V</th><th>bias V</th><th>max |err| V</th>"
       "<th>|err| &gt; 0.05</th><th>ground RMSE / bias</th><th>object RMSE / bias</th><th>contact RMSE / bias</th>"
       "<th>RMSE image</th></tr>\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const ShadowBenchRow& r = rows[i];
    auto num = [](const std::string& v) { return "<td class=\"num\">" + v + "</td>"; };
    s += front[i] ? "<tr class=\"pareto\">" : "<tr>";
    s += "<td>" + escapeXml(r.technique) + "</td><td>" + escapeXml(r.params) + "</td>" +
         num(r.views > 0 ? std::to_string(r.views) : "&ndash;") + num(fmtMs(r.msMaps) + spread(r.msMapsMin, r.msMapsMax) + parts(r)) +
         num(fmtMs(r.msFilter)) + num(fmtMs(r.msPrepare)) + num(fmtMs(r.msEvaluate) + spread(r.msEvaluateMin, r.msEvaluateMax)) +
         num(fmtMs(r.msTotal) + spread(r.msTotalMin, r.msTotalMax)) +
         num(fmtErr(r.rmseV)) + num(fmtBias(r.biasV)) + num(fmtErr(r.maxErrV)) + num(fmtPercent(r.fracErrGt005)) +
         num(fmtErr(r.rmseGround) + " / " + fmtBias(r.biasGround)) +
         num(fmtErr(r.rmseObject) + " / " + fmtBias(r.biasObject)) +
         num(fmtErr(r.rmseContact) + " / " + fmtBias(r.biasContact)) + num(fmtErr(r.rmseImage)) + "</tr>\n";
  }
  s += "</table>\n<p class=\"note\">Times are medians over the runs, with the fastest and slowest run under "
       "them. Highlighted rows are Pareto-optimal: no other row here is both as fast and as accurate and better in "
       "one of the two.</p>\n";
  s += "<p><img class=\"plot\" src=\"" + urlAttr(plotFile) + "\" alt=\"" +
       escapeXml("error against time, " + scene.name) + "\"></p>\n";

  bool any = false;
  for (const ShadowBenchRow& r : rows) any = any || !r.image.empty() || !r.heatMap.empty();
  if (any) {
    s += "<p class=\"note\">Each technique's image and the heat map of its error in V: " + swatch(kHeatBlue) +
         " too much shadow, " + swatch(kHeatWhite) + " exact, " + swatch(kHeatRed) + " light leaking, " +
         swatch(kHeatOutside) + " not compared. Click for the full size.</p>\n<div class=\"gallery\">\n";
    for (const ShadowBenchRow& r : rows) {
      if (r.image.empty() && r.heatMap.empty()) continue;
      s += "<figure><div>";
      if (!r.image.empty()) s += thumb(r.image, rowLabel(r));
      if (!r.heatMap.empty()) s += " " + thumb(r.heatMap, "error heat map: " + rowLabel(r));
      s += "</div><figcaption>" + escapeXml(rowLabel(r)) + " &mdash; " + fmtMs(r.msTotal) + " ms, RMSE V " +
           fmtErr(r.rmseV) + "</figcaption></figure>\n";
    }
    s += "</div>\n";
  }
  return s + "</section>\n";
}

std::string indexHtml(const std::vector<ShadowBenchScene>& scenes,
                      const std::vector<std::vector<size_t>>& sceneRows,
                      const std::vector<ShadowBenchRow>& rows, const std::vector<std::vector<bool>>& fronts,
                      const std::vector<std::string>& plots, const std::string& title,
                      const std::string& machine) {
  std::string s;
  if (!machine.empty()) s += "<p class=\"machine\">" + escapeXml(machine) + "</p>\n";
  s += "<p>Times are wall-clock milliseconds per frame: maps (rasterizing the light's views), filter (image "
       "kernels over the maps), prepare (maps and filter), evaluate (per-pixel lookups). Errors compare the "
       "visible fraction V of the area light with the ray-traced reference over the receivers the light "
       "reaches. "
       "Data: <a href=\"results.json\">results.json</a>, <a href=\"results.csv\">results.csv</a>.</p>\n";
  if (!scenes.empty()) {
    s += "<ul>\n";
    for (size_t i = 0; i < scenes.size(); ++i)
      s += "<li><a href=\"#scene-" + std::to_string(i) + "\">" + escapeXml(scenes[i].name) + "</a></li>\n";
    s += "</ul>\n";
  }
  for (size_t i = 0; i < scenes.size(); ++i) {
    std::vector<ShadowBenchRow> mine;
    for (size_t r : sceneRows[i]) mine.push_back(rows[r]);
    s += sceneSection(i, scenes[i], mine, fronts[i], plots[i]);
  }
  return report::htmlPage(title, s);
}

}  // namespace

std::string toJson(const ShadowBenchRow& row) {
  return report::jsonLine(rowJson(row));
}

std::string csvHeader() {
  std::string s = "scene,technique,params";
  for (const auto& [key, value] : numericColumns(ShadowBenchRow{})) s += std::string(",") + key;
  return s;
}

std::string toCsv(const ShadowBenchRow& r) {
  std::string s = report::csvField(r.scene) + "," + report::csvField(r.technique) + "," + report::csvField(r.params);
  for (const auto& [key, value] : numericColumns(r)) {
    s += ',';  // appended separately: GCC 12 warns (-Wrestrict, a false positive) on "," + std::string
    s += report::number(value);
  }
  return s;
}

std::vector<bool> paretoFront(const std::vector<ShadowBenchRow>& rows) {
  std::vector<std::pair<double, double>> points;
  for (const ShadowBenchRow& r : rows) points.emplace_back(r.msTotal, r.rmseV);
  return report::paretoFront(points);
}

std::vector<std::string> paretoPlotFileNames(const std::vector<ShadowBenchScene>& scenes) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (const ShadowBenchScene& sc : scenes) {
    std::string base;
    for (char c : sc.name) {
      const auto u = static_cast<unsigned char>(c);
      const bool keep = (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') ||
                        c == '-' || c == '_' || c == '.';
      base += keep ? c : '_';
    }
    if (base.empty()) base = "scene";
    std::string name = "pareto-" + base + ".svg";
    for (int k = 2; !taken.insert(name).second; ++k)
      name = "pareto-" + base + "-" + std::to_string(k) + ".svg";
    names.push_back(name);
  }
  return names;
}

Status writeShadowReport(const std::string& dir, const std::vector<ShadowBenchScene>& scenes,
                         const std::vector<ShadowBenchRow>& rows, const std::string& title,
                         const std::string& machineNote) {
  const std::string where = "report " + dir;
  if (dir.empty()) return Error{"report", "no directory given"};
  // Rows grouped by scene, in the order given.
  std::map<std::string, size_t> sceneIndex;
  for (size_t i = 0; i < scenes.size(); ++i)
    if (!sceneIndex.emplace(scenes[i].name, i).second)
      return Error{where, "two scenes are named '" + scenes[i].name + "'"};
  std::vector<std::vector<size_t>> sceneRows(scenes.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    const auto it = sceneIndex.find(rows[r].scene);
    if (it == sceneIndex.end())
      return Error{where, "row " + std::to_string(r) + " (" + rows[r].technique + ") names scene '" +
                              rows[r].scene + "', which is not in the scene list"};
    sceneRows[it->second].push_back(r);
  }

  try {
    const fs::path d(dir);
    std::error_code ec;
    fs::create_directories(d, ec);
    if (ec) return Error{dir, "cannot create the directory: " + ec.message()};
    if (!fs::is_directory(d, ec)) return Error{dir, "not a directory"};

    if (Status st = writeFileAtomically(d / "results.json", resultsJson(scenes, rows, title, machineNote));
        !st)
      return st;
    std::string csv = csvHeader() + "\n";
    for (const ShadowBenchRow& r : rows) csv += toCsv(r) + "\n";
    if (Status st = writeFileAtomically(d / "results.csv", csv); !st) return st;

    const std::vector<std::string> techniques = techniqueOrder(rows);
    const std::vector<std::string> plots = paretoPlotFileNames(scenes);
    std::vector<std::vector<bool>> fronts;
    for (size_t i = 0; i < scenes.size(); ++i) {
      std::vector<ShadowBenchRow> mine;
      for (size_t r : sceneRows[i]) mine.push_back(rows[r]);
      fronts.push_back(paretoFront(mine));
      if (Status st = writeFileAtomically(d / plots[i], paretoSvg(scenes[i], mine, techniques));
          !st)
        return st;
    }
    return writeFileAtomically(d / "index.html",
                               indexHtml(scenes, sceneRows, rows, fronts, plots, title, machineNote));
  } catch (const std::exception& e) {
    return Error{where, e.what()};
  }
}

}  // namespace penumbra::engine
