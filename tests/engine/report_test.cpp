// The shared report pieces: escaping, numbers, one-line JSON, the Pareto front and the plot
// (styles by series, labels, faded points, everything escaped).
#include "engine/report.h"

#include <gtest/gtest.h>

namespace penumbra::engine::report {
namespace {

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(Report, EscapesAndNumbers) {
  EXPECT_EQ(escapeXml("a<b & 'c' \"d\">"), "a&lt;b &amp; &#39;c&#39; &quot;d&quot;&gt;");
  EXPECT_EQ(urlAttr("dir/a b#?.png"), "dir/a%20b%23%3F.png");
  EXPECT_EQ(csvField("x,y"), "\"x,y\"");
  EXPECT_EQ(csvField("plain"), "plain");
  EXPECT_EQ(number(0.1), "0.1");
  EXPECT_EQ(number(-INFINITY), "-inf");
  EXPECT_EQ(jsonLine(Json{{"a", jsonNumber(NAN)}, {"b", "\xff"}}), "{\"a\":null,\"b\":\"\xef\xbf\xbd\"}");
}

TEST(Report, ParetoFrontOfPoints) {
  EXPECT_EQ(paretoFront({{1, 3}, {2, 2}, {3, 3}, {2, 2}, {NAN, 0}}),
            (std::vector<bool>{true, true, false, true, false}));
}

TEST(Report, PlotStylesLabelsAndEscaping) {
  PlotSpec spec;
  spec.title = "<scene>";
  spec.xLabel = "time (ms)";
  spec.yLabel = "error";
  spec.seriesOrder = {"b", "a"};
  std::vector<PlotPoint> pts = {{10, 0.1, "a", "a <1>", false}, {20, 0.05, "b", "b 2", true}, {30, 0.2, "a", "a 3", false}};
  const std::string svg = paretoSvg(spec, pts);
  EXPECT_EQ(count(svg, "class=\"marker\""), 3u);
  EXPECT_EQ(count(svg, "class=\"key\""), 2u);
  EXPECT_EQ(count(svg, "fill-opacity=\"0.35\""), 1u);
  EXPECT_NE(svg.find("&lt;scene&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<scene>"), std::string::npos);
  EXPECT_NE(svg.find(">a &lt;1&gt;</text>"), std::string::npos);  // on the front: labelled
  EXPECT_EQ(svg.find(">a 3</text>"), std::string::npos);          // dominated: not labelled
  EXPECT_NE(svg.find("time (ms, log scale)"), std::string::npos);
  // Series "b" is first in seriesOrder: the first palette color, whatever the point order.
  EXPECT_NE(svg.find("fill=\"#4e79a7\" stroke=\"#000000\" stroke-width=\"1.5\" fill-opacity"), std::string::npos);
  spec.labelAll = true;
  EXPECT_NE(paretoSvg(spec, pts).find(">a 3</text>"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::engine::report
