#include "f2c/report/svg_plot.h"

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <limits>

namespace f2c {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Parses as XML, with an <svg> root; the number of elements named `name` anywhere in it.
int Count(const std::string& svg, const char* name) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.Parse(svg.c_str()), tinyxml2::XML_SUCCESS) << svg;
  if (doc.Error() || !doc.RootElement()) return -1;
  EXPECT_STREQ(doc.RootElement()->Name(), "svg");
  int n = 0;
  std::vector<const tinyxml2::XMLElement*> stack{doc.RootElement()};
  while (!stack.empty()) {
    const tinyxml2::XMLElement* e = stack.back();
    stack.pop_back();
    n += std::string(e->Name()) == name;
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) stack.push_back(c);
  }
  return n;
}

TEST(LinearTicks, NiceStepsCoveringTheRange) {
  EXPECT_EQ(LinearTicks(0, 1, 6), (std::vector<double>{0, 0.2, 0.4, 0.6000000000000001, 0.8, 1}));
  EXPECT_EQ(LinearTicks(-3, 7, 6), (std::vector<double>{-2, 0, 2, 4, 6}));
  EXPECT_EQ(LinearTicks(0.013, 0.027, 4), (std::vector<double>{0.015, 0.02, 0.025}));
  EXPECT_EQ(LinearTicks(5, 5, 6), (std::vector<double>{5}));
  EXPECT_TRUE(LinearTicks(kNaN, 1).empty());
}

TEST(LogTicks, PowersOfTenOrOneTwoFive) {
  EXPECT_EQ(LogTicks(1, 1000), (std::vector<double>{1, 10, 100, 1000}));
  EXPECT_EQ(LogTicks(3, 30), (std::vector<double>{5, 10, 20}));
  EXPECT_TRUE(LogTicks(0, 10).empty());
}

TEST(RenderSvg, ValidXmlWithAxesSeriesAndLegend) {
  Plot p;
  p.title = "errors <m> & \"gaps\"";
  p.x.label = "frame gap";
  p.x.log = true;
  p.y.label = "error (m)";
  p.series.push_back({"T0", {1, 2, 4, 8}, {0.01, 0.02, 0.03, 0.05}, "#d62728"});
  p.series.push_back({"final", {1, 2, 4, 8}, {0.005, 0.007, 0.008, 0.01}, "#2ca02c", PlotSeries::Style::kPoints, 3});
  const std::string svg = RenderSvg(p);
  EXPECT_EQ(Count(svg, "path"), 1);    // the line series
  EXPECT_EQ(Count(svg, "circle"), 4);  // the point series
  EXPECT_NE(svg.find("errors &lt;m&gt; &amp; &quot;gaps&quot;"), std::string::npos);
  EXPECT_NE(svg.find(">T0</text>"), std::string::npos);
  // One decade (1) in 1..8: ticks at 1, 2 and 5 instead.
  EXPECT_NE(svg.find(">2</text>"), std::string::npos);
  EXPECT_NE(svg.find(">5</text>"), std::string::npos);
  EXPECT_EQ(svg, RenderSvg(p));  // the same bytes every time
}

TEST(RenderSvg, NaNBreaksALineAndEmptyPlotsSaySo) {
  Plot p;
  p.series.push_back({"a", {0, 1, 2, 3, 4}, {1, 2, kNaN, 3, 4}});
  const std::string svg = RenderSvg(p);
  const size_t d = svg.find(" d=\"");
  ASSERT_NE(d, std::string::npos);
  const std::string path = svg.substr(d, svg.find('"', d + 4) - d);
  EXPECT_EQ(std::count(path.begin(), path.end(), 'M'), 2);  // two pieces around the NaN
  EXPECT_EQ(std::count(path.begin(), path.end(), 'L'), 2);

  Plot empty;
  empty.series.push_back({"nothing", {kNaN}, {1}});
  const std::string none = RenderSvg(empty);
  EXPECT_NE(none.find(">no data</text>"), std::string::npos);
  EXPECT_EQ(Count(none, "path"), 0);

  Plot one;
  one.series.push_back({"", {2}, {3}, "#000", PlotSeries::Style::kPoints});
  EXPECT_EQ(Count(RenderSvg(one), "circle"), 1);
  // On a log axis, values <= 0 are skipped.
  Plot log;
  log.y.log = true;
  log.series.push_back({"", {1, 2, 3}, {0, 10, 100}, "#000", PlotSeries::Style::kBars});
  EXPECT_EQ(Count(RenderSvg(log), "rect"), 2 + 1 + 2);  // background, frame, clip + 2 bars
}

TEST(RenderSvg, DotsAreOneSquarePerPointInOnePath) {
  Plot p;
  p.x.min = 0, p.x.max = 10, p.y.min = 0, p.y.max = 10;
  p.width = 300, p.height = 300;
  p.series.push_back({"", {1, 5, kNaN, 9}, {1, 5, 2, 9}, "#123456", PlotSeries::Style::kDots, 2});
  const std::string svg = RenderSvg(p);
  EXPECT_EQ(Count(svg, "path"), 1);
  const size_t at = svg.find("fill=\"#123456\"");
  ASSERT_NE(at, std::string::npos);
  const size_t d = svg.rfind(" d=\"", at);
  const std::string path = svg.substr(d + 4, svg.find('"', d + 4) - d - 4);
  EXPECT_EQ(std::count(path.begin(), path.end(), 'M'), 3);  // the NaN point skipped
  EXPECT_EQ(std::count(path.begin(), path.end(), 'z'), 3);
  EXPECT_NE(path.find("h2v2h-2z"), std::string::npos);
}

}  // namespace
}  // namespace f2c
