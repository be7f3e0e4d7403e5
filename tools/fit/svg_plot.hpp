#pragma once
// A small SVG line plot: a few named series on linear axes, enough for a fit report to show
// what a person wants to see at a glance.
#include <string>
#include <vector>

namespace ambdrop {

struct PlotSeries {
  std::string label;
  std::string colour;  ///< an SVG colour
  std::vector<double> x;
  std::vector<double> y;  ///< NaN breaks the line
};

struct Plot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
  bool equal_axes = false;  ///< orbits: one unit is as long on both axes
};

/// The SVG document. Series longer than ~2000 points are thinned (min and max per pixel column
/// kept, so that peaks stay visible).
std::string PlotSvg(const Plot& plot);

}  // namespace ambdrop
