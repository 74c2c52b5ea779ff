#include "f2c/report/svg_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "f2c/util/file.h"

namespace f2c {

std::string EscapeXml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
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

std::vector<double> LinearTicks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(std::isfinite(lo) && std::isfinite(hi)) || hi < lo) return ticks;
  if (hi == lo) return {lo};
  const double raw = (hi - lo) / std::max(1, target - 1);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * power;
    if (step >= raw) break;
  }
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (double t = first; t <= hi + step * 1e-9; t += step) ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  return ticks;
}

std::vector<double> LogTicks(double lo, double hi) {
  std::vector<double> ticks;
  if (!(lo > 0 && hi >= lo && std::isfinite(hi))) return ticks;
  const int a = static_cast<int>(std::floor(std::log10(lo) + 1e-9)),
            b = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
  for (int e = a; e <= b; ++e) {
    const double t = std::pow(10.0, e);
    if (t >= lo * (1 - 1e-9) && t <= hi * (1 + 1e-9)) ticks.push_back(t);
  }
  if (ticks.size() < 3) {
    ticks.clear();
    for (int e = a; e <= b; ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double t = m * std::pow(10.0, e);
        if (t >= lo * (1 - 1e-9) && t <= hi * (1 + 1e-9)) ticks.push_back(t);
      }
    }
  }
  return ticks;
}

namespace {

std::string Number(double v) {
  if (v == 0) return "0";
  const double a = std::abs(v);
  if (a >= 1e5 || a < 1e-3) return fmt::format("{:.0e}", v);
  std::string s = fmt::format("{:.4g}", v);
  return s;
}

bool Usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

// Data range of one axis over every series, with the axis' own bounds taking precedence.
void Range(const Plot& plot, bool x_axis, double* lo, double* hi) {
  const PlotAxis& axis = x_axis ? plot.x : plot.y;
  *lo = std::numeric_limits<double>::infinity(), *hi = -*lo;
  for (const PlotSeries& s : plot.series) {
    const std::vector<double>& v = x_axis ? s.x : s.y;
    const std::vector<double>& other = x_axis ? s.y : s.x;
    const bool other_log = x_axis ? plot.y.log : plot.x.log;
    for (size_t i = 0; i < v.size() && i < other.size(); ++i) {
      if (!Usable(v[i], axis.log) || !Usable(other[i], other_log)) continue;
      *lo = std::min(*lo, v[i]), *hi = std::max(*hi, v[i]);
    }
    if (!x_axis && s.style == PlotSeries::Style::kBars && !axis.log) *lo = std::min(*lo, 0.0);
  }
  if (!std::isfinite(*lo)) return;
  if (axis.log) {
    if (*hi == *lo) *lo /= 2, *hi *= 2;
    const double margin = std::pow(*hi / *lo, 0.04);  // 4% of the decades shown, each side
    *lo /= margin, *hi *= margin;
  } else {
    const double margin = *hi > *lo ? 0.04 * (*hi - *lo) : (*lo != 0 ? 0.1 * std::abs(*lo) : 1.0);
    const bool bars_from_zero = !x_axis && *lo == 0;
    if (!bars_from_zero) *lo -= margin;
    *hi += margin;
  }
  if (axis.min) *lo = *axis.min;
  if (axis.max) *hi = *axis.max;
}

}  // namespace

const char* SeriesColor(int i) {
  static const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                  "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  return kColors[((i % 8) + 8) % 8];
}

std::string RenderSvg(const Plot& plot) {
  const double left = 64, right = 16, top = plot.title.empty() ? 16 : 34, bottom = 46;
  const double w = plot.width - left - right, h = plot.height - top - bottom;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      plot.width, plot.height, plot.width, plot.height);
  if (!plot.title.empty()) {
    svg +=
        fmt::format("<text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\" font-weight=\"bold\">{}</text>\n",
                    plot.width / 2, EscapeXml(plot.title));
  }
  double x0, x1, y0, y1;
  Range(plot, true, &x0, &x1);
  Range(plot, false, &y0, &y1);
  svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\n", left, top,
                     w, h);
  if (!std::isfinite(x0) || !std::isfinite(y0)) {
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#888\">no data</text>\n</svg>\n",
                       left + w / 2, top + h / 2);
    return svg;
  }
  if (plot.equal_aspect && !plot.x.log && !plot.y.log) {
    // Grow the narrower range about its centre so that a unit spans the same pixels.
    const double sx = (x1 - x0) / w, sy = (y1 - y0) / h, s = std::max(sx, sy);
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    x0 = cx - 0.5 * s * w, x1 = cx + 0.5 * s * w, y0 = cy - 0.5 * s * h, y1 = cy + 0.5 * s * h;
  }
  auto map = [](double v, double lo, double hi, bool log) {
    return log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
  };
  auto px = [&](double v) { return left + w * map(v, x0, x1, plot.x.log); };
  auto py = [&](double v) { return top + h * (1 - map(v, y0, y1, plot.y.log)); };

  // Grid, ticks and labels.
  const std::vector<double> xt =
      plot.x.log ? LogTicks(x0, x1) : LinearTicks(x0, x1, std::max(3, static_cast<int>(w / 90)));
  const std::vector<double> yt =
      plot.y.log ? LogTicks(y0, y1) : LinearTicks(y0, y1, std::max(3, static_cast<int>(h / 60)));
  for (double t : xt) {
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#e4e4e4\"/>"
        "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4}</text>\n",
        px(t), top, top + h, top + h + 16, Number(t));
  }
  for (double t : yt) {
    svg += fmt::format(
        "<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#e4e4e4\"/>"
        "<text x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">{5}</text>\n",
        left, py(t), left + w, left - 6, py(t) + 4, Number(t));
  }
  svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", left + w / 2, plot.height - 8,
                     EscapeXml(plot.x.label));
  svg += fmt::format("<text transform=\"translate(14,{}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n", top + h / 2,
                     EscapeXml(plot.y.label));

  // Series, clipped to the frame. The clip's id comes from the plot's content, so that the
  // same plot gives the same bytes and plots on one page do not share an id.
  std::string identity = plot.title + "|" + plot.x.label + "|" + plot.y.label;
  for (const PlotSeries& s : plot.series) identity += "|" + s.name + fmt::format(":{}", s.x.size());
  const std::string clip_id = "clip" + HexString(Fnv1a64(identity));
  svg += fmt::format(
      "<clipPath id=\"{0}\"><rect x=\"{1}\" y=\"{2}\" width=\"{3}\" height=\"{4}\"/></clipPath>\n"
      "<g clip-path=\"url(#{0})\">\n",
      clip_id, left, top, w, h);
  for (const PlotSeries& s : plot.series) {
    const size_t n = std::min(s.x.size(), s.y.size());
    auto ok = [&](size_t i) { return Usable(s.x[i], plot.x.log) && Usable(s.y[i], plot.y.log); };
    if (s.style == PlotSeries::Style::kLine) {
      std::string d;
      bool pen_down = false;
      for (size_t i = 0; i < n; ++i) {
        if (!ok(i)) {
          pen_down = false;
          continue;
        }
        d += fmt::format("{}{:.1f},{:.1f}", pen_down ? "L" : "M", px(s.x[i]), py(s.y[i]));
        pen_down = true;
      }
      if (!d.empty()) {
        svg +=
            fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\"/>\n",
                        d, s.color, s.width);
      }
    } else if (s.style == PlotSeries::Style::kPoints) {
      for (size_t i = 0; i < n; ++i) {
        if (ok(i)) {
          svg += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"{}\" fill=\"{}\"/>", px(s.x[i]), py(s.y[i]),
                             s.width, s.color);
        }
      }
      svg += "\n";
    } else if (s.style == PlotSeries::Style::kDots) {
      std::string d;
      for (size_t i = 0; i < n; ++i) {
        if (ok(i))
          d += fmt::format("M{:.1f} {:.1f}h{}v{}h-{}z", px(s.x[i]) - s.width / 2, py(s.y[i]) - s.width / 2, s.width,
                           s.width, s.width);
      }
      if (!d.empty()) svg += fmt::format("<path d=\"{}\" fill=\"{}\"/>\n", d, s.color);
    } else {
      // Bars centred on x, as wide as the smallest gap between neighbouring x (90%).
      double gap = std::numeric_limits<double>::infinity();
      for (size_t i = 1; i < n; ++i) gap = std::min(gap, std::abs(px(s.x[i]) - px(s.x[i - 1])));
      const double bar = std::isfinite(gap) ? 0.9 * gap : 0.5 * w;
      const double base = plot.y.log ? y0 : std::clamp(0.0, y0, y1);
      for (size_t i = 0; i < n; ++i) {
        if (!ok(i)) continue;
        const double a = py(s.y[i]), b = py(base);
        svg += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\"/>",
                           px(s.x[i]) - bar / 2, std::min(a, b), bar, std::abs(b - a), s.color);
      }
      svg += "\n";
    }
  }
  svg += "</g>\n";

  // Legend, top right inside the frame.
  double ly = top + 8;
  for (const PlotSeries& s : plot.series) {
    if (s.name.empty()) continue;
    const double lx = left + w - 150;
    svg += fmt::format(
        "<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"4\" fill=\"{}\"/>"
        "<text x=\"{}\" y=\"{}\">{}</text>\n",
        lx, ly + 4, s.color, lx + 20, ly + 10, EscapeXml(s.name));
    ly += 16;
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace f2c
