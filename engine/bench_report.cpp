#include "engine/bench_report.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>

#include "engine/metrics.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// ---- Text ---------------------------------------------------------------------------------------

// Shortest decimal form that reads back to the same double (std::to_chars without a format).
std::string number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string printf1(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Text inside HTML or SVG elements and attribute values.
std::string escapeXml(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// A relative path as a URL path: bytes other than unreserved characters and '/' percent-encoded
// (so ':', '?', '#', '%' and spaces cannot change what the link means), then escaped for HTML.
std::string urlAttr(const std::string& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if ((u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || c == '-' || c == '.' ||
        c == '_' || c == '~' || c == '/') {
      out += c;
    } else {
      out += '%';
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  return escapeXml(out);
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// Table cells: milliseconds with about three significant digits, errors with four decimals.
std::string fmtMs(double ms) {
  if (!std::isfinite(ms)) return number(ms);
  const double a = std::fabs(ms);
  return printf1(a >= 100 ? "%.0f" : a >= 10 ? "%.1f" : "%.2f", ms);
}
std::string fmtErr(double e) {
  if (!std::isfinite(e)) return number(e);
  return printf1(e != 0 && std::fabs(e) < 1e-4 ? "%.1e" : "%.4f", e);
}
std::string fmtPercent(double f) {
  return std::isfinite(f) ? printf1("%.2f%%", 100 * f) : number(f);
}
std::string fmtTick(double v) {
  return printf1("%g", v);
}

// ---- Files --------------------------------------------------------------------------------------

std::string errnoMessage(int err) {
  return std::error_code(err, std::generic_category()).message();
}

Status writeFileAtomically(const fs::path& target, const std::string& content) {
  static std::atomic<unsigned> counter{0};
  const fs::path tmp = target.parent_path() /
                       (target.filename().string() + ".tmp-" + std::to_string(static_cast<long>(::getpid())) +
                        "-" + std::to_string(counter.fetch_add(1, std::memory_order_relaxed)));
  const std::string where = target.string();
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) return Error{where, "cannot write: " + errnoMessage(errno)};
  bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  int err = ok ? 0 : errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    err = errno;
  }
  std::error_code ec;
  if (ok) {
    fs::rename(tmp, target, ec);
    if (!ec) return Ok{};
  }
  fs::remove(tmp, ec);
  return Error{where, ok ? "cannot replace the file" : "cannot write: " + errnoMessage(err)};
}

// ---- JSON and CSV -------------------------------------------------------------------------------

Json jsonNumber(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

Json rowJson(const ShadowBenchRow& r) {
  Json j;
  j["scene"] = r.scene;
  j["technique"] = r.technique;
  j["params"] = r.params;
  j["ms_maps"] = jsonNumber(r.msMaps);
  j["ms_filter"] = jsonNumber(r.msFilter);
  j["ms_prepare"] = jsonNumber(r.msPrepare);
  j["ms_evaluate"] = jsonNumber(r.msEvaluate);
  j["ms_total"] = jsonNumber(r.msTotal);
  j["rmse_v"] = jsonNumber(r.rmseV);
  j["max_err_v"] = jsonNumber(r.maxErrV);
  j["frac_err_gt_005"] = jsonNumber(r.fracErrGt005);
  j["rmse_image"] = jsonNumber(r.rmseImage);
  return j;
}

// Invalid UTF-8 (a name read from a file) becomes U+FFFD rather than an exception.
std::string dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string resultsJson(const std::vector<ShadowBenchScene>& scenes, const std::vector<ShadowBenchRow>& rows,
                        const std::string& title, const std::string& machine) {
  std::string s = "{\n  \"title\": " + dump(Json(title)) + ",\n  \"machine\": " + dump(Json(machine)) +
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
    s += (i ? ",\n    " : "\n    ") + dump(j);
  }
  s += scenes.empty() ? "],\n  \"rows\": [" : "\n  ],\n  \"rows\": [";
  for (size_t i = 0; i < rows.size(); ++i) s += (i ? ",\n    " : "\n    ") + toJson(rows[i]);
  s += rows.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return s;
}

// ---- Pareto plot (SVG) --------------------------------------------------------------------------

// Tableau 10: distinct hues that stay apart for common color-vision deficiencies; techniques
// beyond ten reuse the colors with another marker shape.
constexpr const char* kPalette[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                    "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
constexpr int kPaletteSize = 10;
constexpr int kShapes = 4;  // circle, square, triangle, diamond

// One color/shape per technique, in the order techniques first appear in the rows, so a technique
// looks the same in every scene's plot.
using TechniqueStyles = std::map<std::string, int>;

TechniqueStyles techniqueStyles(const std::vector<ShadowBenchRow>& rows) {
  TechniqueStyles styles;
  for (const ShadowBenchRow& r : rows) styles.emplace(r.technique, static_cast<int>(styles.size()));
  return styles;
}

// A marker of the technique's style centred on (x, y), radius about r pixels, of class cls ("marker"
// for data points: one per plotted row; "key" in the legend); `inner` (a <title>) goes inside it.
std::string marker(const char* cls, int style, double x, double y, double r, const std::string& stroke,
                   const std::string& inner) {
  const char* color = kPalette[style % kPaletteSize];
  const int shape = (style / kPaletteSize) % kShapes;
  auto p = [](double v) { return printf1("%.2f", v); };
  std::string tag, geometry;
  if (shape == 0) {
    tag = "circle";
    geometry = "cx=\"" + p(x) + "\" cy=\"" + p(y) + "\" r=\"" + p(r) + "\"";
  } else if (shape == 1) {
    tag = "rect";
    geometry = "x=\"" + p(x - r) + "\" y=\"" + p(y - r) + "\" width=\"" + p(2 * r) + "\" height=\"" +
               p(2 * r) + "\"";
  } else if (shape == 2) {
    tag = "path";
    geometry = "d=\"M" + p(x) + " " + p(y - 1.2 * r) + "L" + p(x + 1.1 * r) + " " + p(y + 0.8 * r) + "L" +
               p(x - 1.1 * r) + " " + p(y + 0.8 * r) + "Z\"";
  } else {
    tag = "path";
    geometry = "d=\"M" + p(x) + " " + p(y - 1.3 * r) + "L" + p(x + 1.3 * r) + " " + p(y) + "L" + p(x) + " " +
               p(y + 1.3 * r) + "L" + p(x - 1.3 * r) + " " + p(y) + "Z\"";
  }
  const std::string open =
      "<" + tag + " class=\"" + cls + "\" " + geometry + " fill=\"" + color + "\" " + stroke;
  return inner.empty() ? open + "/>" : open + ">" + inner + "</" + tag + ">";
}

// An axis maps a value range to pixels, on a log10 or linear scale, with tick values to label.
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;      // in scale units (log10 of the value when log)
  std::vector<double> ticks;  // values (not scale units)

  double scaled(double v) const { return log ? std::log10(v) : v; }
  // Position in [0, 1] from lo to hi.
  double t(double v) const { return (scaled(v) - lo) / (hi - lo); }
};

// Log axis over values in [vmin, vmax] (> 0): padded by 5% of the span (a factor of 2 each way for a
// single value), ticks at 1, 2, 5 x 10^k or every integer multiple when the range is narrow.
Axis logAxis(double vmin, double vmax) {
  Axis a;
  a.log = true;
  const double l0 = std::log10(vmin), l1 = std::log10(vmax);
  const double pad = l1 > l0 ? 0.05 * (l1 - l0) : std::log10(2.0);
  a.lo = l0 - pad;
  a.hi = l1 + pad;
  const std::vector<std::vector<double>> mantissas = {{1}, {1, 2, 5}, {1, 2, 3, 4, 5, 6, 7, 8, 9}};
  for (const std::vector<double>& ms : mantissas) {
    a.ticks.clear();
    for (int k = static_cast<int>(std::floor(a.lo)); k <= static_cast<int>(std::ceil(a.hi)); ++k)
      for (double m : ms) {
        const double v = m * std::pow(10.0, k);
        if (std::log10(v) >= a.lo && std::log10(v) <= a.hi) a.ticks.push_back(v);
      }
    if (a.ticks.size() >= 3) break;
  }
  return a;
}

// Linear axis from 0 to a little above vmax (>= 0), ticks at a 1, 2 or 5 x 10^k step.
Axis linearAxis(double vmax) {
  Axis a;
  a.hi = vmax > 0 ? vmax * 1.08 : 1.0;
  const double raw = a.hi / 5;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw <= p ? p : raw <= 2 * p ? 2 * p : raw <= 5 * p ? 5 * p : 10 * p;
  for (int i = 0; i * step <= a.hi * (1 + 1e-9); ++i) a.ticks.push_back(i * step);
  return a;
}

bool plottable(const ShadowBenchRow& r) {
  return std::isfinite(r.msTotal) && r.msTotal > 0 && std::isfinite(r.rmseV) && r.rmseV >= 0;
}

std::string rowLabel(const ShadowBenchRow& r) {
  return r.params.empty() ? r.technique : r.technique + " " + r.params;
}

std::string paretoSvg(const ShadowBenchScene& scene, const std::vector<ShadowBenchRow>& rows,
                      const std::vector<bool>& front, const TechniqueStyles& styles) {
  // Layout in pixels: the plot area, with room for tick labels left and below, the legend right.
  constexpr double kW = 800, kH = 500, kLeft = 80, kRight = 600, kTop = 44, kBottom = 440;
  auto p = [](double v) { return printf1("%.2f", v); };

  std::vector<size_t> shown;
  for (size_t i = 0; i < rows.size(); ++i)
    if (plottable(rows[i])) shown.push_back(i);
  double msMin = 1, msMax = 1, errMin = 0, errMax = 0;
  if (!shown.empty()) {
    msMin = msMax = rows[shown[0]].msTotal;
    errMin = errMax = rows[shown[0]].rmseV;
    for (size_t i : shown) {
      msMin = std::min(msMin, rows[i].msTotal);
      msMax = std::max(msMax, rows[i].msTotal);
      errMin = std::min(errMin, rows[i].rmseV);
      errMax = std::max(errMax, rows[i].rmseV);
    }
  }
  const Axis ax = logAxis(msMin, msMax);
  // Errors spanning a decade or more read better on a log scale; a zero error needs a linear one.
  const bool logY = errMin > 0 && errMax >= 10 * errMin;
  const Axis ay = logY ? logAxis(errMin, errMax) : linearAxis(errMax);
  auto px = [&](double ms) { return kLeft + ax.t(ms) * (kRight - kLeft); };
  auto py = [&](double err) { return kBottom - ay.t(err) * (kBottom - kTop); };

  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + p(kW) + "\" height=\"" + p(kH) +
                  "\" viewBox=\"0 0 " + p(kW) + " " + p(kH) +
                  "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<title>" + escapeXml(scene.name) + ": RMSE of V against total time</title>\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  s += "<text x=\"" + p(kLeft) + "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">" +
       escapeXml(scene.name) + ": error against time</text>\n";

  // Grid, ticks and tick labels.
  for (double v : ax.ticks) {
    const double x = px(v);
    s += "<line x1=\"" + p(x) + "\" y1=\"" + p(kTop) + "\" x2=\"" + p(x) + "\" y2=\"" + p(kBottom) +
         "\" stroke=\"#e3e3e3\"/>\n";
    s += "<text x=\"" + p(x) + "\" y=\"" + p(kBottom + 18) + "\" text-anchor=\"middle\">" + fmtTick(v) +
         "</text>\n";
  }
  for (double v : ay.ticks) {
    const double y = py(v);
    s += "<line x1=\"" + p(kLeft) + "\" y1=\"" + p(y) + "\" x2=\"" + p(kRight) + "\" y2=\"" + p(y) +
         "\" stroke=\"#e3e3e3\"/>\n";
    s += "<text x=\"" + p(kLeft - 8) + "\" y=\"" + p(y + 4) + "\" text-anchor=\"end\">" + fmtTick(v) +
         "</text>\n";
  }
  s += "<rect x=\"" + p(kLeft) + "\" y=\"" + p(kTop) + "\" width=\"" + p(kRight - kLeft) + "\" height=\"" +
       p(kBottom - kTop) + "\" fill=\"none\" stroke=\"#444444\"/>\n";
  s += "<text x=\"" + p((kLeft + kRight) / 2) + "\" y=\"" + p(kBottom + 42) +
       "\" text-anchor=\"middle\">total time per frame (ms, log scale)</text>\n";
  s += "<text transform=\"translate(18 " + p((kTop + kBottom) / 2) +
       ") rotate(-90)\" text-anchor=\"middle\">RMSE of V against the reference (fraction of light" +
       std::string(logY ? ", log scale)" : ")") + "</text>\n";

  // The Pareto front, left to right.
  std::vector<size_t> frontRows;
  for (size_t i : shown)
    if (front[i]) frontRows.push_back(i);
  std::sort(frontRows.begin(), frontRows.end(), [&](size_t a, size_t b) {
    return rows[a].msTotal != rows[b].msTotal ? rows[a].msTotal < rows[b].msTotal
                                              : rows[a].rmseV > rows[b].rmseV;
  });
  if (frontRows.size() > 1) {
    s += "<polyline fill=\"none\" stroke=\"#333333\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\" points=\"";
    for (size_t k = 0; k < frontRows.size(); ++k)
      s += (k ? " " : "") + p(px(rows[frontRows[k]].msTotal)) + "," + p(py(rows[frontRows[k]].rmseV));
    s += "\"/>\n";
  }

  // One marker per plotted row (Pareto-optimal ones outlined in black and labelled).
  for (size_t i : shown) {
    const ShadowBenchRow& r = rows[i];
    const double x = px(r.msTotal), y = py(r.rmseV);
    const std::string stroke =
        front[i] ? "stroke=\"#000000\" stroke-width=\"1.5\"" : "stroke=\"#ffffff\" stroke-width=\"0.8\"";
    s += marker("marker", styles.at(r.technique), x, y, front[i] ? 6 : 5, stroke,
                "<title>" + escapeXml(rowLabel(r)) + ": " + fmtMs(r.msTotal) + " ms, RMSE " +
                    fmtErr(r.rmseV) + "</title>") +
         "\n";
  }
  for (size_t i : frontRows) {
    const double x = px(rows[i].msTotal), y = py(rows[i].rmseV);
    const bool right = x < kRight - 120;  // labels near the right edge go to the left of the marker
    s += "<text x=\"" + p(right ? x + 9 : x - 9) + "\" y=\"" + p(y - 7) + "\" font-size=\"10\"" +
         (right ? "" : " text-anchor=\"end\"") + ">" + escapeXml(rowLabel(rows[i])) + "</text>\n";
  }

  // Legend: this scene's techniques, then the front.
  double ly = kTop + 8;
  std::set<std::string> listed;
  for (const ShadowBenchRow& r : rows) {
    if (!listed.insert(r.technique).second) continue;
    s += marker("key", styles.at(r.technique), kRight + 24, ly, 5, "stroke=\"none\"", "") + "\n";
    s += "<text x=\"" + p(kRight + 36) + "\" y=\"" + p(ly + 4) + "\">" + escapeXml(r.technique) + "</text>\n";
    ly += 20;
  }
  s += "<line x1=\"" + p(kRight + 14) + "\" y1=\"" + p(ly) + "\" x2=\"" + p(kRight + 34) + "\" y2=\"" +
       p(ly) + "\" stroke=\"#333333\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"/>\n";
  s += "<text x=\"" + p(kRight + 40) + "\" y=\"" + p(ly + 4) + "\">Pareto front</text>\n";
  if (shown.size() < rows.size())
    s += "<text x=\"" + p(kLeft) + "\" y=\"" + p(kH - 6) + "\" font-size=\"11\">" +
         std::to_string(rows.size() - shown.size()) +
         " row(s) not plotted: time not positive or not finite, or error not finite</text>\n";
  s += "</svg>\n";
  return s;
}

// ---- HTML ---------------------------------------------------------------------------------------

constexpr const char* kCss =
    R"(body { font-family: sans-serif; margin: 24px; color: #222; max-width: 1400px; }
h1 { font-size: 1.5em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
.machine, .note { color: #555; }
table { border-collapse: collapse; font-size: 0.9em; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f0f0f0; }
tr.pareto td { background: #fff3c4; font-weight: bold; }
.gallery { display: flex; flex-wrap: wrap; gap: 16px; }
figure { margin: 0; }
figcaption { font-size: 0.85em; max-width: 500px; }
img.thumb { width: 240px; height: auto; border: 1px solid #aaa; image-rendering: auto; }
img.plot { max-width: 100%; height: auto; }
.swatch { display: inline-block; width: 1em; height: 1em; vertical-align: middle; border: 1px solid #888; }
)";

std::string thumb(const std::string& file, const std::string& alt) {
  return "<a href=\"" + urlAttr(file) + "\"><img class=\"thumb\" src=\"" + urlAttr(file) + "\" alt=\"" +
         escapeXml(alt) + "\"></a>";
}

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

  s += "<table>\n<tr><th>technique</th><th>params</th><th>views</th><th>maps ms</th><th>filter ms</th>"
       "<th>prepare ms</th><th>evaluate ms</th><th>total ms</th><th>RMSE V</th><th>max |err| V</th>"
       "<th>|err| &gt; 0.05</th><th>RMSE image</th></tr>\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const ShadowBenchRow& r = rows[i];
    auto num = [](const std::string& v) { return "<td class=\"num\">" + v + "</td>"; };
    s += front[i] ? "<tr class=\"pareto\">" : "<tr>";
    s += "<td>" + escapeXml(r.technique) + "</td><td>" + escapeXml(r.params) + "</td>" +
         num(r.views > 0 ? std::to_string(r.views) : "&ndash;") + num(fmtMs(r.msMaps)) +
         num(fmtMs(r.msFilter)) + num(fmtMs(r.msPrepare)) + num(fmtMs(r.msEvaluate)) + num(fmtMs(r.msTotal)) +
         num(fmtErr(r.rmseV)) + num(fmtErr(r.maxErrV)) + num(fmtPercent(r.fracErrGt005)) +
         num(fmtErr(r.rmseImage)) + "</tr>\n";
  }
  s += "</table>\n<p class=\"note\">Highlighted rows are Pareto-optimal: no other row here is both as fast "
       "and as "
       "accurate and better in one of the two.</p>\n";
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
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                  escapeXml(title) + "</title>\n<style>\n" + kCss + "</style>\n</head>\n<body>\n<h1>" +
                  escapeXml(title) + "</h1>\n";
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
  return s + "</body>\n</html>\n";
}

}  // namespace

std::string toJson(const ShadowBenchRow& row) {
  return dump(rowJson(row));
}

std::string csvHeader() {
  return "scene,technique,params,ms_maps,ms_filter,ms_prepare,ms_evaluate,ms_total,rmse_v,max_err_v,"
         "frac_err_gt_005,rmse_image";
}

std::string toCsv(const ShadowBenchRow& r) {
  std::string s = csvField(r.scene) + "," + csvField(r.technique) + "," + csvField(r.params);
  for (double v : {r.msMaps, r.msFilter, r.msPrepare, r.msEvaluate, r.msTotal, r.rmseV, r.maxErrV,
                   r.fracErrGt005, r.rmseImage}) {
    s += ',';  // appended separately: GCC 12 warns (-Wrestrict, a false positive) on "," + std::string
    s += number(v);
  }
  return s;
}

std::vector<bool> paretoFront(const std::vector<ShadowBenchRow>& rows) {
  auto valid = [](const ShadowBenchRow& r) { return std::isfinite(r.msTotal) && std::isfinite(r.rmseV); };
  std::vector<bool> front(rows.size(), false);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!valid(rows[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < rows.size() && !dominated; ++j) {
      const ShadowBenchRow &a = rows[j], &b = rows[i];
      dominated = j != i && valid(a) && a.msTotal <= b.msTotal && a.rmseV <= b.rmseV &&
                  (a.msTotal < b.msTotal || a.rmseV < b.rmseV);
    }
    front[i] = !dominated;
  }
  return front;
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

    const TechniqueStyles styles = techniqueStyles(rows);
    const std::vector<std::string> plots = paretoPlotFileNames(scenes);
    std::vector<std::vector<bool>> fronts;
    for (size_t i = 0; i < scenes.size(); ++i) {
      std::vector<ShadowBenchRow> mine;
      for (size_t r : sceneRows[i]) mine.push_back(rows[r]);
      fronts.push_back(paretoFront(mine));
      if (Status st = writeFileAtomically(d / plots[i], paretoSvg(scenes[i], mine, fronts.back(), styles));
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
