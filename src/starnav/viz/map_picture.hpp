#pragma once
// MapPicture: a map (occupancy grid or elevation map) with layers on top, in world coordinates,
// rendered to SVG or PNG. Paths, expanded cells, trajectories, robots and labels are layers.
//
//   viz::MapPicture pic(grid, {.title = "A* on maze-512"});
//   pic.add_cells(trace, viz::parse_colour("sky"), 0.4, "expanded");
//   pic.add_polyline(path_points, {.colour = viz::categorical_colour(0), .width_px = 2.5}, "A*");
//   pic.write_svg("astar.svg");
//   pic.write_png("astar.png", viz::RasterSize::per_cell(2));
//
// Pictures show the world frame: x to the right, y up, axes with tick labels in metres, a scale
// bar, an optional title and a legend (the labelled layers; for elevation maps a colour bar
// with the height range in metres). A grid whose origin has a yaw appears rotated, in SVG (the
// raster carries a transform) and PNG alike (every pixel samples the cell under its centre).
// Index grids (GridGeometry::y_down, e.g. MovingAI maps) are drawn as in their files: y grows
// downward, and the axes count cells.
//
// The base map is one pixel per cell, embedded in the SVG as a base64 PNG, so large maps stay
// small; the layers are SVG vectors on top (expanded cells are a second embedded raster).
// Output is deterministic: the same inputs give the same bytes (fixed number formatting, no time
// stamps).
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/viz/colour.hpp"
#include "starnav/viz/map_raster.hpp"
#include "starnav/viz/raster.hpp"

namespace starnav::viz {

// Either side of a picture is below kMaxPictureSidePixels; a PNG holds at most kMaxPicturePixels.
inline constexpr int kMaxPictureSidePixels = 32768;
inline constexpr double kMaxPicturePixels = 400.0 * 1000 * 1000;

struct LineStyle {
  Rgba colour{213, 94, 0, 255};  // vermillion
  double width_px = 2.0;
  double opacity = 1.0;
  bool dashed = false;
};

struct MarkerStyle {
  Rgba fill{0, 114, 178, 255};  // blue
  double radius_px = 3.0;
  Rgba outline{255, 255, 255, 255};
  double outline_px = 1.0;  // 0 = no outline
  double opacity = 1.0;
};

enum class TextAnchor { Start, Middle, End };

struct TextStyle {
  Rgba colour{0, 0, 0, 255};
  double size_px = 12.0;
  TextAnchor anchor = TextAnchor::Start;
  bool halo = true;  // a white outline, legible on any map
};

struct PictureOptions {
  std::string title{};
  // SVG scale in pixels per cell; 0 = automatic (the longer side of the plot is about
  // target_plot_px). write_png has its own size (RasterSize).
  double pixels_per_cell = 0.0;
  int target_plot_px = 800;
  double font_px = 12.0;  // tick labels and legend; the title is 1.3 times larger
  bool axes = true;
  bool scale_bar = true;
  bool legend = true;
  Rgba background{255, 255, 255, 255};       // the page
  Rgba plot_background{224, 224, 224, 255};  // inside the axes where no map cell is (rotated maps, unobserved cells)
  OccupancyPalette occupancy{};
  ElevationStyle elevation{};
};

// Size of a PNG: pixels per cell, or the width of the whole picture in pixels (the height
// follows), or neither (automatic: like the SVG, rounded down to whole pixels per cell when
// that is at least 1, so cells stay crisp).
struct RasterSize {
  double pixels_per_cell = 0.0;
  int width_px = 0;
  static RasterSize per_cell(double ppc) { return {ppc, 0}; }
  static RasterSize width(int px) { return {0.0, px}; }
};

// Where things land in one rendering: the canvas, the plot rectangle (inside the axes) and the
// map from world coordinates to picture pixels (x right, y down, origin top left).
struct PictureLayout {
  int width_px = 0;
  int height_px = 0;
  double plot_x = 0.0;  // left edge of the plot
  double plot_y = 0.0;  // top edge of the plot
  double plot_w = 0.0;
  double plot_h = 0.0;
  double px_per_m = 1.0;  // picture pixels per world unit (metre; cell for index grids)
  double xmin = 0.0, xmax = 0.0, ymin = 0.0, ymax = 0.0;  // the world window shown
  bool y_down = false;

  Vec2 to_picture(const Vec2& world) const {
    return {plot_x + (world.x() - xmin) * px_per_m,
            y_down ? plot_y + (world.y() - ymin) * px_per_m : plot_y + (ymax - world.y()) * px_per_m};
  }
  Vec2 to_world(const Vec2& picture) const {
    return {xmin + (picture.x() - plot_x) / px_per_m,
            y_down ? ymin + (picture.y() - plot_y) / px_per_m : ymax - (picture.y() - plot_y) / px_per_m};
  }
};

class MapPicture {
 public:
  // Throws Error for a bad geometry or bad options (non-positive sizes, non-finite values).
  explicit MapPicture(const OccupancyGrid& grid, PictureOptions options = {});
  explicit MapPicture(const ElevationMap& map, PictureOptions options = {});
  // A blank picture of a grid's extent (plot background only), for layers alone.
  explicit MapPicture(const GridGeometry& geometry, PictureOptions options = {});

  void set_title(std::string title) { options_.title = std::move(title); }
  const PictureOptions& options() const { return options_; }
  const GridGeometry& geometry() const { return geometry_; }
  // The base raster, one pixel per cell, rows in file order (see map_raster.hpp).
  const RgbaImage& base_raster() const { return base_; }

  // Layers, drawn in the order they are added, clipped to the plot. Coordinates are world
  // coordinates (metres; for index grids, cells with y down, a cell's centre at +0.5). A
  // non-empty label puts the layer in the legend. Non-finite coordinates or sizes throw Error.
  void add_polyline(std::vector<Vec2> points, const LineStyle& style = {}, std::string label = {});
  void add_points(std::vector<Vec2> points, const MarkerStyle& style = {}, std::string label = {});
  // Cells of this grid filled with a colour (e.g. expanded nodes); cells outside the map are
  // skipped.
  void add_cells(const std::vector<Cell>& cells, Rgba colour, double opacity = 0.5, std::string label = {});
  // A circle of a radius in world units (a robot's footprint, a goal tolerance).
  void add_circle(const Vec2& centre, double radius_m, const LineStyle& stroke = {},
                  std::optional<Rgba> fill = std::nullopt, std::string label = {});
  // An arrow from the pose's position along its heading.
  void add_pose(const Pose2& pose, double length_m, const LineStyle& style = {}, std::string label = {});
  void add_text(const Vec2& at, std::string text, const TextStyle& style = {});

  PictureLayout svg_layout() const;
  PictureLayout png_layout(const RasterSize& size = {}) const;

  std::string svg_string() const;
  // Throw Error naming the file when it cannot be written.
  void write_svg(const std::string& path) const;
  RgbaImage render_png(const RasterSize& size = {}) const;
  void write_png(const std::string& path, const RasterSize& size = {}) const;

 private:
  struct Polyline {
    std::vector<Vec2> points;
    LineStyle style;
    std::string label;
  };
  struct Points {
    std::vector<Vec2> points;
    MarkerStyle style;
    std::string label;
  };
  struct Cells {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // bounding box (inclusive); empty when x1 < x0
    RgbaImage overlay;                      // the box, rows in file order
    Rgba colour;
    double opacity = 0.5;
    std::string label;
  };
  struct Circle {
    Vec2 centre;
    double radius = 0.0;
    LineStyle stroke;
    std::optional<Rgba> fill;
    std::string label;
  };
  struct Arrow {
    Pose2 pose;
    double length = 0.0;
    LineStyle style;
    std::string label;
  };
  struct Text {
    Vec2 at;
    std::string text;
    TextStyle style;
  };
  using Layer = std::variant<Polyline, Points, Cells, Circle, Arrow, Text>;

  struct Metrics;
  struct Frame;
  enum class Kind { Blank, Occupancy, Elevation };

  MapPicture(const GridGeometry& geometry, PictureOptions options, Kind kind);
  Frame frame(double px_per_m, const Metrics& m) const;
  Frame frame_for_width(int width_px, const Metrics& m) const;
  Frame svg_frame() const;
  Frame png_frame(const RasterSize& size) const;
  double auto_pixels_per_cell() const;

  GridGeometry geometry_;
  PictureOptions options_;
  Kind kind_ = Kind::Blank;
  RgbaImage base_;
  std::optional<HeightRange> height_range_;  // elevation pictures: the colour ramp's range
  std::vector<Layer> layers_;
};

}  // namespace starnav::viz
