// MapPicture and its parts: SVG structure and coordinates, PNG pixels read back with libpng,
// determinism, hillshade, colours, base64 and the bitmap font.
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/viz/colour.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/map_raster.hpp"
#include "starnav/viz/raster.hpp"
#include "support/test_support.hpp"

namespace {

using starnav::Cell;
using starnav::GridGeometry;
using starnav::OccupancyGrid;
using starnav::Pose2;
using starnav::Vec2;
namespace viz = starnav::viz;

GridGeometry geometry(int w, int h, double res, Pose2 origin = {}, bool y_down = false) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = origin;
  g.y_down = y_down;
  return g;
}

// ------------------------------------------------------------------ reading SVG and PNG back

// A minimal XML well-formedness check: tags balance, attributes are quoted, one root <svg>.
// Returns "" when fine, else what is wrong.
std::string check_xml(const std::string& s) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  int roots = 0;
  while ((i = s.find('<', i)) != std::string::npos) {
    if (s.compare(i, 5, "<?xml") == 0) {
      i = s.find("?>", i);
      if (i == std::string::npos) return "unterminated declaration";
      continue;
    }
    const std::size_t end = s.find('>', i);
    if (end == std::string::npos) return "unterminated tag";
    std::string tag = s.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return "'<' inside a tag: " + tag.substr(0, 60);
    // quotes balance inside the tag
    if (std::count(tag.begin(), tag.end(), '"') % 2 != 0) return "unbalanced quotes: " + tag.substr(0, 60);
    if (!tag.empty() && tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name) return "unexpected </" + name + ">";
      stack.pop_back();
    } else {
      const bool self_closing = !tag.empty() && tag.back() == '/';
      const std::string name = tag.substr(0, tag.find_first_of(" \n/"));
      if (stack.empty()) ++roots;
      if (stack.empty() && name != "svg") return "root is <" + name + ">";
      if (!self_closing) stack.push_back(name);
    }
    i = end + 1;
  }
  if (!stack.empty()) return "unclosed <" + stack.back() + ">";
  if (roots != 1) return "expected one root element";
  // Text content must not hold a raw '&' that starts no entity.
  for (std::size_t k = s.find('&'); k != std::string::npos; k = s.find('&', k + 1)) {
    const std::string rest = s.substr(k, 6);
    if (rest.rfind("&amp;", 0) != 0 && rest.rfind("&lt;", 0) != 0 && rest.rfind("&gt;", 0) != 0 &&
        rest.rfind("&quot;", 0) != 0 && rest.rfind("&apos;", 0) != 0)
      return "raw '&'";
  }
  return {};
}

std::size_t count_of(const std::string& s, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t i = s.find(needle); i != std::string::npos; i = s.find(needle, i + 1)) ++n;
  return n;
}

// The value of attribute `name` in the first element starting with `element_start`.
std::string attribute(const std::string& svg, const std::string& element_start, const std::string& name) {
  const std::size_t at = svg.find(element_start);
  if (at == std::string::npos) return {};
  const std::size_t end = svg.find('>', at);
  const std::string tag = svg.substr(at, end - at);
  const std::string key = " " + name + "=\"";
  const std::size_t k = tag.find(key);
  if (k == std::string::npos) return {};
  const std::size_t v = k + key.size();
  return tag.substr(v, tag.find('"', v) - v);
}

std::vector<Vec2> parse_points(const std::string& points) {
  std::vector<Vec2> out;
  std::istringstream in(points);
  std::string pair;
  while (in >> pair) {
    const auto comma = pair.find(',');
    out.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
  }
  return out;
}

std::array<double, 6> parse_matrix(const std::string& transform) {
  std::array<double, 6> m{};
  const std::size_t open = transform.find('(');
  std::istringstream in(transform.substr(open + 1));
  for (double& v : m) in >> v;
  return m;
}

std::string base64_decode(const std::string& s) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  int bits = 0, acc = 0;
  for (char c : s) {
    const int v = value(c);
    if (v < 0) break;  // padding
    acc = (acc << 6) | v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

// PNG decoded by libpng's simplified API into 8-bit RGBA.
struct Decoded {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  viz::Rgba at(int x, int y) const {
    const std::size_t o = (static_cast<std::size_t>(y) * width + x) * 4;
    return {rgba[o], rgba[o + 1], rgba[o + 2], rgba[o + 3]};
  }
};

std::optional<Decoded> decode_png(const std::string& bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return std::nullopt;
  image.format = PNG_FORMAT_RGBA;
  Decoded d;
  d.width = static_cast<int>(image.width);
  d.height = static_cast<int>(image.height);
  d.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, d.rgba.data(), 0, nullptr)) {
    png_image_free(&image);
    return std::nullopt;
  }
  return d;
}

std::optional<Decoded> read_png(const std::string& path) { return decode_png(starnav::test::read_text(path)); }

// The embedded PNG of the first <image> whose class is `cls`.
std::optional<Decoded> embedded_png(const std::string& svg, const std::string& cls) {
  const std::string href = attribute(svg, "<image class=\"" + cls + "\"", "xlink:href");
  const std::string prefix = "data:image/png;base64,";
  if (href.rfind(prefix, 0) != 0) return std::nullopt;
  return decode_png(base64_decode(href.substr(prefix.size())));
}

void expect_colour_near(viz::Rgba got, viz::Rgba want, int tol, const std::string& what) {
  EXPECT_NEAR(got.r, want.r, tol) << what;
  EXPECT_NEAR(got.g, want.g, tol) << what;
  EXPECT_NEAR(got.b, want.b, tol) << what;
  EXPECT_NEAR(got.a, want.a, tol) << what;
}

// Pixel under a picture point.
viz::Rgba pixel_at(const Decoded& d, const Vec2& p) {
  return d.at(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())));
}

// A 20 x 10 map, 0.5 m cells, origin (1, 2): free, with a few cells set.
OccupancyGrid test_grid(Pose2 origin = Pose2(1.0, 2.0, 0.0)) {
  OccupancyGrid grid(geometry(20, 10, 0.5, origin), 0);
  grid.set(3, 2, 100);
  grid.set(4, 2, 100);
  grid.set(10, 7, -1);
  grid.set(15, 5, 30);
  return grid;
}

}  // namespace

// ------------------------------------------------------------------------------------------ SVG

TEST(MapPictureSvg, IsWellFormedWithTheExpectedElements) {
  viz::MapPicture pic(test_grid(), {.title = "Test <map> & co"});
  pic.add_polyline({{1.5, 2.5}, {3.0, 4.0}}, {}, "path A");
  pic.add_polyline({{2.0, 2.5}, {6.0, 4.0}, {8.0, 6.0}}, {.dashed = true}, "path B");
  pic.add_polyline({{2.0, 3.0}});  // a single point, no label
  pic.add_points({{2.0, 2.0}, {3.0, 3.0}, {4.0, 4.0}}, {}, "samples");
  pic.add_cells({{1, 1}, {2, 1}, {50, 50}}, viz::parse_colour("sky"), 0.4, "expanded");
  pic.add_circle({5.0, 4.0}, 0.8, {}, viz::Rgba{0, 200, 0, 100}, "robot");
  pic.add_pose(Pose2(6.0, 5.0, 1.0), 1.0, {}, "start");
  pic.add_text({7.0, 5.5}, "label \"q\" <b>");
  const std::string svg = pic.svg_string();
  EXPECT_EQ(check_xml(svg), "");
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_EQ(count_of(svg, "<polyline "), 3u);
  EXPECT_EQ(count_of(svg, "class=\"layer-points\""), 1u);
  EXPECT_EQ(count_of(svg, "<image class=\"map-raster\""), 1u);
  EXPECT_EQ(count_of(svg, "<image class=\"layer-cells\""), 1u);
  EXPECT_EQ(count_of(svg, "class=\"layer-circle\""), 1u);
  EXPECT_EQ(count_of(svg, "class=\"layer-pose\""), 1u);
  EXPECT_EQ(count_of(svg, "stroke-dasharray"), 2u);  // the dashed path and its legend swatch
  EXPECT_EQ(count_of(svg, "class=\"legend-label\""), 6u);  // every labelled layer, not the text or the bare point
  EXPECT_NE(svg.find(">x [m]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">y [m]</text>"), std::string::npos);
  EXPECT_NE(svg.find("<title>Test &lt;map&gt; &amp; co</title>"), std::string::npos);
  EXPECT_NE(svg.find("label &quot;q&quot; &lt;b&gt;"), std::string::npos);
  EXPECT_NE(svg.find("id=\"scale-bar\""), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

TEST(MapPictureSvg, HugeCoordinatesAreOneClearErrorAndLargeOnesValidXml) {
  // A resolution of 1e70 m: one error, not labels made of overflowed integers.
  OccupancyGrid huge(geometry(4, 3, 1e70, Pose2(1.0, 2.0, 0.0)), 0);
  const std::string e = starnav::test::error_of([&] { viz::MapPicture pic(huge, {}); });
  EXPECT_NE(e.find("picture: the map reaches 4e+70 m from the origin"), std::string::npos) << e;
  EXPECT_NE(e.find("within 1e9 m"), std::string::npos) << e;
  // Near the limit (UTM-sized coordinates with a coarse grid) the SVG is valid and its labels
  // are numbers.
  OccupancyGrid large(geometry(4, 3, 1e8, Pose2(5e8, -5e8, 0.0)), 0);
  large.set(1, 1, 100);
  const std::string svg = viz::MapPicture(large, {.title = "large"}).svg_string();
  EXPECT_EQ(check_xml(svg), "");
  for (char c : svg) ASSERT_TRUE(c == '\n' || c == '\t' || static_cast<unsigned char>(c) >= 0x20) << static_cast<int>(c);
  EXPECT_EQ(svg.find("9223372036854775808"), std::string::npos);
}

TEST(MapPictureSvg, WorldPointsLandWhereTheLayoutSays) {
  // 20 x 10 cells of 0.5 m from (1, 2): the world window is [1, 11] x [2, 7]. At 10 px per cell
  // (20 px per metre) the plot is 200 x 100 px.
  viz::MapPicture pic(test_grid(), {.pixels_per_cell = 10.0});
  const viz::PictureLayout L = pic.svg_layout();
  EXPECT_DOUBLE_EQ(L.px_per_m, 20.0);
  EXPECT_DOUBLE_EQ(L.plot_w, 200.0);
  EXPECT_DOUBLE_EQ(L.plot_h, 100.0);
  EXPECT_DOUBLE_EQ(L.xmin, 1.0);
  EXPECT_DOUBLE_EQ(L.xmax, 11.0);
  EXPECT_DOUBLE_EQ(L.ymin, 2.0);
  EXPECT_DOUBLE_EQ(L.ymax, 7.0);
  EXPECT_GT(L.plot_x, 0.0);
  EXPECT_GT(L.width_px, L.plot_x + L.plot_w);
  EXPECT_GT(L.height_px, L.plot_y + L.plot_h);
  // to_picture by hand: the origin corner is the plot's bottom-left, (11, 7) its top-right.
  const Vec2 o = L.to_picture({1.0, 2.0});
  EXPECT_DOUBLE_EQ(o.x(), L.plot_x);
  EXPECT_DOUBLE_EQ(o.y(), L.plot_y + 100.0);
  const Vec2 tr = L.to_picture({11.0, 7.0});
  EXPECT_DOUBLE_EQ(tr.x(), L.plot_x + 200.0);
  EXPECT_DOUBLE_EQ(tr.y(), L.plot_y);
  EXPECT_TRUE(L.to_world(L.to_picture({3.3, 4.4})).isApprox(Vec2(3.3, 4.4), 1e-12));

  pic.add_polyline({{1.0, 2.0}, {11.0, 7.0}, {6.0, 4.5}, {2.25, 6.5}});
  const std::string svg = pic.svg_string();
  const auto pts = parse_points(attribute(svg, "<polyline", "points"));
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_NEAR(pts[0].x(), L.plot_x, 0.006);
  EXPECT_NEAR(pts[0].y(), L.plot_y + 100.0, 0.006);
  EXPECT_NEAR(pts[1].x(), L.plot_x + 200.0, 0.006);
  EXPECT_NEAR(pts[1].y(), L.plot_y, 0.006);
  EXPECT_NEAR(pts[2].x(), L.plot_x + 100.0, 0.006);
  EXPECT_NEAR(pts[2].y(), L.plot_y + 50.0, 0.006);
  EXPECT_NEAR(pts[3].x(), L.plot_x + 25.0, 0.006);
  EXPECT_NEAR(pts[3].y(), L.plot_y + 10.0, 0.006);
  // The svg element has the layout's size.
  EXPECT_EQ(attribute(svg, "<svg", "width"), std::to_string(L.width_px));
  EXPECT_EQ(attribute(svg, "<svg", "height"), std::to_string(L.height_px));
}

TEST(MapPictureSvg, TickLabelsSitOnTheirValues) {
  viz::MapPicture pic(test_grid(), {.pixels_per_cell = 30.0});
  const viz::PictureLayout L = pic.svg_layout();
  const std::string svg = pic.svg_string();
  const std::regex tick_x("<text class=\"tick-x\" x=\"([-0-9.]+)\" y=\"[-0-9.]+\" text-anchor=\"middle\">([-0-9.]+)</text>");
  const std::regex tick_y("<text class=\"tick-y\" x=\"[-0-9.]+\" y=\"([-0-9.]+)\" text-anchor=\"end\">([-0-9.]+)</text>");
  int nx = 0, ny = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick_x); it != std::sregex_iterator(); ++it, ++nx) {
    const double x = std::stod((*it)[1]), v = std::stod((*it)[2]);
    EXPECT_GE(v, L.xmin - 1e-9);
    EXPECT_LE(v, L.xmax + 1e-9);
    EXPECT_NEAR(x, L.to_picture({v, 0}).x(), 0.006) << v;
  }
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick_y); it != std::sregex_iterator(); ++it, ++ny) {
    const double y = std::stod((*it)[1]), v = std::stod((*it)[2]);
    EXPECT_GE(v, L.ymin - 1e-9);
    EXPECT_LE(v, L.ymax + 1e-9);
    // labels are centred on the tick: baseline a little below it
    const double ty = L.to_picture({0, v}).y();
    EXPECT_GT(y, ty);
    EXPECT_LT(y, ty + 12.0);
  }
  EXPECT_GE(nx, 2);
  EXPECT_GE(ny, 2);
  // Scale bar: a 1-2-5 length in metres, drawn that long.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(svg, m, std::regex("class=\"scale-label\"[^>]*>([0-9.]+) m</text>")));
  const double bar_m = std::stod(m[1]);
  EXPECT_GT(bar_m, 0.0);
  EXPECT_LE(bar_m, 0.3 * (L.xmax - L.xmin) + 1e-9);
  ASSERT_TRUE(std::regex_search(svg, m, std::regex("<g id=\"scale-bar\">\\n<rect x=\"[0-9.]+\" y=\"[0-9.]+\" width=\"([0-9.]+)\"")));
  EXPECT_NEAR(std::stod(m[1]), bar_m * L.px_per_m, 0.006);
}

TEST(MapPictureSvg, IndexGridsCountCellsDownward) {
  GridGeometry g = geometry(32, 16, 1.0, {}, /*y_down=*/true);
  OccupancyGrid grid(g, 0);
  grid.set(3, 1, 100);
  viz::MapPicture pic(grid, {.pixels_per_cell = 10.0});
  const viz::PictureLayout L = pic.svg_layout();
  EXPECT_TRUE(L.y_down);
  // y = 0 (the file's top row) is the top of the plot, y grows downward.
  EXPECT_DOUBLE_EQ(L.to_picture({0.0, 0.0}).y(), L.plot_y);
  EXPECT_DOUBLE_EQ(L.to_picture({0.0, 16.0}).y(), L.plot_y + 160.0);
  EXPECT_DOUBLE_EQ(L.to_picture({3.5, 1.5}).y(), L.plot_y + 15.0);
  const std::string svg = pic.svg_string();
  EXPECT_NE(svg.find(">x [cells]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">y [cells]</text>"), std::string::npos);
  EXPECT_NE(svg.find(" cells</text>"), std::string::npos);  // the scale bar
  // The embedded raster keeps the file's row order: the blocked cell is in row 1.
  const auto raster = embedded_png(svg, "map-raster");
  ASSERT_TRUE(raster.has_value());
  const int k = raster->width / 32;
  ASSERT_EQ(raster->width, 32 * k);
  ASSERT_EQ(raster->height, 16 * k);
  expect_colour_near(raster->at(3 * k, 1 * k), {0, 0, 0, 255}, 0, "blocked cell (3, 1)");
  expect_colour_near(raster->at(3 * k, 14 * k), {255, 255, 255, 255}, 0, "free cell (3, 14)");
}

TEST(MapPictureSvg, RotatedRasterCornersMatchTheGrid) {
  const Pose2 origin(3.0, -1.0, 0.5);
  const OccupancyGrid grid = test_grid(origin);
  viz::MapPicture pic(grid, {.pixels_per_cell = 8.0});
  const viz::PictureLayout L = pic.svg_layout();
  const GridGeometry& g = grid.geometry();
  // The window is the rotated rectangle's bounding box.
  double xmin = 1e9, xmax = -1e9;
  for (const Vec2& c : {Vec2(0, 0), Vec2(10, 0), Vec2(0, 5), Vec2(10, 5)}) {
    xmin = std::min(xmin, g.grid_to_world(c).x());
    xmax = std::max(xmax, g.grid_to_world(c).x());
  }
  EXPECT_NEAR(L.xmin, xmin, 1e-12);
  EXPECT_NEAR(L.xmax, xmax, 1e-12);
  const std::string svg = pic.svg_string();
  const auto m = parse_matrix(attribute(svg, "<image class=\"map-raster\"", "transform"));
  const double w = std::stod(attribute(svg, "<image class=\"map-raster\"", "width"));
  const double h = std::stod(attribute(svg, "<image class=\"map-raster\"", "height"));
  auto apply = [&](double u, double v) { return Vec2(m[0] * u + m[2] * v + m[4], m[1] * u + m[3] * v + m[5]); };
  // Image corners: bottom-left is the origin corner, top-left is (0, height_m) in the grid,
  // bottom-right is (width_m, 0).
  const std::array<std::pair<Vec2, Vec2>, 3> corners{{{Vec2(0, h), Vec2(0, 0)},
                                                      {Vec2(0, 0), Vec2(0, g.height_m())},
                                                      {Vec2(w, h), Vec2(g.width_m(), 0)}}};
  for (const auto& [image_px, grid_m] : corners) {
    const Vec2 got = apply(image_px.x(), image_px.y());
    const Vec2 want = L.to_picture(g.grid_to_world(grid_m));
    EXPECT_NEAR(got.x(), want.x(), 0.01) << image_px.transpose();
    EXPECT_NEAR(got.y(), want.y(), 0.01) << image_px.transpose();
  }
  // A real rotation: the image's x axis points up-right in the picture (yaw 0.5, y up).
  EXPECT_GT(m[0], 0.0);
  EXPECT_LT(m[1], 0.0);
  EXPECT_NEAR(std::atan2(-m[1], m[0]), 0.5, 1e-4);
}

TEST(MapPictureSvg, EmbeddedRasterHasTheMapColours) {
  const OccupancyGrid grid = test_grid();
  viz::MapPicture pic(grid, {.pixels_per_cell = 3.0});
  const auto raster = embedded_png(pic.svg_string(), "map-raster");
  ASSERT_TRUE(raster.has_value());
  const int k = raster->width / 20;
  ASSERT_GE(k, 1);
  ASSERT_EQ(raster->height, 10 * k);
  auto cell = [&](int ix, int iy) { return raster->at(ix * k, (9 - iy) * k); };  // y up: row 0 is iy = 9
  expect_colour_near(cell(3, 2), {0, 0, 0, 255}, 0, "occupied");
  expect_colour_near(cell(0, 0), {255, 255, 255, 255}, 0, "free");
  expect_colour_near(cell(10, 7), {128, 128, 128, 255}, 0, "unknown");
  expect_colour_near(cell(15, 5), {179, 179, 179, 255}, 0, "30 % occupied");
}

TEST(MapPictureSvg, ElevationLegendShowsTheHeightRange) {
  starnav::ElevationMap em(geometry(12, 8, 0.25));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 12; ++x)
      if (x != 5) em.set_height(x, y, 1.25 + 2.25 * (x + y) / 18.0);
  viz::MapPicture pic(em);
  const std::string svg = pic.svg_string();
  EXPECT_EQ(check_xml(svg), "");
  EXPECT_NE(svg.find(">height [m]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">1.25 to 3.50 m</text>"), std::string::npos);
  EXPECT_NE(svg.find("id=\"height-ramp\""), std::string::npos);
  EXPECT_EQ(count_of(svg, "<stop "), 11u);
  // Unobserved column 5 is transparent in the embedded raster.
  const auto raster = embedded_png(svg, "map-raster");
  ASSERT_TRUE(raster.has_value());
  const int k = raster->width / 12;
  EXPECT_EQ(raster->at(5 * k, 0).a, 0);
  EXPECT_EQ(raster->at(4 * k, 0).a, 255);
}

TEST(MapPictureSvg, RejectsBadInput) {
  viz::MapPicture pic(test_grid());
  const double nan = std::nan("");
  EXPECT_THROW(pic.add_polyline({{1.0, 2.0}, {nan, 3.0}}), starnav::Error);
  EXPECT_THROW(pic.add_points({{std::numeric_limits<double>::infinity(), 0.0}}), starnav::Error);
  EXPECT_THROW(pic.add_polyline({{1.0, 2.0}}, {.width_px = 0.0}), starnav::Error);
  EXPECT_THROW(pic.add_cells({{1, 1}}, {}, 1.5), starnav::Error);
  EXPECT_THROW(pic.add_circle({1.0, 1.0}, -1.0), starnav::Error);
  EXPECT_THROW(pic.add_pose(Pose2(0, 0, nan), 1.0), starnav::Error);
  EXPECT_THROW(pic.add_text({0, 0}, "x", {.size_px = 0.0}), starnav::Error);
  EXPECT_THROW(viz::MapPicture(test_grid(), {.font_px = -1.0}), starnav::Error);
  EXPECT_THROW(viz::MapPicture(test_grid(), {.pixels_per_cell = nan}), starnav::Error);
  EXPECT_THROW(viz::MapPicture(OccupancyGrid{}), starnav::Error);  // no cells
  EXPECT_THROW((void)pic.render_png({2.0, 300}), starnav::Error);    // both sizes
  EXPECT_THROW((void)pic.render_png(viz::RasterSize::width(5)), starnav::Error);  // no room for the map
  EXPECT_THROW((void)pic.render_png(viz::RasterSize::per_cell(5000.0)), starnav::Error);  // too large
  try {
    pic.write_svg("/nonexistent-dir/x.svg");
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.file(), "/nonexistent-dir/x.svg");
  }
  // Bad input left the picture as it was: only valid layers were added (none).
  EXPECT_EQ(count_of(pic.svg_string(), "<polyline"), 0u);
}

// ------------------------------------------------------------------------------------------ PNG

TEST(MapPicturePng, WrittenAndReadBackWithExpectedSizeAndColours) {
  starnav::test::ScratchDir dir;
  const OccupancyGrid grid = test_grid();
  viz::MapPicture pic(grid, {.title = "png"});
  const viz::RasterSize size = viz::RasterSize::per_cell(6);
  const viz::PictureLayout L = pic.png_layout(size);
  EXPECT_DOUBLE_EQ(L.plot_w, 120.0);
  EXPECT_DOUBLE_EQ(L.plot_h, 60.0);
  const std::string path = dir.file("map.png");
  pic.write_png(path, size);
  const auto png = read_png(path);
  ASSERT_TRUE(png.has_value());
  EXPECT_EQ(png->width, L.width_px);
  EXPECT_EQ(png->height, L.height_px);
  const GridGeometry& g = grid.geometry();
  auto at_cell = [&](int ix, int iy) { return pixel_at(*png, L.to_picture(g.cell_center(ix, iy))); };
  expect_colour_near(at_cell(3, 2), {0, 0, 0, 255}, 0, "occupied (3, 2)");
  expect_colour_near(at_cell(4, 2), {0, 0, 0, 255}, 0, "occupied (4, 2)");
  expect_colour_near(at_cell(0, 0), {255, 255, 255, 255}, 0, "free (0, 0)");
  expect_colour_near(at_cell(19, 9), {255, 255, 255, 255}, 0, "free (19, 9)");
  expect_colour_near(at_cell(10, 7), {128, 128, 128, 255}, 0, "unknown (10, 7)");
  expect_colour_near(at_cell(15, 5), {179, 179, 179, 255}, 0, "30 % (15, 5)");
  // Cell edges fall on pixel edges: every pixel of cell (3, 2) is black, its neighbours white.
  const Vec2 corner = L.to_picture(g.grid_to_world({1.5, 1.5}));  // top-left of cell (3, 2)
  const int cx = static_cast<int>(corner.x()), cy = static_cast<int>(corner.y());
  EXPECT_DOUBLE_EQ(corner.x(), cx);
  for (int dy = 0; dy < 6; ++dy)
    for (int dx = 0; dx < 6; ++dx) ASSERT_EQ(png->at(cx + dx, cy + dy), (viz::Rgba{0, 0, 0, 255})) << dx << "," << dy;
  EXPECT_EQ(png->at(cx - 1, cy + 2), (viz::Rgba{255, 255, 255, 255}));
  EXPECT_EQ(png->at(cx + 2, cy + 6), (viz::Rgba{255, 255, 255, 255}));
  // The page outside the plot is the background.
  EXPECT_EQ(png->at(png->width - 1, png->height - 1), (viz::Rgba{255, 255, 255, 255}));
}

TEST(MapPicturePng, LayersAreDrawnAtTheirWorldPositions) {
  const OccupancyGrid grid = test_grid();
  const GridGeometry& g = grid.geometry();
  viz::MapPicture pic(grid);
  pic.add_cells({{10, 2}, {11, 2}}, {0, 0, 255, 255}, 0.5, "cells");
  pic.add_polyline({g.cell_center(0, 8), g.cell_center(8, 8)}, {.colour = {255, 0, 0, 255}, .width_px = 4.0});
  pic.add_points({g.cell_center(17, 2)}, {.fill = {0, 160, 0, 255}, .radius_px = 4.0, .outline_px = 0.0});
  const viz::RasterSize size = viz::RasterSize::per_cell(8);
  const viz::PictureLayout L = pic.png_layout(size);
  const viz::RgbaImage img = pic.render_png(size);
  auto at_world = [&](const Vec2& w) { return pixel_at({img.width, img.height, img.rgba}, L.to_picture(w)); };
  // Blue at 50 % over white: 255 * 0.5 = 127.5 either way.
  expect_colour_near(at_world(g.cell_center(10, 2)), {128, 128, 255, 255}, 1, "cells layer");
  expect_colour_near(at_world(g.cell_center(11, 2)), {128, 128, 255, 255}, 1, "cells layer");
  expect_colour_near(at_world(g.cell_center(12, 2)), {255, 255, 255, 255}, 0, "next to the cells");
  expect_colour_near(at_world(g.cell_center(4, 8)), {255, 0, 0, 255}, 0, "line middle");
  expect_colour_near(at_world(g.cell_center(4, 6)), {255, 255, 255, 255}, 0, "away from the line");
  expect_colour_near(at_world(g.cell_center(17, 2)), {0, 160, 0, 255}, 0, "point");
}

TEST(MapPicturePng, RotatedGridIsDrawnRotated) {
  const Pose2 origin(3.0, -1.0, 0.5);
  const OccupancyGrid grid = test_grid(origin);
  const GridGeometry& g = grid.geometry();
  viz::MapPicture pic(grid);
  const viz::RasterSize size = viz::RasterSize::per_cell(10);
  const viz::PictureLayout L = pic.png_layout(size);
  const viz::RgbaImage img = pic.render_png(size);
  const Decoded d{img.width, img.height, img.rgba};
  expect_colour_near(pixel_at(d, L.to_picture(g.cell_center(3, 2))), {0, 0, 0, 255}, 0, "occupied");
  expect_colour_near(pixel_at(d, L.to_picture(g.cell_center(10, 7))), {128, 128, 128, 255}, 0, "unknown");
  expect_colour_near(pixel_at(d, L.to_picture(g.cell_center(2, 2))), {255, 255, 255, 255}, 0, "free");
  // Inside the window but outside the rotated map: the plot background.
  const Vec2 outside = g.grid_to_world({-0.3, 2.5});
  ASSERT_GT(outside.x(), L.xmin);
  expect_colour_near(pixel_at(d, L.to_picture(outside)), pic.options().plot_background, 0, "outside the map");
}

TEST(MapPicturePng, WidthIsHonouredExactly) {
  viz::MapPicture pic(test_grid(), {.title = "width"});
  for (const int w : {300, 517, 1200}) {
    const viz::RgbaImage img = pic.render_png(viz::RasterSize::width(w));
    EXPECT_EQ(img.width, w);
    const viz::PictureLayout L = pic.png_layout(viz::RasterSize::width(w));
    EXPECT_EQ(L.width_px, w);
    EXPECT_LE(L.plot_x + L.plot_w, w);
    EXPECT_NEAR(L.plot_h / L.plot_w, 0.5, 1e-9);  // the map's aspect ratio
  }
}

TEST(MapPicturePng, BigMapDrawnSmallKeepsThinWalls) {
  // A one-cell wall in a 1000-cell-wide map drawn at 0.25 px per cell still darkens its pixels.
  OccupancyGrid grid(geometry(1000, 400, 0.05), 0);
  for (int x = 0; x < 1000; ++x) grid(x, 200) = 100;
  viz::MapPicture pic(grid);
  const viz::RasterSize size = viz::RasterSize::per_cell(0.25);
  const viz::PictureLayout L = pic.png_layout(size);
  const viz::RgbaImage img = pic.render_png(size);
  const Decoded d{img.width, img.height, img.rgba};
  const Vec2 p = L.to_picture(grid.geometry().cell_center(500, 200));
  const viz::Rgba c = pixel_at(d, p);
  EXPECT_LT(c.r, 230) << "the wall vanished";
  EXPECT_GT(c.r, 100);  // averaged with the free cells around it
}

// ------------------------------------------------------------------------------------ determinism

TEST(MapPicture, SameInputsGiveTheSameBytes) {
  starnav::test::ScratchDir dir;
  auto build = [] {
    starnav::ElevationMap em(geometry(40, 30, 0.1, Pose2(0.5, -0.25, 0.3)));
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        if ((x * 7 + y * 3) % 11) em.set_height(x, y, 0.01 * x * x - 0.02 * y + std::sin(0.3 * x));
    viz::MapPicture pic(em, {.title = "determinism"});
    pic.add_polyline({{0.6, 0.0}, {2.0, 1.0}, {3.1, 2.2}}, {.colour = viz::categorical_colour(1)}, "path");
    pic.add_cells({{1, 1}, {2, 2}, {3, 3}}, viz::parse_colour("#ff000080"), 0.7, "cells");
    pic.add_text({1.0, 1.0}, "hello");
    return pic;
  };
  const viz::MapPicture a = build(), b = build();
  EXPECT_EQ(a.svg_string(), b.svg_string());
  EXPECT_EQ(a.svg_string(), a.svg_string());
  a.write_png(dir.file("a.png"));
  b.write_png(dir.file("b.png"));
  a.write_svg(dir.file("a.svg"));
  b.write_svg(dir.file("b.svg"));
  const std::string pa = starnav::test::read_text(dir.file("a.png")), pb = starnav::test::read_text(dir.file("b.png"));
  EXPECT_FALSE(pa.empty());
  EXPECT_EQ(pa, pb);
  EXPECT_EQ(starnav::test::read_text(dir.file("a.svg")), starnav::test::read_text(dir.file("b.svg")));
  EXPECT_EQ(starnav::test::read_text(dir.file("a.svg")), a.svg_string());
  // And a different input gives different bytes.
  viz::MapPicture c = build();
  c.add_points({{1.0, 1.0}});
  EXPECT_NE(a.svg_string(), c.svg_string());
}

// -------------------------------------------------------------------------------------- hillshade

namespace {

// The shade of a plane z = a x + b y (world frame) under the default light, by hand.
double plane_shade(double a, double b, bool y_down = false) {
  const double az = starnav::deg_to_rad(315.0), alt = starnav::deg_to_rad(45.0);
  const double lx = std::cos(alt) * std::sin(az), ly = (y_down ? -1.0 : 1.0) * std::cos(alt) * std::cos(az),
               lz = std::sin(alt);
  return (-a * lx - b * ly + lz) / std::sqrt(a * a + b * b + 1.0);
}

starnav::ElevationMap plane(const GridGeometry& g, double a, double b, double c) {
  starnav::ElevationMap em(g);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 w = g.cell_center(x, y);
      em.set_height(x, y, a * w.x() + b * w.y() + c);
    }
  return em;
}

}  // namespace

TEST(Hillshade, PlaneWithKnownSlopeHasAUniformShade) {
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0.0, 0.0}, {0.3, 0.0}, {-0.2, 0.5}, {1.5, -0.7}}) {
    const starnav::ElevationMap em = plane(geometry(30, 20, 0.2, Pose2(-1.0, 4.0, 0.0)), a, b, 2.0);
    const std::vector<float> shade = viz::hillshade(em);
    ASSERT_EQ(shade.size(), em.cell_count());
    const double want = std::clamp(plane_shade(a, b), 0.0, 1.0);
    for (std::size_t i = 0; i < shade.size(); ++i) ASSERT_NEAR(shade[i], want, 1e-5) << a << " " << b << " cell " << i;
  }
  // Flat ground: sin(altitude).
  const starnav::ElevationMap flat = plane(geometry(5, 5, 1.0), 0, 0, 1.0);
  EXPECT_NEAR(viz::hillshade(flat)[12], std::sin(starnav::deg_to_rad(45.0)), 1e-6);
  // A slope facing the light (rising toward the lower right, i.e. away from the upper-left light) is brighter.
  const double facing = viz::hillshade(plane(geometry(5, 5, 1.0), 0.5, -0.5, 0.0))[12];
  const double away = viz::hillshade(plane(geometry(5, 5, 1.0), -0.5, 0.5, 0.0))[12];
  EXPECT_GT(facing, std::sin(starnav::deg_to_rad(45.0)));
  EXPECT_LT(away, std::sin(starnav::deg_to_rad(45.0)));
}

TEST(Hillshade, RotatedGridsAndIndexGridsUseTheWorldSlope) {
  // The plane is given in world coordinates; the grid is rotated; the shade is the world one.
  const starnav::ElevationMap rotated = plane(geometry(25, 15, 0.5, Pose2(2.0, 1.0, 0.8)), 0.4, -0.3, 0.0);
  for (float s : viz::hillshade(rotated)) ASSERT_NEAR(s, plane_shade(0.4, -0.3), 1e-5);
  // y_down: the light still comes from the picture's upper left, which is world -y.
  const starnav::ElevationMap index = plane(geometry(10, 10, 1.0, {}, true), 0.2, 0.6, 0.0);
  for (float s : viz::hillshade(index)) ASSERT_NEAR(s, plane_shade(0.2, 0.6, true), 1e-5);
}

TEST(Hillshade, UnobservedCellsAndBadOptions) {
  starnav::ElevationMap em = plane(geometry(6, 4, 1.0), 0.3, 0.0, 0.0);
  em.clear_cell(2, 1);
  const auto shade = viz::hillshade(em);
  EXPECT_TRUE(std::isnan(shade[em.geometry().index(2, 1)]));
  // Neighbours of the hole use one-sided slopes: still the plane's shade.
  EXPECT_NEAR(shade[em.geometry().index(1, 1)], plane_shade(0.3, 0.0), 1e-6);
  EXPECT_NEAR(shade[em.geometry().index(3, 1)], plane_shade(0.3, 0.0), 1e-6);
  EXPECT_THROW(viz::hillshade(em, {.altitude_deg = 0.0}), starnav::Error);
  EXPECT_THROW(viz::hillshade(em, {.azimuth_deg = std::nan("")}), starnav::Error);
}

TEST(ElevationRaster, FlatGroundKeepsTheRampColourAndSlopesAreShaded) {
  // Flat: the range widens to 1.5 .. 2.5, the height sits mid-ramp, the shade changes nothing.
  starnav::ElevationMap flat = plane(geometry(8, 6, 0.5), 0.0, 0.0, 2.0);
  flat.clear_cell(0, 0);
  const viz::RgbaImage img = viz::elevation_raster(flat);
  const viz::Rgba mid = viz::viridis(0.5);
  for (int r = 0; r < img.height; ++r)
    for (int c = 0; c < img.width; ++c) {
      if (c == 0 && r == img.height - 1) {  // cell (0, 0) is the bottom-left pixel
        EXPECT_EQ(img.at(c, r).a, 0);
        continue;
      }
      ASSERT_EQ(img.at(c, r), mid) << c << "," << r;
    }
  // Tilted: colour = ramp(t) * ((1 - s) + s * shade / sin(alt)) at every cell.
  const starnav::ElevationMap tilted = plane(geometry(10, 10, 1.0), 0.4, 0.1, 0.0);
  viz::ElevationStyle style;
  style.hillshade_strength = 1.0;
  const viz::RgbaImage t = viz::elevation_raster(tilted, style);
  const auto range = *tilted.height_range();
  const double factor = plane_shade(0.4, 0.1) / std::sin(starnav::deg_to_rad(45.0));
  for (const Cell c : {Cell{0, 0}, Cell{4, 7}, Cell{9, 9}}) {
    const viz::Rgba ramp = viz::viridis((tilted.height_at(c.x, c.y) - range.min) / (range.max - range.min));
    const viz::Rgba got = t.at(c.x, 9 - c.y);
    EXPECT_NEAR(got.r, std::min(255.0, ramp.r * factor), 0.51);
    EXPECT_NEAR(got.g, std::min(255.0, ramp.g * factor), 0.51);
    EXPECT_NEAR(got.b, std::min(255.0, ramp.b * factor), 0.51);
  }
  // A fixed range from the style, and a bad one.
  viz::ElevationStyle fixed;
  fixed.range = starnav::HeightRange{0.0, 10.0};
  fixed.hillshade = false;
  EXPECT_EQ(viz::elevation_raster(flat, fixed).at(3, 3), viz::viridis(0.2));
  fixed.range = starnav::HeightRange{3.0, 1.0};
  EXPECT_THROW(viz::elevation_raster(flat, fixed), starnav::Error);
}

// ------------------------------------------------------------------------------ colours and parts

TEST(Colour, ParsingNamesAndRamps) {
  EXPECT_EQ(viz::parse_colour("#ff8000"), (viz::Rgba{255, 128, 0, 255}));
  EXPECT_EQ(viz::parse_colour("#F80"), (viz::Rgba{255, 136, 0, 255}));
  EXPECT_EQ(viz::parse_colour("#0000ff80"), (viz::Rgba{0, 0, 255, 128}));
  EXPECT_EQ(viz::parse_colour("White"), (viz::Rgba{255, 255, 255, 255}));
  EXPECT_EQ(viz::parse_colour("none").a, 0);
  for (const char* bad : {"", "#", "#12", "#12345", "#gg0000", "blurple", "#1234567"}) {
    try {
      (void)viz::parse_colour(bad);
      ADD_FAILURE() << bad;
    } catch (const starnav::Error& e) {
      EXPECT_EQ(e.field(), "colour");
    }
  }
  EXPECT_EQ(viz::to_hex({1, 171, 255, 7}), "#01abff");
  EXPECT_EQ(viz::with_opacity({10, 20, 30, 200}, 0.5).a, 100);
  EXPECT_EQ(viz::viridis(0.0), (viz::Rgba{0x44, 0x01, 0x54, 255}));
  EXPECT_EQ(viz::viridis(1.0), (viz::Rgba{0xfd, 0xe7, 0x25, 255}));
  EXPECT_EQ(viz::viridis(-3.0), viz::viridis(0.0));
  EXPECT_EQ(viz::viridis(std::nan("")), viz::viridis(0.0));
  // Perceptually ordered: luminance rises along the ramp.
  double last = -1.0;
  for (int i = 0; i <= 100; ++i) {
    const viz::Rgba c = viz::viridis(i / 100.0);
    const double lum = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    EXPECT_GT(lum, last - 0.6) << i;  // monotone up to rounding
    last = lum;
  }
  EXPECT_EQ(viz::occupancy_colour(0), (viz::Rgba{255, 255, 255, 255}));
  EXPECT_EQ(viz::occupancy_colour(100), (viz::Rgba{0, 0, 0, 255}));
  EXPECT_EQ(viz::occupancy_colour(-1), (viz::Rgba{128, 128, 128, 255}));
  EXPECT_EQ(viz::occupancy_colour(25), (viz::Rgba{191, 191, 191, 255}));
  EXPECT_NE(viz::categorical_colour(0), viz::categorical_colour(1));
  EXPECT_EQ(viz::categorical_colour(0), viz::categorical_colour(7));
}

TEST(Raster, Base64AndPngRoundTrip) {
  EXPECT_EQ(viz::base64_encode(""), "");
  EXPECT_EQ(viz::base64_encode("f"), "Zg==");
  EXPECT_EQ(viz::base64_encode("fo"), "Zm8=");
  EXPECT_EQ(viz::base64_encode("foo"), "Zm9v");
  EXPECT_EQ(viz::base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(viz::base64_encode(std::string("\xff\x00\x10", 3)), "/wAQ");
  viz::RgbaImage img(7, 5, {10, 20, 30, 255});
  img.set(6, 4, {200, 100, 50, 255});
  img.set(0, 0, {1, 2, 3, 4});  // not opaque: RGBA
  const auto d = decode_png(viz::encode_png(img));
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->width, 7);
  EXPECT_EQ(d->height, 5);
  EXPECT_EQ(d->rgba, img.rgba);
  img.set(0, 0, {1, 2, 3, 255});  // opaque: RGB
  const auto e = decode_png(viz::encode_png(img));
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->rgba, img.rgba);
  EXPECT_THROW(viz::encode_png(viz::RgbaImage{}), starnav::Error);
  // Blending: 50 % red over opaque white.
  viz::RgbaImage w(1, 1, {255, 255, 255, 255});
  w.blend(0, 0, {255, 0, 0, 255}, 0.5);
  expect_colour_near(w.at(0, 0), {255, 128, 128, 255}, 1, "blend");
}

TEST(Raster, FontCoversPrintableAscii) {
  using F = viz::BitmapFont;
  for (int c = 33; c < 127; ++c) {
    int ink = 0;
    for (auto row : F::glyph(static_cast<char>(c))) ink += std::popcount(static_cast<unsigned>(row));
    EXPECT_GT(ink, 0) << "no glyph for '" << static_cast<char>(c) << "'";
  }
  for (auto row : F::glyph(' ')) EXPECT_EQ(row, 0);
  EXPECT_EQ(F::glyph('\x01'), F::glyph('?'));
  EXPECT_EQ(F::glyph(static_cast<char>(0xC3)), F::glyph('?'));
  // Descenders go below the baseline, capitals do not.
  EXPECT_NE(F::glyph('g')[7] | F::glyph('g')[8], 0);
  EXPECT_EQ(F::glyph('A')[7] | F::glyph('A')[8], 0);
  // Text is drawn where asked: "8" at (10, 20) inks pixels just above the baseline.
  viz::RgbaImage img(40, 30, {255, 255, 255, 255});
  viz::Canvas cv(img);
  cv.text({10, 20}, "8", {0, 0, 0, 255});
  int dark = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      if (img.at(x, y).r == 0) {
        ++dark;
        EXPECT_GE(x, 10);
        EXPECT_LT(x, 15);
        EXPECT_GE(y, 13);
        EXPECT_LT(y, 20);
      }
  EXPECT_GT(dark, 10);
}

TEST(MapPicture, BarePictureAndBlankGeometry) {
  // No axes, scale bar, legend or title: the plot fills the picture up to a small margin.
  viz::MapPicture bare(test_grid(), {.pixels_per_cell = 4.0, .axes = false, .scale_bar = false, .legend = false});
  bare.add_polyline({{1.5, 2.5}, {3.0, 4.0}}, {}, "not shown in a legend");
  const std::string svg = bare.svg_string();
  EXPECT_EQ(check_xml(svg), "");
  EXPECT_EQ(svg.find("id=\"axes\""), std::string::npos);
  EXPECT_EQ(svg.find("id=\"scale-bar\""), std::string::npos);
  EXPECT_EQ(svg.find("id=\"legend\""), std::string::npos);
  const viz::PictureLayout L = bare.svg_layout();
  EXPECT_LE(L.width_px - L.plot_w, 16.0);
  EXPECT_LE(L.height_px - L.plot_h, 16.0);
  const viz::RgbaImage img = bare.render_png(viz::RasterSize::per_cell(2));
  EXPECT_EQ(img.width, bare.png_layout(viz::RasterSize::per_cell(2)).width_px);
  // A blank picture of a geometry: plot background only, layers on top.
  viz::MapPicture blank(geometry(10, 10, 1.0));
  blank.add_points({{5.0, 5.0}}, {}, "p");
  const std::string b = blank.svg_string();
  EXPECT_EQ(check_xml(b), "");
  EXPECT_EQ(b.find("map-raster"), std::string::npos);
  const viz::PictureLayout BL = blank.png_layout(viz::RasterSize::per_cell(10));
  const viz::RgbaImage bi = blank.render_png(viz::RasterSize::per_cell(10));
  const Decoded d{bi.width, bi.height, bi.rgba};
  expect_colour_near(pixel_at(d, BL.to_picture({1.5, 1.5})), blank.options().plot_background, 0, "blank plot");
}

TEST(Raster, SegmentsRunningFarOffTheCanvasCostWhatTheirVisiblePartCosts) {
  // A vertex at 1e300 (a wild pose in a trajectory) used to loop over 1e300 pixels of dashes and to
  // convert beyond the int range. The visible part is drawn as if the segment ended just past the
  // canvas: the same pixels as the segment cut by hand 100 pixels beyond the edge.
  const viz::Rgba ink{200, 30, 30, 255};
  for (const bool dashed : {false, true}) {
    SCOPED_TRACE(dashed ? "dashed" : "solid");
    const auto draw = [&](const std::vector<starnav::Vec2>& points) {
      viz::RgbaImage image(120, 60, {255, 255, 255, 255});
      viz::Canvas(image).stroke_polyline(points, 2.0, ink, dashed);
      return image.rgba;
    };
    // Up to the last bit of a dash end's position, so a byte may round the other way.
    const auto same = [](const std::vector<std::uint8_t>& x, const std::vector<std::uint8_t>& y) {
      if (x.size() != y.size()) return false;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (std::abs(int{x[i]} - int{y[i]}) > 1) return false;
      return true;
    };
    EXPECT_TRUE(same(draw({{10.37, 30.21}, {1e300, 30.21}}), draw({{10.37, 30.21}, {220.37, 30.21}})));
    EXPECT_TRUE(same(draw({{10.37, 30.21}, {10.37, -1e300}}), draw({{10.37, 30.21}, {10.37, -100.21}})));
    // From a wild end into the canvas: the dashes' phase there is the far end's, so only solid strokes compare.
    if (!dashed) {
      EXPECT_TRUE(same(draw({{1e300, 1e300}, {60.4, 20.8}}), draw({{260.4, 220.8}, {60.4, 20.8}})));
    }
    // Wholly off the canvas, or through it between two wild ends: finishes, paints nothing it should not.
    EXPECT_EQ(draw({{-1e300, -5.0}, {1e300, -5.0}}), draw({}));
    const std::vector<std::uint8_t> across = draw({{-1e300, -1e300}, {1e300, 1e300}});
    EXPECT_EQ(across.size(), 120u * 60u * 4u);
  }
}
