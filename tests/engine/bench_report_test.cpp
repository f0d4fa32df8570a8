// The benchmark report: the Pareto front on hand-made sets, JSON and CSV round trips, plot file
// names, and the report directory (files present, JSON parsed back, SVG and HTML well formed and
// escaped, failures naming the file and leaving no temporary behind).
#include "engine/bench_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::vector<std::string> kKeys = {
    "scene",         "technique",     "params",        "ms_maps",        "ms_filter",      "ms_prepare",
    "ms_evaluate",   "ms_total",      "rmse_v",        "bias_v",         "max_err_v",      "frac_err_gt_005",
    "rmse_v_ground", "bias_v_ground", "rmse_v_object", "bias_v_object",  "rmse_v_contact", "bias_v_contact",
    "rmse_image",    "ms_maps_min",   "ms_maps_max",   "ms_evaluate_min", "ms_evaluate_max", "ms_total_min",
    "ms_total_max",  "ms_points",     "ms_splat"};

ShadowBenchRow row(const std::string& scene, const std::string& technique, const std::string& params,
                   double ms, double rmse) {
  ShadowBenchRow r;
  r.scene = scene;
  r.technique = technique;
  r.params = params;
  r.msMaps = ms * 0.5;
  r.msFilter = ms * 0.125;
  r.msPrepare = ms * 0.625;
  r.msEvaluate = ms * 0.375;
  r.msTotal = ms;
  r.rmseV = rmse;
  r.maxErrV = rmse * 4;
  r.fracErrGt005 = rmse;
  r.rmseImage = rmse / 3;
  r.biasV = -rmse / 5;
  r.rmseGround = rmse / 2, r.biasGround = rmse / 7;
  r.rmseObject = rmse * 2, r.biasObject = rmse / 9;
  r.rmseContact = rmse * 3, r.biasContact = -rmse / 11;
  return r;
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
  return n;
}

// Splits one CSV record per RFC 4180 (quoted fields, doubled quotes).
std::vector<std::string> parseCsv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// Checks that markup is well formed: tags balance (void elements excepted), attribute values are
// quoted, and text holds no raw '<' and only entity references after '&'. Returns "" or the problem.
std::string checkMarkup(const std::string& s, const std::set<std::string>& voidElements) {
  std::vector<std::string> open;
  size_t i = 0;
  auto entityAt = [&](size_t at) {
    const size_t semi = s.find(';', at);
    if (semi == std::string::npos || semi - at > 8) return false;
    for (size_t k = at + 1; k < semi; ++k)
      if (!std::isalnum(static_cast<unsigned char>(s[k])) && s[k] != '#') return false;
    return semi > at + 1;
  };
  while (i < s.size()) {
    if (s[i] == '&') {
      if (!entityAt(i)) return "bare '&' at " + std::to_string(i);
      ++i;
      continue;
    }
    if (s[i] == '>') return "bare '>' at " + std::to_string(i);
    if (s[i] != '<') {
      ++i;
      continue;
    }
    if (s.compare(i, 9, "<!DOCTYPE") == 0) {
      i = s.find('>', i) + 1;
      continue;
    }
    // A tag: scan to its '>' outside quoted attribute values.
    size_t j = i + 1;
    char quote = 0;
    for (; j < s.size() && (quote || s[j] != '>'); ++j) {
      if (quote && s[j] == quote)
        quote = 0;
      else if (!quote && (s[j] == '"' || s[j] == '\''))
        quote = s[j];
      else if (!quote && s[j] == '<')
        return "'<' inside a tag at " + std::to_string(j);
      else if (quote && (s[j] == '<' || (s[j] == '&' && !entityAt(j))))
        return "unescaped attribute at " + std::to_string(j);
    }
    if (j >= s.size()) return "unterminated tag at " + std::to_string(i);
    const std::string tag = s.substr(i + 1, j - i - 1);
    i = j + 1;
    if (tag.empty()) return "empty tag";
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name)
        return "</" + name + "> does not close <" + (open.empty() ? "" : open.back()) + ">";
      open.pop_back();
      continue;
    }
    const std::string name = tag.substr(0, tag.find_first_of(" \n/"));
    if (tag.back() == '/' || voidElements.count(name)) continue;
    open.push_back(name);
  }
  return open.empty() ? "" : "<" + open.back() + "> not closed";
}

TEST(BenchReport, ParetoFrontHandMade) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<ShadowBenchRow> rows = {
      row("s", "a", "", 10, 0.1),    // 0 front
      row("s", "b", "", 20, 0.05),   // 1 front
      row("s", "c", "", 20, 0.1),    // 2 dominated by 0 (slower, same error) and 1 (same time, worse)
      row("s", "d", "", 5, 0.3),     // 3 front: fastest
      row("s", "e", "", 10, 0.1),    // 4 front: ties row 0 exactly
      row("s", "f", "", 30, 0.05),   // 5 dominated by 1 (same error, slower)
      row("s", "g", "", -inf, 0.0),  // 6 not finite: off the front, and dominates nobody
      row("s", "h", "", 1, inf),     // 7 not finite
      row("s", "i", "", nan, 0.0),   // 8 not finite
      row("s", "j", "", 40, 0.01),   // 9 front: most accurate
      row("s", "k", "", 35, 0.2),    // 10 dominated by 1, 4, ...
  };
  const std::vector<bool> expected = {true, true, false, true, true, false, false, false, false, true, false};
  EXPECT_EQ(paretoFront(rows), expected);
  EXPECT_TRUE(paretoFront({}).empty());
  EXPECT_EQ(paretoFront({row("s", "x", "", 3, 0.5)}), std::vector<bool>{true});
}

TEST(BenchReport, JsonRoundTripsWithExactKeys) {
  ShadowBenchRow r = row("cornell \"box\"", "pcss", "kernel=7,blocker=16", 1.0 / 3, 0.1 + 0.2);
  r.msMaps = 1e-300;
  r.maxErrV = 123456789.123456789;
  r.views = 4;
  r.image = "img.png";
  r.msMapsMin = 0.25, r.msMapsMax = 1.0 / 7, r.msEvaluateMin = 2.5, r.msEvaluateMax = 3.5;
  r.msTotalMin = 1e-9, r.msTotalMax = 1e9, r.msPoints = 0.125, r.msSplat = 1.0 / 9;
  const std::string text = toJson(r);
  EXPECT_EQ(text.find('\n'), std::string::npos);
  const Json j = Json::parse(text);
  std::vector<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys, kKeys);
  EXPECT_EQ(j["scene"], r.scene);
  EXPECT_EQ(j["technique"], "pcss");
  EXPECT_EQ(j["params"], r.params);
  const double values[] = {r.msMaps,      r.msFilter,   r.msPrepare,   r.msEvaluate,  r.msTotal,     r.rmseV,
                           r.biasV,       r.maxErrV,    r.fracErrGt005, r.rmseGround, r.biasGround, r.rmseObject,
                           r.biasObject,  r.rmseContact, r.biasContact, r.rmseImage,  r.msMapsMin,  r.msMapsMax,
                           r.msEvaluateMin, r.msEvaluateMax, r.msTotalMin, r.msTotalMax, r.msPoints, r.msSplat};
  ASSERT_EQ(std::size(values) + 3, kKeys.size());
  for (size_t k = 0; k < std::size(values); ++k) {
    ASSERT_TRUE(j[kKeys[3 + k]].is_number()) << kKeys[3 + k];
    EXPECT_EQ(j[kKeys[3 + k]].get<double>(), values[k]) << kKeys[3 + k];  // bit-exact round trip
  }

  r.rmseV = std::numeric_limits<double>::quiet_NaN();
  r.msTotal = std::numeric_limits<double>::infinity();
  const Json n = Json::parse(toJson(r));
  EXPECT_TRUE(n["rmse_v"].is_null());
  EXPECT_TRUE(n["ms_total"].is_null());
}

TEST(BenchReport, CsvQuotingAndColumns) {
  EXPECT_EQ(parseCsv(csvHeader()), kKeys);
  ShadowBenchRow r = row("plain", "we\"ird", "kernel=7,blocker=16", 0.1, 1.0 / 7);
  const std::string line = toCsv(r);
  EXPECT_EQ(line.rfind("plain,\"we\"\"ird\",\"kernel=7,blocker=16\",", 0), 0u) << line;
  const std::vector<std::string> f = parseCsv(line);
  ASSERT_EQ(f.size(), kKeys.size());
  EXPECT_EQ(f[0], "plain");
  EXPECT_EQ(f[1], "we\"ird");
  EXPECT_EQ(f[2], "kernel=7,blocker=16");
  EXPECT_EQ(std::strtod(f[3].c_str(), nullptr), r.msMaps);
  EXPECT_EQ(std::strtod(f[7].c_str(), nullptr), r.msTotal);
  EXPECT_EQ(std::strtod(f[8].c_str(), nullptr), r.rmseV);  // shortest round-trip form
  EXPECT_EQ(f[8], "0.14285714285714285");

  r.params = "line\nbreak";
  r.rmseImage = -std::numeric_limits<double>::infinity();
  const std::vector<std::string> g = parseCsv(toCsv(r));
  EXPECT_EQ(g[2], "line\nbreak");
  EXPECT_EQ(g[18], "-inf");
  EXPECT_EQ(parseCsv(toCsv(row("s", "t", "", 1, 2)))[2], "");
}

TEST(BenchReport, PlotFileNames) {
  std::vector<ShadowBenchScene> scenes(5);
  scenes[0].name = "cornell";
  scenes[1].name = "a<b&c";
  scenes[2].name = "a_b_c";
  scenes[3].name = "";
  scenes[4].name = "../x y";
  const std::vector<std::string> expected = {"pareto-cornell.svg", "pareto-a_b_c.svg", "pareto-a_b_c-2.svg",
                                             "pareto-scene.svg", "pareto-.._x_y.svg"};
  EXPECT_EQ(paretoPlotFileNames(scenes), expected);
}

class BenchReportDir : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("penumbra-bench-report-" + std::to_string(::getpid()) + "-" +
                                         testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  std::vector<std::string> listing(const fs::path& d) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path root_;
};

TEST_F(BenchReportDir, WritesAllFiles) {
  std::vector<ShadowBenchScene> scenes(2);
  scenes[0].name = "a<b&c";
  scenes[0].description = "Tricky <script>alert('x')</script> & \"quotes\"";
  scenes[0].referenceImage = "ref/a b.png";
  scenes[0].referenceNote = "ray traced, 256 samples";
  scenes[0].width = 64;
  scenes[0].height = 48;
  scenes[1].name = "plain";
  std::vector<ShadowBenchRow> rows = {
      row("a<b&c", "hard", "", 2.0, 0.2),                      // front
      row("plain", "pcss", "kernel=7,blocker=16", 2.0, 0.01),  // front: fastest in its scene
      row("a<b&c", "pcss", "kernel=7,blocker=16", 8.0, 0.05),  // front
      row("a<b&c", "pcf", "size=3", 10.0, 0.1),                // dominated by pcss
      row("plain", "hard", "", 3.0, 0.0),                      // front, rmse 0: linear y axis
  };
  rows[0].image = "img/hard.png";
  rows[0].heatMap = "img/hard-heat.png";
  rows[0].views = 1;
  const fs::path dir = root_ / "nested" / "report";
  const Status st = writeShadowReport(dir.string(), scenes, rows, "Shadows <bench>", "machine & 'cores'");
  ASSERT_TRUE(st.ok()) << st.error().line();
  EXPECT_EQ(listing(dir), (std::vector<std::string>{"index.html", "pareto-a_b_c.svg", "pareto-plain.svg",
                                                    "results.csv", "results.json"}));

  // JSON: header fields, scenes, and every row as toJson writes it.
  const Json j = Json::parse(readFile(dir / "results.json"));
  EXPECT_EQ(j["title"], "Shadows <bench>");
  EXPECT_EQ(j["machine"], "machine & 'cores'");
  ASSERT_EQ(j["scenes"].size(), 2u);
  EXPECT_EQ(j["scenes"][0]["name"], "a<b&c");
  EXPECT_EQ(j["scenes"][0]["reference_image"], "ref/a b.png");
  EXPECT_EQ(j["scenes"][0]["width"], 64);
  ASSERT_EQ(j["rows"].size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(j["rows"][i], Json::parse(toJson(rows[i]))) << i;

  // CSV: the header and one line per row.
  std::istringstream csv(readFile(dir / "results.csv"));
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), rows.size() + 1);
  EXPECT_EQ(lines[0], csvHeader());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(lines[i + 1], toCsv(rows[i]));

  // SVG: well formed, one marker per row of its scene, the front labelled, names escaped.
  const std::string svg = readFile(dir / "pareto-a_b_c.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(checkMarkup(svg, {}), "");
  EXPECT_EQ(count(svg, "class=\"marker\""), 3u);
  EXPECT_EQ(count(svg, "class=\"key\""), 3u);  // legend: hard, pcss, pcf
  EXPECT_NE(svg.find("a&lt;b&amp;c"), std::string::npos);
  EXPECT_EQ(svg.find("a<b"), std::string::npos);
  EXPECT_NE(svg.find(">pcss kernel=7,blocker=16</text>"), std::string::npos);  // front label
  EXPECT_NE(svg.find(">hard</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">pcf size=3</text>"), std::string::npos);  // dominated: not labelled
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(svg.find("ms, log scale"), std::string::npos);
  EXPECT_NE(svg.find(">10</text>"), std::string::npos);  // a tick between 2 and 10 ms
  const std::string svg2 = readFile(dir / "pareto-plain.svg");
  EXPECT_EQ(svg2.rfind("<svg", 0), 0u);
  EXPECT_EQ(checkMarkup(svg2, {}), "");
  EXPECT_EQ(count(svg2, "class=\"marker\""), 2u);
  EXPECT_NE(svg2.find(">0</text>"), std::string::npos);  // linear error axis from 0

  // HTML: well formed, escaped, the front highlighted, images and plots referenced.
  const std::string html = readFile(dir / "index.html");
  EXPECT_EQ(checkMarkup(html, {"meta", "img", "br"}), "");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("a<b"), std::string::npos);
  EXPECT_NE(html.find("<h2>a&lt;b&amp;c</h2>"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)"), std::string::npos);
  EXPECT_NE(html.find("<title>Shadows &lt;bench&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("machine &amp; &#39;cores&#39;"), std::string::npos);
  EXPECT_EQ(count(html, "<tr class=\"pareto\">"), 4u);
  EXPECT_EQ(count(html, "<tr"), rows.size() + scenes.size());  // a header row per scene, one per row
  EXPECT_NE(html.find("src=\"pareto-a_b_c.svg\""), std::string::npos);
  EXPECT_NE(html.find("src=\"pareto-plain.svg\""), std::string::npos);
  EXPECT_NE(html.find("href=\"img/hard-heat.png\""), std::string::npos);
  EXPECT_NE(html.find("src=\"ref/a%20b.png\""), std::string::npos);
  EXPECT_NE(html.find("ray traced, 256 samples"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);  // no external resource
}

TEST_F(BenchReportDir, RejectsInconsistentInput) {
  std::vector<ShadowBenchScene> scenes(1);
  scenes[0].name = "one";
  const fs::path dir = root_ / "out";
  const Status unknown = writeShadowReport(dir.string(), scenes, {row("two", "hard", "", 1, 0.1)}, "t", "m");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().what.find("'two'"), std::string::npos) << unknown.error().line();
  scenes.push_back(scenes[0]);
  const Status dup = writeShadowReport(dir.string(), scenes, {}, "t", "m");
  ASSERT_FALSE(dup.ok());
  EXPECT_NE(dup.error().what.find("'one'"), std::string::npos) << dup.error().line();
  EXPECT_FALSE(fs::exists(dir));  // nothing written
}

TEST_F(BenchReportDir, FailureNamesTheFileAndLeavesNoTemporary) {
  std::vector<ShadowBenchScene> scenes(1);
  scenes[0].name = "one";
  const std::vector<ShadowBenchRow> rows = {row("one", "hard", "", 1, 0.1)};

  // The directory is a regular file.
  const fs::path file = root_ / "file";
  std::ofstream(file) << "x";
  const Status notDir = writeShadowReport(file.string(), scenes, rows, "t", "m");
  ASSERT_FALSE(notDir.ok());
  EXPECT_EQ(notDir.error().where, file.string());

  // results.csv cannot be replaced (a directory is in the way): the error names it, results.json
  // was written, nothing else was, and no temporary is left.
  const fs::path dir = root_ / "out";
  fs::create_directories(dir / "results.csv");
  const Status blocked = writeShadowReport(dir.string(), scenes, rows, "t", "m");
  ASSERT_FALSE(blocked.ok());
  EXPECT_EQ(blocked.error().where, (dir / "results.csv").string());
  EXPECT_EQ(listing(dir), (std::vector<std::string>{"results.csv", "results.json"}));
  EXPECT_TRUE(fs::is_directory(dir / "results.csv"));
}

}  // namespace
}  // namespace penumbra::engine
