#pragma once
// Simple line plots as SVG (time series, tracks): axes with "nice" ticks, labelled series, shaded
// x bands (e.g. where obstacles lie), a legend. Deterministic output (fixed number formatting).
//
//   viz::LinePlot plot({.title = "Height", .x_label = "t [s]", .y_label = "z [m]"});
//   plot.add_series(points, {.colour = viz::categorical_colour(0)}, "z(t)");
//   plot.write_svg("height_trace.svg");
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/viz/colour.hpp"

namespace starnav::viz {

struct PlotOptions {
  std::string title{};
  std::string x_label{};
  std::string y_label{};
  int width_px = 900;
  int height_px = 420;
  double font_px = 12.0;
  // Fixed axis ranges; automatic (data plus a margin, widened to whole ticks) when absent.
  std::optional<std::pair<double, double>> x_range{};
  std::optional<std::pair<double, double>> y_range{};
  // Same metres per pixel on both axes (for XY tracks); the plot's height follows its width.
  bool equal_aspect = false;
};

struct SeriesStyle {
  Rgba colour{0, 114, 178, 255};
  double width_px = 1.8;
  bool dashed = false;
  bool markers = false;  // a small dot at every point (no line when width_px is 0)
};

class LinePlot {
 public:
  explicit LinePlot(PlotOptions options = {});
  // Non-finite points are skipped (they break the line).
  void add_series(std::vector<Vec2> points, const SeriesStyle& style = {}, std::string label = {});
  // A shaded vertical band x0..x1 with a label at its top.
  void add_band(double x0, double x1, Rgba colour, std::string label = {});

  std::string svg_string() const;
  // Throws Error naming the file when it cannot be written.
  void write_svg(const std::string& path) const;

  // Tick positions covering [lo, hi] with a 1-2-5 step giving about `target` ticks.
  static std::vector<double> nice_ticks(double lo, double hi, int target = 6);

 private:
  struct Series {
    std::vector<Vec2> points;
    SeriesStyle style;
    std::string label;
  };
  struct Band {
    double x0, x1;
    Rgba colour;
    std::string label;
  };
  PlotOptions options_;
  std::vector<Series> series_;
  std::vector<Band> bands_;
};

}  // namespace starnav::viz
