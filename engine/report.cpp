#include "engine/report.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace penumbra::engine::report {

namespace {

std::string printf1(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

std::string escapeXml(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

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

std::string number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

Json jsonNumber(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

std::string jsonLine(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

std::string jsonFile(const Json& j) { return j.dump(1, ' ', false, Json::error_handler_t::replace) + "\n"; }

std::string fmtMs(double ms) {
  if (!std::isfinite(ms)) return number(ms);
  const double a = std::fabs(ms);
  return printf1(a >= 100 ? "%.0f" : a >= 10 ? "%.1f" : "%.2f", ms);
}
std::string fmtErr(double e) {
  if (!std::isfinite(e)) return number(e);
  return printf1(e != 0 && std::fabs(e) < 1e-4 ? "%.1e" : "%.4f", e);
}
std::string fmtBias(double e) { return std::isfinite(e) ? printf1("%+.4f", e) : number(e); }
std::string fmtPercent(double f) { return std::isfinite(f) ? printf1("%.2f%%", 100 * f) : number(f); }

std::vector<bool> paretoFront(const std::vector<std::pair<double, double>>& pts) {
  auto valid = [](const std::pair<double, double>& p) { return std::isfinite(p.first) && std::isfinite(p.second); };
  std::vector<bool> front(pts.size(), false);
  for (size_t i = 0; i < pts.size(); ++i) {
    if (!valid(pts[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < pts.size() && !dominated; ++j) {
      const auto &a = pts[j], &b = pts[i];
      dominated = j != i && valid(a) && a.first <= b.first && a.second <= b.second &&
                  (a.first < b.first || a.second < b.second);
    }
    front[i] = !dominated;
  }
  return front;
}

// ---- The plot ------------------------------------------------------------------------------------

namespace {

// Tableau 10: distinct hues that stay apart for common color-vision deficiencies; series beyond
// ten reuse the colors with another marker shape.
constexpr const char* kPalette[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                    "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
constexpr int kPaletteSize = 10;
constexpr int kShapes = 4;  // circle, square, triangle, diamond

std::string p2(double v) { return printf1("%.2f", v); }

// A marker of the style centred on (x, y), radius about r pixels, of class cls ("marker" for data
// points: one per plotted point; "key" in the legend); `inner` (a <title>) goes inside it.
std::string marker(const char* cls, int style, double x, double y, double r, const std::string& attrs,
                   const std::string& inner) {
  const char* color = kPalette[style % kPaletteSize];
  const int shape = (style / kPaletteSize) % kShapes;
  std::string tag, geometry;
  if (shape == 0) {
    tag = "circle";
    geometry = "cx=\"" + p2(x) + "\" cy=\"" + p2(y) + "\" r=\"" + p2(r) + "\"";
  } else if (shape == 1) {
    tag = "rect";
    geometry = "x=\"" + p2(x - r) + "\" y=\"" + p2(y - r) + "\" width=\"" + p2(2 * r) + "\" height=\"" + p2(2 * r) + "\"";
  } else if (shape == 2) {
    tag = "path";
    geometry = "d=\"M" + p2(x) + " " + p2(y - 1.2 * r) + "L" + p2(x + 1.1 * r) + " " + p2(y + 0.8 * r) + "L" +
               p2(x - 1.1 * r) + " " + p2(y + 0.8 * r) + "Z\"";
  } else {
    tag = "path";
    geometry = "d=\"M" + p2(x) + " " + p2(y - 1.3 * r) + "L" + p2(x + 1.3 * r) + " " + p2(y) + "L" + p2(x) + " " +
               p2(y + 1.3 * r) + "L" + p2(x - 1.3 * r) + " " + p2(y) + "Z\"";
  }
  const std::string open = "<" + tag + " class=\"" + cls + "\" " + geometry + " fill=\"" + color + "\" " + attrs;
  return inner.empty() ? open + "/>" : open + ">" + inner + "</" + tag + ">";
}

// An axis maps a value range to pixels, on a log10 or linear scale, with tick values to label.
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;      // in scale units (log10 of the value when log)
  std::vector<double> ticks;  // values (not scale units)
  double scaled(double v) const { return log ? std::log10(v) : v; }
  double t(double v) const { return (scaled(v) - lo) / (hi - lo); }  // position in [0, 1]
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

// "time (ms)" -> "time (ms, log scale)"; "error" -> "error (log scale)".
std::string logCaption(const std::string& caption) {
  if (!caption.empty() && caption.back() == ')') return caption.substr(0, caption.size() - 1) + ", log scale)";
  return caption + " (log scale)";
}

bool plottable(const PlotPoint& p) { return std::isfinite(p.x) && p.x > 0 && std::isfinite(p.y) && p.y >= 0; }

}  // namespace

std::string paretoSvg(const PlotSpec& spec, const std::vector<PlotPoint>& points) {
  // Layout in pixels: the plot area, with room for tick labels left and below, the legend right.
  constexpr double kW = 800, kH = 500, kLeft = 80, kRight = 600, kTop = 44, kBottom = 440;
  std::map<std::string, int> styles;
  for (const std::string& s : spec.seriesOrder) styles.emplace(s, static_cast<int>(styles.size()));
  for (const PlotPoint& p : points) styles.emplace(p.series, static_cast<int>(styles.size()));
  std::vector<std::pair<double, double>> xy;
  for (const PlotPoint& p : points) xy.emplace_back(p.x, p.y);
  const std::vector<bool> front = paretoFront(xy);

  std::vector<size_t> shown;
  for (size_t i = 0; i < points.size(); ++i)
    if (plottable(points[i])) shown.push_back(i);
  double xMin = 1, xMax = 1, yMin = 0, yMax = 0;
  if (!shown.empty()) {
    xMin = xMax = points[shown[0]].x;
    yMin = yMax = points[shown[0]].y;
    for (size_t i : shown) {
      xMin = std::min(xMin, points[i].x), xMax = std::max(xMax, points[i].x);
      yMin = std::min(yMin, points[i].y), yMax = std::max(yMax, points[i].y);
    }
  }
  const Axis ax = logAxis(xMin, xMax);
  // Errors spanning a decade or more read better on a log scale; a zero error needs a linear one.
  const bool logY = yMin > 0 && yMax >= 10 * yMin;
  const Axis ay = logY ? logAxis(yMin, yMax) : linearAxis(yMax);
  auto px = [&](double x) { return kLeft + ax.t(x) * (kRight - kLeft); };
  auto py = [&](double y) { return kBottom - ay.t(y) * (kBottom - kTop); };

  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + p2(kW) + "\" height=\"" + p2(kH) +
                  "\" viewBox=\"0 0 " + p2(kW) + " " + p2(kH) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<title>" + escapeXml(spec.title) + "</title>\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  s += "<text x=\"" + p2(kLeft) + "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">" + escapeXml(spec.title) +
       "</text>\n";
  // Grid, ticks and tick labels.
  for (double v : ax.ticks) {
    const double x = px(v);
    s += "<line x1=\"" + p2(x) + "\" y1=\"" + p2(kTop) + "\" x2=\"" + p2(x) + "\" y2=\"" + p2(kBottom) +
         "\" stroke=\"#e3e3e3\"/>\n";
    s += "<text x=\"" + p2(x) + "\" y=\"" + p2(kBottom + 18) + "\" text-anchor=\"middle\">" + printf1("%g", v) +
         "</text>\n";
  }
  for (double v : ay.ticks) {
    const double y = py(v);
    s += "<line x1=\"" + p2(kLeft) + "\" y1=\"" + p2(y) + "\" x2=\"" + p2(kRight) + "\" y2=\"" + p2(y) +
         "\" stroke=\"#e3e3e3\"/>\n";
    s += "<text x=\"" + p2(kLeft - 8) + "\" y=\"" + p2(y + 4) + "\" text-anchor=\"end\">" + printf1("%g", v) +
         "</text>\n";
  }
  s += "<rect x=\"" + p2(kLeft) + "\" y=\"" + p2(kTop) + "\" width=\"" + p2(kRight - kLeft) + "\" height=\"" +
       p2(kBottom - kTop) + "\" fill=\"none\" stroke=\"#444444\"/>\n";
  s += "<text x=\"" + p2((kLeft + kRight) / 2) + "\" y=\"" + p2(kBottom + 42) + "\" text-anchor=\"middle\">" +
       escapeXml(logCaption(spec.xLabel)) + "</text>\n";
  s += "<text transform=\"translate(18 " + p2((kTop + kBottom) / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
       escapeXml(logY ? logCaption(spec.yLabel) : spec.yLabel) + "</text>\n";

  // The Pareto front, left to right.
  std::vector<size_t> frontPoints;
  for (size_t i : shown)
    if (front[i]) frontPoints.push_back(i);
  std::sort(frontPoints.begin(), frontPoints.end(), [&](size_t a, size_t b) {
    return points[a].x != points[b].x ? points[a].x < points[b].x : points[a].y > points[b].y;
  });
  if (frontPoints.size() > 1) {
    s += "<polyline fill=\"none\" stroke=\"#333333\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\" points=\"";
    for (size_t k = 0; k < frontPoints.size(); ++k)
      s += (k ? " " : "") + p2(px(points[frontPoints[k]].x)) + "," + p2(py(points[frontPoints[k]].y));
    s += "\"/>\n";
  }
  // One marker per plotted point (Pareto-optimal ones outlined in black).
  for (size_t i : shown) {
    const PlotPoint& p = points[i];
    const std::string attrs =
        std::string(front[i] ? "stroke=\"#000000\" stroke-width=\"1.5\"" : "stroke=\"#ffffff\" stroke-width=\"0.8\"") +
        (p.faded ? " fill-opacity=\"0.35\"" : "");
    s += marker("marker", styles.at(p.series), px(p.x), py(p.y), front[i] ? 6 : 5, attrs,
                "<title>" + escapeXml(p.label) + ": " + fmtMs(p.x) + " ms, " + fmtErr(p.y) + "</title>") +
         "\n";
  }
  for (size_t i : shown) {
    if (!front[i] && !spec.labelAll) continue;
    const double x = px(points[i].x), y = py(points[i].y);
    const bool right = x < kRight - 120;  // labels near the right edge go to the left of the marker
    s += "<text x=\"" + p2(right ? x + 9 : x - 9) + "\" y=\"" + p2(y - 7) + "\" font-size=\"10\"" +
         (right ? "" : " text-anchor=\"end\"") + ">" + escapeXml(points[i].label) + "</text>\n";
  }
  // Legend: the series in the order they appear, then the front.
  double ly = kTop + 8;
  std::set<std::string> listed;
  for (const PlotPoint& p : points) {
    if (!listed.insert(p.series).second) continue;
    s += marker("key", styles.at(p.series), kRight + 24, ly, 5, "stroke=\"none\"", "") + "\n";
    s += "<text x=\"" + p2(kRight + 36) + "\" y=\"" + p2(ly + 4) + "\">" + escapeXml(p.series) + "</text>\n";
    ly += 20;
  }
  s += "<line x1=\"" + p2(kRight + 14) + "\" y1=\"" + p2(ly) + "\" x2=\"" + p2(kRight + 34) + "\" y2=\"" + p2(ly) +
       "\" stroke=\"#333333\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"/>\n";
  s += "<text x=\"" + p2(kRight + 40) + "\" y=\"" + p2(ly + 4) + "\">Pareto front</text>\n";
  std::string note = spec.note;
  if (shown.size() < points.size())
    note += (note.empty() ? "" : "; ") + std::to_string(points.size() - shown.size()) +
            " point(s) not plotted: time not positive or not finite, or error not finite";
  if (!note.empty())
    s += "<text x=\"" + p2(kLeft) + "\" y=\"" + p2(kH - 6) + "\" font-size=\"11\">" + escapeXml(note) + "</text>\n";
  s += "</svg>\n";
  return s;
}

// ---- HTML ---------------------------------------------------------------------------------------

namespace {

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

}  // namespace

std::string htmlPage(const std::string& title, const std::string& body) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + escapeXml(title) +
         "</title>\n<style>\n" + kCss + "</style>\n</head>\n<body>\n<h1>" + escapeXml(title) + "</h1>\n" + body +
         "</body>\n</html>\n";
}

std::string thumb(const std::string& file, const std::string& alt) {
  return "<a href=\"" + urlAttr(file) + "\"><img class=\"thumb\" src=\"" + urlAttr(file) + "\" alt=\"" +
         escapeXml(alt) + "\"></a>";
}

}  // namespace penumbra::engine::report
