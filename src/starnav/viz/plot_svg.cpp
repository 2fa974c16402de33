#include "starnav/viz/plot_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav::viz {

namespace {

std::string num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  if (s == "-0.00") s = "0.00";
  return s;
}

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

// A tick label: as few decimals as the step needs.
std::string tick_label(double v, double step) {
  int decimals = 0;
  while (decimals < 6 && std::abs(step * std::pow(10.0, decimals) - std::round(step * std::pow(10.0, decimals))) > 1e-6)
    ++decimals;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < 0.5 * step * 1e-6 ? 0.0 : v);
  return buf;
}

double tick_step(double lo, double hi, int target) {
  const double span = hi - lo;
  const double raw = span / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) return m * mag;
  return 10.0 * mag;
}

std::pair<double, double> auto_range(double lo, double hi, bool pad) {
  if (!(lo <= hi)) return {0.0, 1.0};
  if (hi - lo < 1e-9) {
    const double d = std::max(1e-3, 0.05 * std::abs(lo));
    return {lo - d, hi + d};
  }
  if (pad) {
    const double m = 0.05 * (hi - lo);
    return {lo - m, hi + m};
  }
  return {lo, hi};
}

}  // namespace

LinePlot::LinePlot(PlotOptions options) : options_(std::move(options)) {
  if (options_.width_px < 100 || options_.height_px < 80) throw Error("plot must be at least 100 x 80 pixels", {}, 0, "size");
}

void LinePlot::add_series(std::vector<Vec2> points, const SeriesStyle& style, std::string label) {
  series_.push_back({std::move(points), style, std::move(label)});
}

void LinePlot::add_band(double x0, double x1, Rgba colour, std::string label) {
  if (!std::isfinite(x0) || !std::isfinite(x1)) throw Error("band limits must be finite", {}, 0, "band");
  bands_.push_back({std::min(x0, x1), std::max(x0, x1), colour, std::move(label)});
}

std::vector<double> LinePlot::nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  const double step = tick_step(lo, hi, target);
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (int i = 0; i < 1000; ++i) {
    const double t = first + i * step;
    if (t > hi + 1e-9 * step) break;
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  }
  return ticks;
}

std::string LinePlot::svg_string() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double xlo = kInf, xhi = -kInf, ylo = kInf, yhi = -kInf;
  for (const Series& s : series_)
    for (const Vec2& p : s.points)
      if (p.allFinite()) {
        xlo = std::min(xlo, p.x());
        xhi = std::max(xhi, p.x());
        ylo = std::min(ylo, p.y());
        yhi = std::max(yhi, p.y());
      }
  // Plain variables, not structured bindings: the lambdas below capture them.
  const auto x_range = options_.x_range ? *options_.x_range : auto_range(xlo, xhi, false);
  const auto y_range = options_.y_range ? *options_.y_range : auto_range(ylo, yhi, true);
  double x0 = x_range.first, x1 = x_range.second, y0 = y_range.first, y1 = y_range.second;
  if (!(x1 > x0)) x1 = x0 + 1.0;
  if (!(y1 > y0)) y1 = y0 + 1.0;

  const double f = options_.font_px;
  const double left = 5.5 * f + 10.0, right = 20.0, top = options_.title.empty() ? 15.0 : 2.5 * f + 10.0;
  double bottom = 3.5 * f + 10.0;
  int width = options_.width_px, height = options_.height_px;
  double pw = width - left - right, ph = height - top - bottom;
  if (options_.equal_aspect) {
    ph = pw * (y1 - y0) / (x1 - x0);
    if (ph < 60.0) {  // too flat: widen the y range about its centre
      const double c = 0.5 * (y0 + y1), half = 0.5 * 60.0 * (x1 - x0) / pw;
      y0 = c - half;
      y1 = c + half;
      ph = 60.0;
    }
    height = static_cast<int>(std::ceil(top + ph + bottom));
  }
  const auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * pw; };
  const auto py = [&](double y) { return top + (y1 - y) / (y1 - y0) * ph; };

  std::string o;
  o += std::string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"") + std::to_string(width) + "\" height=\"" +
       std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
       "\" font-family=\"sans-serif\" font-size=\"" + num(f) + "\">\n";
  o += std::string("<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n");
  if (!options_.title.empty())
    o += std::string("<text x=\"") + num(left + 0.5 * pw) + "\" y=\"" + num(1.6 * f + 5.0) + "\" text-anchor=\"middle\" font-size=\"" +
         num(1.3 * f) + "\">" + escape(options_.title) + "</text>\n";
  o += std::string("<defs><clipPath id=\"plot\"><rect x=\"") + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(pw) +
       "\" height=\"" + num(ph) + "\"/></clipPath></defs>\n";
  // Bands under everything.
  for (const Band& b : bands_) {
    const double a = std::max(x0, b.x0), c = std::min(x1, b.x1);
    if (!(c > a)) continue;
    o += std::string("<rect x=\"") + num(px(a)) + "\" y=\"" + num(top) + "\" width=\"" + num(px(c) - px(a)) + "\" height=\"" + num(ph) +
         "\" fill=\"" + to_hex(b.colour) + "\" fill-opacity=\"" + num(b.colour.a / 255.0) + "\"/>\n";
    if (!b.label.empty())
      o += std::string("<text x=\"") + num(0.5 * (px(a) + px(c))) + "\" y=\"" + num(top + 1.2 * f) + "\" text-anchor=\"middle\" font-size=\"" +
           num(0.85 * f) + "\" fill=\"#333333\">" + escape(b.label) + "</text>\n";
  }
  // Grid and ticks.
  const std::vector<double> xt = nice_ticks(x0, x1, std::max(2, static_cast<int>(pw / 90.0)));
  const std::vector<double> yt = nice_ticks(y0, y1, std::max(2, static_cast<int>(ph / 60.0)));
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ys = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (const double t : xt) {
    o += std::string("<line x1=\"") + num(px(t)) + "\" y1=\"" + num(top) + "\" x2=\"" + num(px(t)) + "\" y2=\"" + num(top + ph) +
         "\" stroke=\"#dddddd\" stroke-width=\"1\"/>\n";
    o += std::string("<text x=\"") + num(px(t)) + "\" y=\"" + num(top + ph + 1.3 * f) + "\" text-anchor=\"middle\">" + tick_label(t, xs) +
         "</text>\n";
  }
  for (const double t : yt) {
    o += std::string("<line x1=\"") + num(left) + "\" y1=\"" + num(py(t)) + "\" x2=\"" + num(left + pw) + "\" y2=\"" + num(py(t)) +
         "\" stroke=\"#dddddd\" stroke-width=\"1\"/>\n";
    o += std::string("<text x=\"") + num(left - 5.0) + "\" y=\"" + num(py(t) + 0.35 * f) + "\" text-anchor=\"end\">" + tick_label(t, ys) +
         "</text>\n";
  }
  o += std::string("<rect x=\"") + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(pw) + "\" height=\"" + num(ph) +
       "\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1\"/>\n";
  if (!options_.x_label.empty())
    o += std::string("<text x=\"") + num(left + 0.5 * pw) + "\" y=\"" + num(top + ph + 2.8 * f) + "\" text-anchor=\"middle\">" +
         escape(options_.x_label) + "</text>\n";
  if (!options_.y_label.empty()) {
    const double x = 1.2 * f, y = top + 0.5 * ph;
    o += std::string("<text x=\"") + num(x) + "\" y=\"" + num(y) + "\" text-anchor=\"middle\" transform=\"rotate(-90 " + num(x) + " " +
         num(y) + ")\">" + escape(options_.y_label) + "</text>\n";
  }
  // Series.
  o += std::string("<g clip-path=\"url(#plot)\">\n");
  for (const Series& s : series_) {
    const std::string colour = to_hex(s.style.colour);
    if (s.style.width_px > 0.0) {
      std::string d;
      bool pen_down = false;
      for (const Vec2& p : s.points) {
        if (!p.allFinite()) {
          pen_down = false;
          continue;
        }
        d += pen_down ? 'L' : 'M';
        d += num(px(p.x()));
        d += ' ';
        d += num(py(p.y()));
        pen_down = true;
      }
      if (!d.empty())
        o += std::string("<path d=\"") + d + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + num(s.style.width_px) +
             "\" stroke-linejoin=\"round\"" + (s.style.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
    }
    if (s.style.markers)
      for (const Vec2& p : s.points)
        if (p.allFinite())
          o += std::string("<circle cx=\"") + num(px(p.x())) + "\" cy=\"" + num(py(p.y())) + "\" r=\"2.5\" fill=\"" + colour + "\"/>\n";
  }
  o += std::string("</g>\n");
  // Legend (top right, inside the plot).
  int row = 0;
  for (const Series& s : series_) {
    if (s.label.empty()) continue;
    const double y = top + 2.4 * f + row * 1.4 * f, x = left + pw - 10.0;
    o += std::string("<line x1=\"") + num(x - 28.0) + "\" y1=\"" + num(y - 0.35 * f) + "\" x2=\"" + num(x - 8.0) + "\" y2=\"" +
         num(y - 0.35 * f) + "\" stroke=\"" + to_hex(s.style.colour) + "\" stroke-width=\"" + num(std::max(1.5, s.style.width_px)) +
         "\"" + (s.style.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
    o += std::string("<text x=\"") + num(x - 32.0) + "\" y=\"" + num(y) + "\" text-anchor=\"end\">" + escape(s.label) + "</text>\n";
    ++row;
  }
  o += std::string("</svg>\n");
  return o;
}

void LinePlot::write_svg(const std::string& path) const { write_file_atomically(path, svg_string()); }

}  // namespace starnav::viz
