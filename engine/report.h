// The pieces every report Penumbra writes is made of (the HTML pages, SVG plots, JSON and CSV of
// `bench shadows` and `bench stochastic`): escaping for HTML, SVG, URLs and CSV, numbers in the
// shortest form that reads back the same, one-line JSON, the Pareto front, and the
// run-time-against-error plot. Nothing in a report is left unescaped: names come from files.
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::engine::report {

using Json = nlohmann::ordered_json;  // keys in insertion order

// Text inside HTML or SVG elements and attribute values.
std::string escapeXml(const std::string& s);
// A relative path as a URL path: bytes other than unreserved characters and '/' percent-encoded,
// then escaped for HTML.
std::string urlAttr(const std::string& path);
// A CSV field (RFC 4180): quoted when it holds a comma, a double quote, CR or LF.
std::string csvField(const std::string& s);
// The shortest decimal form that reads back to the same double; "nan", "inf", "-inf".
std::string number(double v);
// A number for JSON: itself, or null when not finite (JSON has no NaN).
Json jsonNumber(double v);
// One line of JSON; invalid UTF-8 (a name read from a file) becomes U+FFFD, never an exception.
std::string jsonLine(const Json& j);
// Indented JSON, one value per line, for results files.
std::string jsonFile(const Json& j);

// Table cells: milliseconds with about three significant digits, errors with four decimals, a
// fraction as a percentage.
std::string fmtMs(double ms);
std::string fmtErr(double e);
std::string fmtPercent(double f);
// A signed error with its sign always shown ("+0.0123", "-0.0040").
std::string fmtBias(double e);

// Per point (x, y), both smaller-is-better: true when no other point is at least as good in both
// and strictly better in one (equal points are optimal together). A non-finite point is never
// optimal and dominates nothing.
std::vector<bool> paretoFront(const std::vector<std::pair<double, double>>& points);

// The run-time-against-error plot of one scene: x (time, > 0) on a log scale, y (error, >= 0) on a
// log scale when it spans a decade or more, else linear from 0; the Pareto front joined by a
// dashed line; one color and marker shape per series, the same in every plot given the same
// `seriesOrder`; a legend.
struct PlotPoint {
  double x = 0, y = 0;
  std::string series;   // e.g. the technique or the bounding method
  std::string label;    // e.g. "pcss kernel=7"
  bool faded = false;   // drawn lighter (a variant shown for comparison)
};
struct PlotSpec {
  std::string title;                     // the SVG's <title> and heading
  std::string xLabel, yLabel;            // axis captions; ", log scale" is added where it applies
  std::vector<std::string> seriesOrder;  // styles by position; series not listed follow
  bool labelAll = false;                 // label every point (else the Pareto front only)
  std::string note;                      // a line under the plot ("" for none)
};
std::string paretoSvg(const PlotSpec& spec, const std::vector<PlotPoint>& points);

// A static HTML page (inline CSS, no script, no external resource) around `body`.
std::string htmlPage(const std::string& title, const std::string& body);
// A linked thumbnail of an image file (relative path).
std::string thumb(const std::string& file, const std::string& alt);

}  // namespace penumbra::engine::report
