#pragma once
// Plots as inline SVG, drawn by the program itself (no Python, no network at run time): line,
// point and bar series on linear or logarithmic axes with ticks, grid, labels and a legend.
// For report.html (report.h); general enough for any x-y data.

#include <optional>
#include <string>
#include <vector>

namespace f2c {

struct PlotSeries {
  // kDots: a square of side `width` per point, all in one <path>: about a third of the bytes
  // of kPoints' circles, for thousands of points (maps, slices).
  enum class Style { kLine, kPoints, kBars, kDots };
  std::string name;  // in the legend; empty: not listed
  std::vector<double> x,
      y;  // same length; a NaN or infinite value (or <= 0 on a log axis) breaks a line and is skipped
  std::string color = "#1f77b4";
  Style style = Style::kLine;
  double width = 1.5;  // line width or point radius (pixels)
};

struct PlotAxis {
  std::string label;
  bool log = false;                // base 10
  std::optional<double> min, max;  // default: the data's range (with a margin)
};

struct Plot {
  std::string title;
  PlotAxis x, y;
  std::vector<PlotSeries> series;
  int width = 640, height = 400;  // pixels
  bool equal_aspect = false;      // one unit is as long on both axes (maps, trajectories)
};

// The plot as an <svg> element (UTF-8 text, valid XML). An empty plot (no finite data) says
// so in the middle of its frame.
std::string RenderSvg(const Plot& plot);

// Tick positions: "nice" steps (1, 2 or 5 times a power of ten) covering [lo, hi] with about
// `target` ticks; on a log axis the powers of ten in [lo, hi] (and 2x, 5x when fewer than 3).
std::vector<double> LinearTicks(double lo, double hi, int target = 6);
std::vector<double> LogTicks(double lo, double hi);

// The i-th colour of the plots' palette (8 colours, repeating): the series of one plot, the
// estimates of one report.
const char* SeriesColor(int i);

// Text safe inside XML/HTML (& < > " ').
std::string EscapeXml(const std::string& text);

}  // namespace f2c
