#include "tools/fit/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ambdrop {
namespace {

constexpr double kWidth = 800, kHeight = 420;
constexpr double kLeft = 90, kRight = 20, kTop = 40, kBottom = 60;

std::string Escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

// Ticks at 1, 2 or 5 times a power of ten, about five of them.
std::vector<double> Ticks(double lo, double hi) {
  const double span = hi - lo;
  if (!(span > 0)) return {lo};
  const double raw = span / 5.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * power;
    if (step >= raw) break;
  }
  std::vector<double> t;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) t.push_back(v);
  return t;
}

}  // namespace

std::string PlotSvg(const Plot& plot) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const PlotSeries& s : plot.series) {
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) {
    const double pad = std::max(std::abs(y0) * 0.1, 1e-12);
    y0 -= pad;
    y1 += pad;
  }
  const double w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;
  if (plot.equal_axes) {
    // The larger span sets the scale of both axes.
    const double span = std::max((x1 - x0) / w, (y1 - y0) / h);
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    x0 = cx - 0.5 * span * w, x1 = cx + 0.5 * span * w;
    y0 = cy - 0.5 * span * h, y1 = cy + 0.5 * span * h;
  } else {
    const double pad = 0.05 * (y1 - y0);
    y0 -= pad;
    y1 += pad;
  }
  const auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * w; };
  const auto py = [&](double y) { return kTop + (1.0 - (y - y0) / (y1 - y0)) * h; };

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
      "fill=\"white\"/>\n<text x=\"{}\" y=\"22\" font-size=\"15\">{}</text>\n",
      kWidth, kHeight, kLeft, Escape(plot.title));
  svg += fmt::format(
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" "
      "stroke=\"#888\"/>\n",
      kLeft, kTop, w, h);
  for (const double t : Ticks(x0, x1)) {
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#eee\"/>"
        "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4:.4g}</text>\n",
        px(t), kTop, kTop + h, kTop + h + 16, t);
  }
  for (const double t : Ticks(y0, y1)) {
    svg += fmt::format(
        "<line x1=\"{1}\" y1=\"{0:.1f}\" x2=\"{2}\" y2=\"{0:.1f}\" stroke=\"#eee\"/>"
        "<text x=\"{3}\" y=\"{0:.1f}\" text-anchor=\"end\" "
        "dominant-baseline=\"middle\">{4:.4g}</text>\n",
        py(t), kLeft, kLeft + w, kLeft - 6, t);
  }
  svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", kLeft + w / 2,
                     kHeight - 18, Escape(plot.x_label));
  svg += fmt::format(
      "<text x=\"16\" y=\"{0}\" text-anchor=\"middle\" "
      "transform=\"rotate(-90 16 {0})\">{1}</text>\n",
      kTop + h / 2, Escape(plot.y_label));
  double legend_x = kLeft + 10;
  for (const PlotSeries& s : plot.series) {
    // Thin long series: every k-th point, plus each stretch's extremes (peaks stay visible).
    const std::size_t n = std::min(s.x.size(), s.y.size());
    const std::size_t k = std::max<std::size_t>(1, n / 2000);
    std::string path;
    bool pen_down = false;
    for (std::size_t i = 0; i < n; i += k) {
      std::size_t lo = i, hi = i;
      for (std::size_t j = i; j < std::min(n, i + k); ++j) {
        if (!std::isfinite(s.y[j])) continue;
        if (!std::isfinite(s.y[lo]) || s.y[j] < s.y[lo]) lo = j;
        if (!std::isfinite(s.y[hi]) || s.y[j] > s.y[hi]) hi = j;
      }
      for (const std::size_t j : {std::min(lo, hi), std::max(lo, hi)}) {
        if (!std::isfinite(s.x[j]) || !std::isfinite(s.y[j])) {
          pen_down = false;
          continue;
        }
        path += fmt::format("{}{:.1f},{:.1f} ", pen_down ? "L" : "M", px(s.x[j]), py(s.y[j]));
        pen_down = true;
      }
    }
    svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.2\"/>\n", path,
                       s.colour);
    svg += fmt::format(
        "<rect x=\"{:.0f}\" y=\"{}\" width=\"14\" height=\"3\" fill=\"{}\"/>"
        "<text x=\"{:.0f}\" y=\"{}\">{}</text>\n",
        legend_x, kTop + 10, s.colour, legend_x + 18, kTop + 15, Escape(s.label));
    legend_x += 30 + 7.0 * static_cast<double>(s.label.size());
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace ambdrop
