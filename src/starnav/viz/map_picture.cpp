#include "starnav/viz/map_picture.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav::viz {

namespace {

constexpr double kTickLen = 5.0;

// Fixed-point text of a number, locale-independent; never "-0".
std::string fmt(double v, int decimals) {
  if (!std::isfinite(v)) v = 0.0;
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  // A number too long for fixed notation (1e70) is written in the shortest general form, which
  // always fits: never the buffer's unwritten bytes.
  if (r.ec != std::errc()) r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general);
  std::string s(buf, r.ptr);
  if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}
std::string px(double v) { return fmt(v, 2); }

// XML text: escapes markup, replaces control characters and invalid UTF-8 by '?'.
std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out.push_back(c < 0x20 && c != '\t' ? '?' : static_cast<char>(c));
      }
      ++i;
      continue;
    }
    const std::size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    bool ok = len != 0 && i + len <= s.size();
    for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
    if (ok) {
      out.append(s.substr(i, len));
      i += len;
    } else {
      out.push_back('?');
      ++i;
    }
  }
  return out;
}

}  // namespace

// Outside the anonymous namespace: MapPicture::Frame (declared in the header) holds them.
struct Ticks {
  double step = 1.0;
  int decimals = 0;
  std::vector<double> values;
};

namespace {

double nice_number(double raw) {
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  return (n < 1.5 ? 1.0 : n < 3.0 ? 2.0 : n < 7.0 ? 5.0 : 10.0) * mag;
}

int decimals_for(double step) { return std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9))); }

Ticks nice_ticks(double lo, double hi, int target) {
  Ticks t;
  const double span = hi - lo;
  t.step = span > 0.0 ? nice_number(span / std::max(1, target)) : 1.0;
  t.decimals = decimals_for(t.step);
  const auto k0 = static_cast<long long>(std::ceil(lo / t.step - 1e-9));
  const auto k1 = static_cast<long long>(std::floor(hi / t.step + 1e-9));
  for (long long k = k0; k <= k1 && t.values.size() < 100; ++k) t.values.push_back(static_cast<double>(k) * t.step);
  return t;
}

// The largest 1-2-5 number not above x.
double nice_floor(double x) {
  const double mag = std::pow(10.0, std::floor(std::log10(x)));
  for (const double f : {5.0, 2.0, 1.0})
    if (f * mag <= x * (1.0 + 1e-12)) return f * mag;
  return mag;
}

void check_finite(const Vec2& p, const char* field) {
  if (!p.allFinite()) throw Error("coordinates must be finite", {}, 0, field);
}
void check_opacity(double v, const char* field) {
  if (!(v >= 0.0 && v <= 1.0)) throw Error("opacity must be in [0, 1]", {}, 0, field);
}

// A 2x3 affine map (SVG's matrix(a b c d e f)): (x, y) -> (a x + c y + e, b x + d y + f).
struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
  Vec2 apply(const Vec2& p) const { return {a * p.x() + c * p.y() + e, b * p.x() + d * p.y() + f}; }
  Affine inverse() const {
    const double det = a * d - b * c;
    Affine r;
    r.a = d / det;
    r.b = -b / det;
    r.c = -c / det;
    r.d = a / det;
    r.e = -(r.a * e + r.c * f);
    r.f = -(r.b * e + r.d * f);
    return r;
  }
};

// Paints `image` (pixels mapped to the canvas by `m`) into the canvas, clipped to the rectangle;
// each canvas pixel averages n x n samples (n > 1 when image pixels are smaller than canvas
// pixels), so thin walls do not vanish when a big map is drawn small.
void draw_raster(RgbaImage& canvas, const RgbaImage& image, const Affine& m, double cx0, double cy0, double cx1,
                 double cy1) {
  if (image.width <= 0 || image.height <= 0) return;
  const Affine inv = m.inverse();
  double minx = std::numeric_limits<double>::infinity(), maxx = -minx, miny = minx, maxy = -minx;
  for (const Vec2& corner : {Vec2(0, 0), Vec2(image.width, 0), Vec2(0, image.height), Vec2(image.width, image.height)}) {
    const Vec2 p = m.apply(corner);
    minx = std::min(minx, p.x());
    maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y());
    maxy = std::max(maxy, p.y());
  }
  const int x0 = std::max({0, static_cast<int>(std::floor(std::max(minx, cx0)))});
  const int y0 = std::max({0, static_cast<int>(std::floor(std::max(miny, cy0)))});
  const int x1 = std::min(canvas.width, static_cast<int>(std::ceil(std::min(maxx, cx1))));
  const int y1 = std::min(canvas.height, static_cast<int>(std::ceil(std::min(maxy, cy1))));
  const double pixel = std::min(std::hypot(m.a, m.b), std::hypot(m.c, m.d));  // canvas px per image px
  const int n = std::clamp(static_cast<int>(std::ceil(1.0 / pixel - 1e-9)), 1, 8);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      if (n == 1) {  // one sample: the image pixel under the centre
        const Vec2 uv = inv.apply({x + 0.5, y + 0.5});
        const double fu = std::floor(uv.x()), fv = std::floor(uv.y());
        if (fu < 0 || fv < 0 || fu >= image.width || fv >= image.height) continue;
        canvas.blend(x, y, image.at(static_cast<int>(fu), static_cast<int>(fv)));
        continue;
      }
      double sr = 0, sg = 0, sb = 0, sa = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Vec2 uv = inv.apply({x + (i + 0.5) / n, y + (j + 0.5) / n});
          const double fu = std::floor(uv.x()), fv = std::floor(uv.y());
          if (fu < 0 || fv < 0 || fu >= image.width || fv >= image.height) continue;
          const Rgba c = image.at(static_cast<int>(fu), static_cast<int>(fv));
          sr += c.r * c.a;
          sg += c.g * c.a;
          sb += c.b * c.a;
          sa += c.a;
        }
      if (sa <= 0.0) continue;
      const Rgba avg{static_cast<std::uint8_t>(std::lround(sr / sa)), static_cast<std::uint8_t>(std::lround(sg / sa)),
                     static_cast<std::uint8_t>(std::lround(sb / sa)), 255};
      canvas.blend(x, y, avg, sa / (255.0 * n * n));
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Layout

struct MapPicture::Metrics {
  bool svg = true;
  double size = 12;        // font size (SVG) or line height (PNG), px
  double char_w = 7.2;     // average advance per character
  double ascent = 9;       // baseline below the top of a line
  double title_size = 15.6;
  double title_char_w = 9.4;
  double title_ascent = 11.7;
  int text_scale = 1;      // PNG bitmap font scales
  int title_scale = 2;

  static Metrics for_svg(double font_px) {
    Metrics m;
    m.svg = true;
    m.size = font_px;
    m.char_w = 0.62 * font_px;
    m.ascent = 0.75 * font_px;
    m.title_size = 1.3 * font_px;
    m.title_char_w = 0.65 * m.title_size;
    m.title_ascent = 0.75 * m.title_size;
    return m;
  }
  static Metrics for_png(double font_px) {
    Metrics m;
    m.svg = false;
    m.text_scale = std::max(1, static_cast<int>(std::lround(font_px / 12.0)));
    m.title_scale = m.text_scale + 1;
    m.size = BitmapFont::kLineHeight * m.text_scale;
    m.char_w = BitmapFont::kAdvance * m.text_scale;
    m.ascent = BitmapFont::kAscent * m.text_scale;
    m.title_size = BitmapFont::kLineHeight * m.title_scale;
    m.title_char_w = BitmapFont::kAdvance * m.title_scale;
    m.title_ascent = BitmapFont::kAscent * m.title_scale;
    return m;
  }
  double width(std::string_view s) const { return static_cast<double>(s.size()) * char_w; }
  double title_width(std::string_view s) const { return static_cast<double>(s.size()) * title_char_w; }
};

struct MapPicture::Frame {
  PictureLayout layout;
  Metrics m;
  double pad = 6;
  std::string units;
  Ticks xt, yt;
  std::vector<std::string> xl, yl;
  std::string x_title, y_title;
  double bar_world = 0.0;  // scale bar length in world units
  std::string bar_label;
  double bar_y = 0.0;      // top of the scale bar block
  // legend
  double legend_x = 0.0;
  bool colour_bar = false;
  double cbar_title_y = 0.0, cbar_top = 0.0, cbar_h = 0.0, cbar_caption_y = 0.0;
  Ticks zt;
  std::vector<std::string> zl;
  std::string z_caption;
  struct Entry {
    std::size_t layer;
    double y;  // centre line of the row
  };
  std::vector<Entry> entries;
};

namespace {

// The legend label of a layer ("" for text layers, which have none).
template <class Layer>
std::string label_of(const Layer& layer) {
  return std::visit(
      [](const auto& l) -> std::string {
        if constexpr (requires { l.label; }) return l.label;
        else return {};
      },
      layer);
}

}  // namespace

double MapPicture::auto_pixels_per_cell() const {
  // The rotated grid's bounding box, in cells.
  const double c = std::abs(std::cos(geometry_.origin.yaw)), s = std::abs(std::sin(geometry_.origin.yaw));
  const double bw = geometry_.width * c + geometry_.height * s, bh = geometry_.width * s + geometry_.height * c;
  return options_.target_plot_px / std::max({bw, bh, 1e-9});
}

MapPicture::Frame MapPicture::frame(double px_per_m, const Metrics& m) const {
  if (!(px_per_m > 0.0) || !std::isfinite(px_per_m)) throw Error("picture scale must be positive", {}, 0, "size");
  Frame f;
  f.m = m;
  PictureLayout& L = f.layout;
  L.y_down = geometry_.y_down;
  L.px_per_m = px_per_m;
  // The world window: bounding box of the (possibly rotated) grid.
  L.xmin = L.ymin = std::numeric_limits<double>::infinity();
  L.xmax = L.ymax = -std::numeric_limits<double>::infinity();
  for (const Vec2& g : {Vec2(0, 0), Vec2(geometry_.width_m(), 0), Vec2(0, geometry_.height_m()),
                        Vec2(geometry_.width_m(), geometry_.height_m())}) {
    const Vec2 w = geometry_.grid_to_world(g);
    L.xmin = std::min(L.xmin, w.x());
    L.xmax = std::max(L.xmax, w.x());
    L.ymin = std::min(L.ymin, w.y());
    L.ymax = std::max(L.ymax, w.y());
  }
  L.plot_w = (L.xmax - L.xmin) * px_per_m;
  L.plot_h = (L.ymax - L.ymin) * px_per_m;
  f.pad = std::round(m.size * 0.5);
  const double pad = f.pad;
  f.units = geometry_.y_down ? "cells" : "m";

  double left = pad, right = pad, top = pad, bottom = pad;
  double last_half = 0.0;  // how far the last x tick label reaches right of the plot
  if (!options_.title.empty()) top += m.title_size + pad;
  if (options_.axes) {
    const int xtarget = std::clamp(static_cast<int>(L.plot_w / std::max(60.0, 8.0 * m.char_w)), 2, 10);
    const int ytarget = std::clamp(static_cast<int>(L.plot_h / std::max(40.0, 3.0 * m.size)), 2, 10);
    f.xt = nice_ticks(L.xmin, L.xmax, xtarget);
    f.yt = nice_ticks(L.ymin, L.ymax, ytarget);
    double ylabel_w = 0.0;
    for (double v : f.xt.values) f.xl.push_back(fmt(v, f.xt.decimals));
    for (double v : f.yt.values) {
      f.yl.push_back(fmt(v, f.yt.decimals));
      ylabel_w = std::max(ylabel_w, m.width(f.yl.back()));
    }
    f.x_title = "x [" + f.units + "]";
    f.y_title = "y [" + f.units + "]";
    const double first_half = f.xl.empty() ? 0.0 : m.width(f.xl.front()) / 2;
    last_half = f.xl.empty() ? 0.0 : m.width(f.xl.back()) / 2;
    left = std::max({pad + ylabel_w + 3 + kTickLen, first_half + pad, pad + m.width(f.y_title) + 3 + kTickLen});
    right = std::max(right, last_half + pad);
    top += m.size * 1.5 + pad;  // the y axis title above the plot, clear of the top tick label
    bottom += kTickLen + 3 + m.size + pad + m.size;
  }
  if (options_.scale_bar) {
    const double span = L.xmax - L.xmin;
    f.bar_world = nice_floor(0.3 * span);
    f.bar_label = fmt(f.bar_world, decimals_for(f.bar_world)) + " " + f.units;
    bottom += pad + m.size + 4;
  }
  L.plot_x = std::ceil(left);
  L.plot_y = std::ceil(top);

  // Legend, right of the plot.
  double legend_w = 0.0, legend_bottom = L.plot_y;
  if (options_.legend) {
    f.legend_x = L.plot_x + L.plot_w + std::max(2 * pad, last_half + pad);
    double y = L.plot_y;
    if (kind_ == Kind::Elevation && height_range_) {
      f.colour_bar = true;
      const HeightRange r = *height_range_;
      f.cbar_title_y = y + m.ascent;
      const std::string title = "height [m]";
      legend_w = std::max(legend_w, m.width(title));
      f.cbar_top = y + m.size + 6;
      f.cbar_h = std::clamp(L.plot_h * 0.5, 80.0, 320.0);
      f.zt = nice_ticks(r.min, r.max, std::clamp(static_cast<int>(f.cbar_h / (2.5 * m.size)), 2, 6));
      double zw = 0.0;
      for (double v : f.zt.values) {
        f.zl.push_back(fmt(v, f.zt.decimals));
        zw = std::max(zw, m.width(f.zl.back()));
      }
      legend_w = std::max(legend_w, 14 + 4 + kTickLen + zw);
      const int zdec = std::max(2, f.zt.decimals);
      f.z_caption = fmt(r.min, zdec) + " to " + fmt(r.max, zdec) + " m";
      legend_w = std::max(legend_w, m.width(f.z_caption));
      f.cbar_caption_y = f.cbar_top + f.cbar_h + 6 + m.ascent;
      y = f.cbar_top + f.cbar_h + 6 + m.size + 2 * pad;
    }
    const double row = std::max(m.size, 12.0) + 6;
    for (std::size_t i = 0; i < layers_.size(); ++i) {
      const std::string label = label_of(layers_[i]);
      if (label.empty()) continue;
      f.entries.push_back({i, y + row / 2});
      legend_w = std::max(legend_w, 24 + 6 + m.width(label));
      y += row;
    }
    legend_bottom = y;
    if (legend_w > 0.0) right = std::max(right, (f.legend_x - (L.plot_x + L.plot_w)) + legend_w + pad);
  }

  double w = L.plot_x + L.plot_w + right;
  if (!options_.title.empty()) w = std::max(w, m.title_width(options_.title) + 2 * pad);
  const double h = std::max(L.plot_y + L.plot_h + bottom, legend_bottom + pad);
  if (!std::isfinite(w) || !std::isfinite(h))
    throw Error("the picture's size is not a finite number of pixels (the map's extent, resolution or scale is out of range)",
                {}, 0, "size");
  if (!(w < kMaxPictureSidePixels) || !(h < kMaxPictureSidePixels))
    throw Error("picture would be " + fmt(w, 0) + " x " + fmt(h, 0) + " pixels, more than " +
                    std::to_string(kMaxPictureSidePixels) + " on a side",
                {}, 0, "size");
  L.width_px = static_cast<int>(std::ceil(w));
  L.height_px = static_cast<int>(std::ceil(h));
  f.bar_y = L.plot_y + L.plot_h + (options_.axes ? kTickLen + 3 + m.size + pad + m.size : 0.0) + pad;
  return f;
}

MapPicture::Frame MapPicture::frame_for_width(int width_px, const Metrics& m) const {
  if (width_px <= 0 || width_px >= kMaxPictureSidePixels)
    throw Error("PNG width must be 1.." + std::to_string(kMaxPictureSidePixels - 1) + " pixels, got " + std::to_string(width_px),
                {}, 0, "width");
  double s = auto_pixels_per_cell() / geometry_.resolution;
  Frame f = frame(s, m);
  const double world_w = f.layout.xmax - f.layout.xmin;
  for (int iteration = 0; iteration < 4; ++iteration) {
    const double around = f.layout.width_px - f.layout.plot_w;  // margins, legend, rounding
    const double plot = width_px - around;
    if (plot < 1.0)
      throw Error("a picture " + std::to_string(width_px) + " pixels wide leaves no room for the map", {}, 0,
                  "width");
    s = plot / world_w;
    f = frame(s, m);
  }
  f.layout.width_px = width_px;
  return f;
}

MapPicture::Frame MapPicture::svg_frame() const {
  const double ppc = options_.pixels_per_cell > 0.0 ? options_.pixels_per_cell : auto_pixels_per_cell();
  return frame(ppc / geometry_.resolution, Metrics::for_svg(options_.font_px));
}

MapPicture::Frame MapPicture::png_frame(const RasterSize& size) const {
  const Metrics m = Metrics::for_png(options_.font_px);
  if (size.pixels_per_cell != 0.0 && size.width_px != 0)
    throw Error("give either pixels per cell or a width, not both", {}, 0, "size");
  if (!(size.pixels_per_cell >= 0.0) || !std::isfinite(size.pixels_per_cell))
    throw Error("pixels per cell must be positive and finite", {}, 0, "pixels_per_cell");
  Frame f;
  if (size.width_px != 0) {
    f = frame_for_width(size.width_px, m);
  } else {
    double ppc = size.pixels_per_cell;
    if (ppc == 0.0) {
      ppc = auto_pixels_per_cell();
      if (ppc >= 1.0) ppc = std::floor(ppc);
    }
    f = frame(ppc / geometry_.resolution, m);
  }
  if (static_cast<double>(f.layout.width_px) * f.layout.height_px > kMaxPicturePixels)
    throw Error("PNG would have " + fmt(static_cast<double>(f.layout.width_px) * f.layout.height_px, 0) +
                    " pixels, more than " + fmt(kMaxPicturePixels, 0),
                {}, 0, "size");
  return f;
}

PictureLayout MapPicture::svg_layout() const { return svg_frame().layout; }
PictureLayout MapPicture::png_layout(const RasterSize& size) const { return png_frame(size).layout; }

// ---------------------------------------------------------------------------------------------
// Construction and layers

MapPicture::MapPicture(const GridGeometry& geometry, PictureOptions options, Kind kind)
    : geometry_(geometry), options_(std::move(options)), kind_(kind) {
  validate_geometry(geometry_, "picture");
  // Axis ticks, labels and pixel positions are computed in integers: beyond a planet's scale
  // they would overflow. Every map corner lies within kMaxCoordinateM of the origin.
  const double w_m = geometry_.width * geometry_.resolution, h_m = geometry_.height * geometry_.resolution;
  for (const Vec2& corner : {geometry_.grid_to_world({0.0, 0.0}), geometry_.grid_to_world({w_m, 0.0}),
                             geometry_.grid_to_world({0.0, h_m}), geometry_.grid_to_world({w_m, h_m})})
    if (!(plausible_coordinate(corner.x()) && plausible_coordinate(corner.y())))
      throw Error("the map reaches " + fmt(std::max(std::abs(corner.x()), std::abs(corner.y())), 0) +
                      " m from the origin; pictures draw maps within 1e9 m of it",
                  {}, 0, "picture");
  if (!(options_.font_px > 0.0) || !std::isfinite(options_.font_px) || options_.font_px > 200.0)
    throw Error("font size must be in (0, 200] pixels", {}, 0, "font_px");
  if (options_.target_plot_px <= 0 || options_.target_plot_px >= kMaxPictureSidePixels)
    throw Error("target plot size must be 1.." + std::to_string(kMaxPictureSidePixels - 1) + " pixels", {}, 0, "target_plot_px");
  if (!(options_.pixels_per_cell >= 0.0) || !std::isfinite(options_.pixels_per_cell))
    throw Error("pixels per cell must be positive and finite (0 = automatic)", {}, 0, "pixels_per_cell");
}

MapPicture::MapPicture(const OccupancyGrid& grid, PictureOptions options)
    : MapPicture(grid.geometry(), std::move(options), Kind::Occupancy) {
  base_ = occupancy_raster(grid, options_.occupancy);
}

MapPicture::MapPicture(const ElevationMap& map, PictureOptions options)
    : MapPicture(map.geometry(), std::move(options), Kind::Elevation) {
  base_ = elevation_raster(map, options_.elevation);
  height_range_ = elevation_colour_range(map, options_.elevation);
}

MapPicture::MapPicture(const GridGeometry& geometry, PictureOptions options)
    : MapPicture(geometry, std::move(options), Kind::Blank) {}

namespace {

void check_line_style(const LineStyle& s) {
  require_positive(s.width_px, "width_px");
  check_opacity(s.opacity, "opacity");
}

}  // namespace

void MapPicture::add_polyline(std::vector<Vec2> points, const LineStyle& style, std::string label) {
  for (const Vec2& p : points) check_finite(p, "points");
  check_line_style(style);
  layers_.emplace_back(Polyline{std::move(points), style, std::move(label)});
}

void MapPicture::add_points(std::vector<Vec2> points, const MarkerStyle& style, std::string label) {
  for (const Vec2& p : points) check_finite(p, "points");
  require_positive(style.radius_px, "radius_px");
  if (!(style.outline_px >= 0.0) || !std::isfinite(style.outline_px))
    throw Error("outline width must be >= 0 and finite", {}, 0, "outline_px");
  check_opacity(style.opacity, "opacity");
  layers_.emplace_back(Points{std::move(points), style, std::move(label)});
}

void MapPicture::add_cells(const std::vector<Cell>& cells, Rgba colour, double opacity, std::string label) {
  check_opacity(opacity, "opacity");
  Cells layer;
  layer.colour = colour;
  layer.opacity = opacity;
  layer.label = std::move(label);
  layer.x0 = layer.y0 = std::numeric_limits<int>::max();
  layer.x1 = layer.y1 = std::numeric_limits<int>::min();
  for (const Cell& c : cells) {
    if (!geometry_.contains(c)) continue;
    layer.x0 = std::min(layer.x0, c.x);
    layer.y0 = std::min(layer.y0, c.y);
    layer.x1 = std::max(layer.x1, c.x);
    layer.y1 = std::max(layer.y1, c.y);
  }
  if (layer.x1 < layer.x0) {  // nothing inside the map: an empty layer (still in the legend)
    layer.x0 = layer.y0 = 0;
    layer.x1 = layer.y1 = -1;
  } else {
    layer.overlay = RgbaImage(layer.x1 - layer.x0 + 1, layer.y1 - layer.y0 + 1);
    const Rgba c = with_opacity(colour, opacity);
    for (const Cell& cell : cells) {
      if (!geometry_.contains(cell)) continue;
      const int row = geometry_.y_down ? cell.y - layer.y0 : layer.y1 - cell.y;
      layer.overlay.set(cell.x - layer.x0, row, c);
    }
  }
  layers_.emplace_back(std::move(layer));
}

void MapPicture::add_circle(const Vec2& centre, double radius_m, const LineStyle& stroke, std::optional<Rgba> fill,
                            std::string label) {
  check_finite(centre, "centre");
  require_positive(radius_m, "radius");
  check_line_style(stroke);
  layers_.emplace_back(Circle{centre, radius_m, stroke, fill, std::move(label)});
}

void MapPicture::add_pose(const Pose2& pose, double length_m, const LineStyle& style, std::string label) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw))
    throw Error("pose must be finite", {}, 0, "pose");
  require_positive(length_m, "length");
  check_line_style(style);
  layers_.emplace_back(Arrow{pose, length_m, style, std::move(label)});
}

void MapPicture::add_text(const Vec2& at, std::string text, const TextStyle& style) {
  check_finite(at, "position");
  require_positive(style.size_px, "size_px");
  layers_.emplace_back(Text{at, std::move(text), style});
}

// ---------------------------------------------------------------------------------------------
// Shared geometry of both backends

namespace {

// Maps pixel (u, v) of a raster holding cells [x0, x1] x [y0, y1] (rows in file order) to the
// picture.
Affine raster_affine(const GridGeometry& g, const PictureLayout& L, int x0, int y0, int y1) {
  auto P = [&](double u, double v) {
    const double gx = (x0 + u) * g.resolution;
    const double gy = g.y_down ? (y0 + v) * g.resolution : (y1 + 1 - v) * g.resolution;
    return L.to_picture(g.grid_to_world({gx, gy}));
  };
  const Vec2 p0 = P(0, 0), pu = P(1, 0) - p0, pv = P(0, 1) - p0;
  return {pu.x(), pu.y(), pv.x(), pv.y(), p0.x(), p0.y()};
}

struct ArrowShape {
  Vec2 base, shaft_end, tip;
  std::vector<Vec2> head;
};

ArrowShape arrow_shape(const PictureLayout& L, const Pose2& pose, double length, double width_px) {
  ArrowShape a;
  a.base = L.to_picture({pose.x, pose.y});
  a.tip = L.to_picture({pose.x + length * std::cos(pose.yaw), pose.y + length * std::sin(pose.yaw)});
  const Vec2 d = a.tip - a.base;
  const double len = d.norm();
  const Vec2 u = len > 0 ? Vec2(d / len) : Vec2(1, 0);
  const Vec2 n(-u.y(), u.x());
  const double hl = std::min(std::max(6.0, 3.0 * width_px), std::max(len, 1.0));
  const double hw = 0.5 * hl;
  a.shaft_end = a.tip - u * (0.8 * hl);
  a.head = {a.tip, Vec2(a.tip - u * hl + n * hw), Vec2(a.tip - u * hl - n * hw)};
  return a;
}

Rgba faded(Rgba c, double opacity) { return with_opacity(c, opacity); }

double anchor_fraction(TextAnchor a) { return a == TextAnchor::Start ? 0.0 : a == TextAnchor::Middle ? 0.5 : 1.0; }
const char* anchor_name(TextAnchor a) {
  return a == TextAnchor::Start ? "start" : a == TextAnchor::Middle ? "middle" : "end";
}

double ramp_y(double top, double h, double zmin, double zmax, double z) {
  return top + h * (1.0 - (z - zmin) / (zmax - zmin));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// SVG

namespace {

// fill/stroke attributes; opacity only when below 1.
void svg_paint(std::string& o, const char* what, Rgba c, double opacity = 1.0) {
  o += ' ';
  o += what;
  o += "=\"";
  o += c.a == 0 || opacity <= 0.0 ? std::string("none") : to_hex(c);
  o += '"';
  const double a = c.a / 255.0 * opacity;
  if (c.a != 0 && a < 1.0) {
    o += ' ';
    o += what;
    o += "-opacity=\"" + fmt(a, 3) + "\"";
  }
}

// Each pixel repeated k x k times.
RgbaImage upscaled(const RgbaImage& image, int k) {
  RgbaImage out(image.width * k, image.height * k);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.set(x, y, image.at(x / k, y / k));
  return out;
}

// An embedded raster. Viewers that smooth images when scaling them up (librsvg, some editors
// ignore image-rendering) would blur small maps, so a raster shown at several pixels per cell is
// embedded upscaled by a whole factor (up to 8, while it stays below 4 megapixels).
void svg_image(std::string& o, const char* cls, const RgbaImage& source, Affine m) {
  const double shown = std::min(std::hypot(m.a, m.b), std::hypot(m.c, m.d));  // picture px per pixel
  int k = std::clamp(static_cast<int>(std::floor(shown)), 1, 8);
  while (k > 1 && static_cast<double>(source.width) * source.height * k * k > 4e6) --k;
  RgbaImage scaled;
  if (k > 1) {
    scaled = upscaled(source, k);
    m.a /= k;
    m.b /= k;
    m.c /= k;
    m.d /= k;
  }
  const RgbaImage& image = k > 1 ? scaled : source;
  o += "<image class=\"";
  o += cls;
  o += "\" x=\"0\" y=\"0\" width=\"" + std::to_string(image.width) + "\" height=\"" + std::to_string(image.height) +
       "\" preserveAspectRatio=\"none\" image-rendering=\"optimizeSpeed\" style=\"image-rendering:pixelated\"";
  o += " transform=\"matrix(" + fmt(m.a, 6) + " " + fmt(m.b, 6) + " " + fmt(m.c, 6) + " " + fmt(m.d, 6) + " " +
       fmt(m.e, 4) + " " + fmt(m.f, 4) + ")\"";
  o += " xlink:href=\"data:image/png;base64,";
  o += base64_encode(encode_png(image));
  o += "\"/>\n";
}

void svg_text(std::string& o, const char* cls, const Vec2& at, std::string_view text, const char* anchor,
              const std::string& extra = {}) {
  o += "<text class=\"";
  o += cls;
  o += "\" x=\"";
  o += px(at.x());
  o += "\" y=\"";
  o += px(at.y());
  o += '"';
  if (std::string_view(anchor) != "start") {
    o += " text-anchor=\"";
    o += anchor;
    o += '"';
  }
  o += extra;
  o += '>';
  o += xml_escape(text);
  o += "</text>\n";
}

}  // namespace

std::string MapPicture::svg_string() const {
  const Frame f = svg_frame();
  const PictureLayout& L = f.layout;
  const Metrics& m = f.m;
  const double pad = f.pad;
  std::string o;
  o.reserve(4096 + static_cast<std::size_t>(base_.width) * static_cast<std::size_t>(base_.height) / 2);
  o += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" version=\"1.1\"";
  o += " width=\"" + std::to_string(L.width_px) + "\" height=\"" + std::to_string(L.height_px) + "\" viewBox=\"0 0 " +
       std::to_string(L.width_px) + " " + std::to_string(L.height_px) + "\"";
  o += " font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"" + px(m.size) + "\">\n";
  if (!options_.title.empty()) o += "<title>" + xml_escape(options_.title) + "</title>\n";
  o += "<rect id=\"background\" x=\"0\" y=\"0\" width=\"" + std::to_string(L.width_px) + "\" height=\"" +
       std::to_string(L.height_px) + "\"";
  svg_paint(o, "fill", options_.background);
  o += "/>\n";
  const std::string plot_rect = "x=\"" + px(L.plot_x) + "\" y=\"" + px(L.plot_y) + "\" width=\"" + px(L.plot_w) +
                                "\" height=\"" + px(L.plot_h) + "\"";
  o += "<defs>\n<clipPath id=\"plot-area\"><rect " + plot_rect + "/></clipPath>\n";
  if (f.colour_bar) {
    o += "<linearGradient id=\"height-ramp\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">\n";
    for (int i = 0; i <= 10; ++i)
      o += "<stop offset=\"" + fmt(i / 10.0, 1) + "\" stop-color=\"" + to_hex(viridis(i / 10.0)) + "\"/>\n";
    o += "</linearGradient>\n";
  }
  o += "</defs>\n";

  // The map.
  o += "<g id=\"map\" clip-path=\"url(#plot-area)\">\n<rect class=\"plot-background\" " + plot_rect;
  svg_paint(o, "fill", options_.plot_background);
  o += "/>\n";
  if (base_.width > 0) svg_image(o, "map-raster", base_, raster_affine(geometry_, L, 0, 0, geometry_.height - 1));
  o += "</g>\n";

  // The layers.
  o += "<g id=\"layers\" clip-path=\"url(#plot-area)\">\n";
  for (const Layer& layer : layers_) {
    if (const auto* l = std::get_if<Polyline>(&layer)) {
      o += "<polyline class=\"layer-polyline\" points=\"";
      for (std::size_t i = 0; i < l->points.size(); ++i) {
        const Vec2 p = L.to_picture(l->points[i]);
        if (i) o += ' ';
        o += px(p.x()) + "," + px(p.y());
      }
      if (l->points.size() == 1) {  // a zero-length line: round caps draw a dot
        const Vec2 p = L.to_picture(l->points[0]);
        o += " " + px(p.x()) + "," + px(p.y());
      }
      o += "\" fill=\"none\"";
      svg_paint(o, "stroke", l->style.colour, l->style.opacity);
      o += " stroke-width=\"" + px(l->style.width_px) + "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
      if (l->style.dashed)
        o += " stroke-dasharray=\"" + px(std::max(3.0, 4.0 * l->style.width_px)) + " " +
             px(std::max(2.0, 2.0 * l->style.width_px)) + "\"";
      o += "/>\n";
    } else if (const auto* l = std::get_if<Points>(&layer)) {
      o += "<g class=\"layer-points\"";
      svg_paint(o, "fill", l->style.fill, l->style.opacity);
      if (l->style.outline_px > 0.0) {
        svg_paint(o, "stroke", l->style.outline, l->style.opacity);
        o += " stroke-width=\"" + px(l->style.outline_px) + "\"";
      }
      o += ">\n";
      for (const Vec2& w : l->points) {
        const Vec2 p = L.to_picture(w);
        o += "<circle cx=\"" + px(p.x()) + "\" cy=\"" + px(p.y()) + "\" r=\"" + px(l->style.radius_px) + "\"/>\n";
      }
      o += "</g>\n";
    } else if (const auto* l = std::get_if<Cells>(&layer)) {
      if (l->x1 >= l->x0) svg_image(o, "layer-cells", l->overlay, raster_affine(geometry_, L, l->x0, l->y0, l->y1));
    } else if (const auto* l = std::get_if<Circle>(&layer)) {
      const Vec2 c = L.to_picture(l->centre);
      o += "<circle class=\"layer-circle\" cx=\"" + px(c.x()) + "\" cy=\"" + px(c.y()) + "\" r=\"" +
           px(l->radius * L.px_per_m) + "\"";
      if (l->fill) svg_paint(o, "fill", *l->fill);
      else o += " fill=\"none\"";
      svg_paint(o, "stroke", l->stroke.colour, l->stroke.opacity);
      o += " stroke-width=\"" + px(l->stroke.width_px) + "\"";
      if (l->stroke.dashed)
        o += " stroke-dasharray=\"" + px(std::max(3.0, 4.0 * l->stroke.width_px)) + " " +
             px(std::max(2.0, 2.0 * l->stroke.width_px)) + "\"";
      o += "/>\n";
    } else if (const auto* l = std::get_if<Arrow>(&layer)) {
      const ArrowShape a = arrow_shape(L, l->pose, l->length, l->style.width_px);
      o += "<g class=\"layer-pose\"";
      svg_paint(o, "stroke", l->style.colour, l->style.opacity);
      svg_paint(o, "fill", l->style.colour, l->style.opacity);
      o += " stroke-width=\"" + px(l->style.width_px) + "\" stroke-linecap=\"round\">\n";
      o += "<line x1=\"" + px(a.base.x()) + "\" y1=\"" + px(a.base.y()) + "\" x2=\"" + px(a.shaft_end.x()) +
           "\" y2=\"" + px(a.shaft_end.y()) + "\"/>\n";
      o += "<polygon stroke=\"none\" points=\"";
      for (std::size_t i = 0; i < a.head.size(); ++i)
        o += (i ? " " : "") + px(a.head[i].x()) + "," + px(a.head[i].y());
      o += "\"/>\n</g>\n";
    } else if (const auto* l = std::get_if<Text>(&layer)) {
      std::string extra = " font-size=\"" + px(l->style.size_px) + "\"";
      std::string fill;
      svg_paint(fill, "fill", l->style.colour);
      extra += fill;
      if (l->style.halo)
        extra += " stroke=\"#ffffff\" stroke-width=\"3.00\" stroke-linejoin=\"round\" paint-order=\"stroke\"";
      svg_text(o, "layer-text", L.to_picture(l->at), l->text, anchor_name(l->style.anchor), extra);
    }
  }
  o += "</g>\n";

  // Axes.
  const double bottom = L.plot_y + L.plot_h;
  if (options_.axes) {
    o += "<g id=\"axes\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1\">\n";
    o += "<rect x=\"" + px(L.plot_x - 0.5) + "\" y=\"" + px(L.plot_y - 0.5) + "\" width=\"" + px(L.plot_w + 1) +
         "\" height=\"" + px(L.plot_h + 1) + "\"/>\n<path d=\"";
    for (const double v : f.xt.values)
      o += "M" + px(L.to_picture({v, 0}).x()) + " " + px(bottom + 0.5) + "v" + px(kTickLen);
    for (const double v : f.yt.values)
      o += "M" + px(L.plot_x - 0.5) + " " + px(L.to_picture({0, v}).y()) + "h" + px(-kTickLen);
    o += "\"/>\n</g>\n<g id=\"tick-labels\" fill=\"#000000\">\n";
    for (std::size_t i = 0; i < f.xt.values.size(); ++i)
      svg_text(o, "tick-x", {L.to_picture({f.xt.values[i], 0}).x(), bottom + kTickLen + 3 + m.ascent}, f.xl[i],
               "middle");
    for (std::size_t i = 0; i < f.yt.values.size(); ++i)
      svg_text(o, "tick-y", {L.plot_x - kTickLen - 3, L.to_picture({0, f.yt.values[i]}).y() + m.ascent / 2},
               f.yl[i], "end");
    svg_text(o, "axis-title", {L.plot_x + L.plot_w / 2, bottom + kTickLen + 3 + m.size + pad + m.ascent}, f.x_title,
             "middle");
    svg_text(o, "axis-title", {L.plot_x - kTickLen - 3, L.plot_y - m.size / 2 - pad}, f.y_title, "end");
    o += "</g>\n";
  }
  if (options_.scale_bar) {
    const double len = f.bar_world * L.px_per_m, y = f.bar_y + m.size / 2;
    o += "<g id=\"scale-bar\">\n";
    o += "<rect x=\"" + px(L.plot_x) + "\" y=\"" + px(y - 2) + "\" width=\"" + px(len) +
         "\" height=\"4\" fill=\"#000000\"/>\n";
    o += "<path d=\"M" + px(L.plot_x + 0.5) + " " + px(y - 5) + "v10M" + px(L.plot_x + len - 0.5) + " " + px(y - 5) +
         "v10\" stroke=\"#000000\" stroke-width=\"1\" fill=\"none\"/>\n";
    svg_text(o, "scale-label", {L.plot_x + len + 6, y + m.ascent / 2}, f.bar_label, "start");
    o += "</g>\n";
  }
  if (f.colour_bar || !f.entries.empty()) {
    o += "<g id=\"legend\">\n";
    const double x = f.legend_x;
    if (f.colour_bar) {
      const HeightRange r = *height_range_;
      svg_text(o, "legend-title", {x, f.cbar_title_y}, "height [m]", "start");
      o += "<rect x=\"" + px(x) + "\" y=\"" + px(f.cbar_top) + "\" width=\"14\" height=\"" + px(f.cbar_h) +
           "\" fill=\"url(#height-ramp)\" stroke=\"#000000\" stroke-width=\"1\"/>\n<path d=\"";
      for (const double z : f.zt.values)
        o += "M" + px(x + 14) + " " + px(ramp_y(f.cbar_top, f.cbar_h, r.min, r.max, z)) + "h" + px(kTickLen);
      o += "\" stroke=\"#000000\" stroke-width=\"1\" fill=\"none\"/>\n";
      for (std::size_t i = 0; i < f.zt.values.size(); ++i)
        svg_text(o, "legend-tick",
                 {x + 14 + kTickLen + 3, ramp_y(f.cbar_top, f.cbar_h, r.min, r.max, f.zt.values[i]) + m.ascent / 2},
                 f.zl[i], "start");
      svg_text(o, "legend-range", {x, f.cbar_caption_y}, f.z_caption, "start");
    }
    for (const auto& e : f.entries) {
      const Layer& layer = layers_[e.layer];
      const double y = e.y;
      if (const auto* l = std::get_if<Polyline>(&layer)) {
        o += "<line x1=\"" + px(x) + "\" y1=\"" + px(y) + "\" x2=\"" + px(x + 24) + "\" y2=\"" + px(y) + "\"";
        svg_paint(o, "stroke", l->style.colour, l->style.opacity);
        o += " stroke-width=\"" + px(l->style.width_px) + "\"";
        if (l->style.dashed) o += " stroke-dasharray=\"4 2\"";
        o += "/>\n";
      } else if (const auto* l = std::get_if<Points>(&layer)) {
        o += "<circle cx=\"" + px(x + 12) + "\" cy=\"" + px(y) + "\" r=\"" + px(std::min(l->style.radius_px, 6.0)) + "\"";
        svg_paint(o, "fill", l->style.fill, l->style.opacity);
        if (l->style.outline_px > 0.0) {
          svg_paint(o, "stroke", l->style.outline, l->style.opacity);
          o += " stroke-width=\"" + px(l->style.outline_px) + "\"";
        }
        o += "/>\n";
      } else if (const auto* l = std::get_if<Cells>(&layer)) {
        o += "<rect x=\"" + px(x + 6) + "\" y=\"" + px(y - 6) + "\" width=\"12\" height=\"12\"";
        svg_paint(o, "fill", l->colour, l->opacity);
        o += "/>\n";
      } else if (const auto* l = std::get_if<Circle>(&layer)) {
        o += "<circle cx=\"" + px(x + 12) + "\" cy=\"" + px(y) + "\" r=\"6\"";
        if (l->fill) svg_paint(o, "fill", *l->fill);
        else o += " fill=\"none\"";
        svg_paint(o, "stroke", l->stroke.colour, l->stroke.opacity);
        o += " stroke-width=\"" + px(std::min(l->stroke.width_px, 3.0)) + "\"/>\n";
      } else if (const auto* l = std::get_if<Arrow>(&layer)) {
        o += "<path d=\"M" + px(x) + " " + px(y) + "h16M" + px(x + 24) + " " + px(y) + "l-8 -4v8z\"";
        svg_paint(o, "stroke", l->style.colour, l->style.opacity);
        svg_paint(o, "fill", l->style.colour, l->style.opacity);
        o += " stroke-width=\"" + px(std::min(l->style.width_px, 3.0)) + "\"/>\n";
      }
      svg_text(o, "legend-label", {x + 30, y + m.ascent / 2}, label_of(layer), "start");
    }
    o += "</g>\n";
  }
  if (!options_.title.empty()) {
    const double cx = std::max(L.plot_x + L.plot_w / 2, pad + m.title_width(options_.title) / 2);
    svg_text(o, "title", {cx, pad + m.title_ascent}, options_.title, "middle",
             " font-size=\"" + px(m.title_size) + "\" font-weight=\"bold\"");
  }
  o += "</svg>\n";
  return o;
}

void MapPicture::write_svg(const std::string& path) const { write_file_atomically(path, svg_string()); }

// ---------------------------------------------------------------------------------------------
// PNG

RgbaImage MapPicture::render_png(const RasterSize& size) const {
  const Frame f = png_frame(size);
  const PictureLayout& L = f.layout;
  const Metrics& m = f.m;
  const double pad = f.pad;
  RgbaImage img(L.width_px, L.height_px, options_.background);
  Canvas cv(img);
  const double x0 = L.plot_x, y0 = L.plot_y, x1 = L.plot_x + L.plot_w, y1 = L.plot_y + L.plot_h;
  const Rgba black{0, 0, 0, 255}, white{255, 255, 255, 255};

  cv.set_clip(x0, y0, x1, y1);
  cv.fill_rect(x0, y0, x1, y1, options_.plot_background);
  if (base_.width > 0) draw_raster(img, base_, raster_affine(geometry_, L, 0, 0, geometry_.height - 1), x0, y0, x1, y1);
  for (const Layer& layer : layers_) {
    if (const auto* l = std::get_if<Polyline>(&layer)) {
      std::vector<Vec2> pts;
      pts.reserve(l->points.size());
      for (const Vec2& w : l->points) pts.push_back(L.to_picture(w));
      cv.stroke_polyline(pts, l->style.width_px, faded(l->style.colour, l->style.opacity), l->style.dashed);
    } else if (const auto* l = std::get_if<Points>(&layer)) {
      for (const Vec2& w : l->points) {
        const Vec2 p = L.to_picture(w);
        cv.fill_disc(p, l->style.radius_px, faded(l->style.fill, l->style.opacity));
        if (l->style.outline_px > 0.0)
          cv.stroke_circle(p, l->style.radius_px, l->style.outline_px, faded(l->style.outline, l->style.opacity));
      }
    } else if (const auto* l = std::get_if<Cells>(&layer)) {
      if (l->x1 >= l->x0)
        draw_raster(img, l->overlay, raster_affine(geometry_, L, l->x0, l->y0, l->y1), x0, y0, x1, y1);
    } else if (const auto* l = std::get_if<Circle>(&layer)) {
      const Vec2 c = L.to_picture(l->centre);
      const double r = l->radius * L.px_per_m;
      if (l->fill) cv.fill_disc(c, r, *l->fill);
      cv.stroke_circle(c, r, l->stroke.width_px, faded(l->stroke.colour, l->stroke.opacity));
    } else if (const auto* l = std::get_if<Arrow>(&layer)) {
      const ArrowShape a = arrow_shape(L, l->pose, l->length, l->style.width_px);
      const Rgba c = faded(l->style.colour, l->style.opacity);
      cv.stroke_polyline({a.base, a.shaft_end}, l->style.width_px, c);
      cv.fill_convex_polygon(a.head, c);
    } else if (const auto* l = std::get_if<Text>(&layer)) {
      const int scale = std::max(1, static_cast<int>(std::lround(l->style.size_px / 12.0)));
      cv.text(L.to_picture(l->at), l->text, l->style.colour, scale, anchor_fraction(l->style.anchor),
              l->style.halo ? white : Rgba{0, 0, 0, 0});
    }
  }
  cv.reset_clip();

  const int s = m.text_scale;
  if (options_.axes) {
    // Frame, one pixel outside the plot.
    cv.fill_rect(x0 - 1, y0 - 1, x1 + 1, y0, black);
    cv.fill_rect(x0 - 1, y1, x1 + 1, y1 + 1, black);
    cv.fill_rect(x0 - 1, y0, x0, y1, black);
    cv.fill_rect(x1, y0, x1 + 1, y1, black);
    for (std::size_t i = 0; i < f.xt.values.size(); ++i) {
      const double tx = std::floor(L.to_picture({f.xt.values[i], 0}).x());
      cv.fill_rect(tx, y1 + 1, tx + 1, y1 + 1 + kTickLen, black);
      cv.text({tx + 0.5, y1 + kTickLen + 3 + m.ascent}, f.xl[i], black, s, 0.5);
    }
    for (std::size_t i = 0; i < f.yt.values.size(); ++i) {
      const double ty = std::floor(L.to_picture({0, f.yt.values[i]}).y());
      cv.fill_rect(x0 - 1 - kTickLen, ty, x0 - 1, ty + 1, black);
      cv.text({x0 - kTickLen - 3, ty + 0.5 + m.ascent / 2}, f.yl[i], black, s, 1.0);
    }
    cv.text({x0 + L.plot_w / 2, y1 + kTickLen + 3 + m.size + pad + m.ascent}, f.x_title, black, s, 0.5);
    cv.text({x0 - kTickLen - 3, y0 - m.size / 2 - pad}, f.y_title, black, s, 1.0);
  }
  if (options_.scale_bar) {
    const double len = f.bar_world * L.px_per_m, y = std::floor(f.bar_y + m.size / 2);
    cv.fill_rect(x0, y - 2, x0 + len, y + 2, black);
    cv.fill_rect(x0, y - 5, x0 + 1, y + 5, black);
    cv.fill_rect(x0 + len - 1, y - 5, x0 + len, y + 5, black);
    cv.text({x0 + len + 6, y + m.ascent / 2}, f.bar_label, black, s, 0.0);
  }
  const double x = f.legend_x;
  if (f.colour_bar) {
    const HeightRange r = *height_range_;
    cv.text({x, f.cbar_title_y}, "height [m]", black, s, 0.0);
    const int top = static_cast<int>(std::floor(f.cbar_top)), h = static_cast<int>(std::lround(f.cbar_h));
    for (int j = 0; j < h; ++j)
      cv.fill_rect(x, top + j, x + 14, top + j + 1, viridis(1.0 - (j + 0.5) / h));
    cv.fill_rect(x - 1, top - 1, x + 15, top, black);
    cv.fill_rect(x - 1, top + h, x + 15, top + h + 1, black);
    cv.fill_rect(x - 1, top, x, top + h, black);
    cv.fill_rect(x + 14, top, x + 15, top + h, black);
    for (std::size_t i = 0; i < f.zt.values.size(); ++i) {
      const double ty = std::floor(ramp_y(top, h, r.min, r.max, f.zt.values[i]));
      cv.fill_rect(x + 15, ty, x + 15 + kTickLen, ty + 1, black);
      cv.text({x + 14 + kTickLen + 3, ty + 0.5 + m.ascent / 2}, f.zl[i], black, s, 0.0);
    }
    cv.text({x, f.cbar_caption_y}, f.z_caption, black, s, 0.0);
  }
  for (const auto& e : f.entries) {
    const Layer& layer = layers_[e.layer];
    const double y = std::floor(e.y) + 0.5;
    if (const auto* l = std::get_if<Polyline>(&layer)) {
      cv.stroke_polyline({Vec2(x, y), Vec2(x + 24, y)}, l->style.width_px, faded(l->style.colour, l->style.opacity),
                         l->style.dashed);
    } else if (const auto* l = std::get_if<Points>(&layer)) {
      const double r = std::min(l->style.radius_px, 6.0);
      cv.fill_disc({x + 12, y}, r, faded(l->style.fill, l->style.opacity));
      if (l->style.outline_px > 0.0) cv.stroke_circle({x + 12, y}, r, l->style.outline_px, faded(l->style.outline, l->style.opacity));
    } else if (const auto* l = std::get_if<Cells>(&layer)) {
      cv.fill_rect(x + 6, y - 6.5, x + 18, y + 5.5, with_opacity(l->colour, l->opacity));
    } else if (const auto* l = std::get_if<Circle>(&layer)) {
      if (l->fill) cv.fill_disc({x + 12, y}, 6, *l->fill);
      cv.stroke_circle({x + 12, y}, 6, std::min(l->stroke.width_px, 3.0), faded(l->stroke.colour, l->stroke.opacity));
    } else if (const auto* l = std::get_if<Arrow>(&layer)) {
      const Rgba c = faded(l->style.colour, l->style.opacity);
      cv.stroke_polyline({Vec2(x, y), Vec2(x + 16, y)}, std::min(l->style.width_px, 3.0), c);
      cv.fill_convex_polygon({Vec2(x + 24, y), Vec2(x + 16, y - 4), Vec2(x + 16, y + 4)}, c);
    }
    cv.text({x + 30, y + m.ascent / 2}, label_of(layer), black, s, 0.0);
  }
  if (!options_.title.empty()) {
    const double cx = std::max(x0 + L.plot_w / 2, pad + m.title_width(options_.title) / 2);
    cv.text({cx, pad + m.title_ascent}, options_.title, black, m.title_scale, 0.5);
  }
  return img;
}

void MapPicture::write_png(const std::string& path, const RasterSize& size) const {
  write_png_file(render_png(size), path);
}

}  // namespace starnav::viz
