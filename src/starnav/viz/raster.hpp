#pragma once
// RGBA rasters: a pixel buffer, PNG encoding through libpng (8-bit RGBA or RGB, no time stamp or
// other varying chunks, so the same pixels always give the same bytes), base64 for data URIs,
// and a small anti-aliased painter with a built-in 5x7 bitmap font for the PNG backend of
// MapPicture.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/viz/colour.hpp"

namespace starnav::viz {

// Row-major RGBA pixels, top row first (as in image files), straight alpha.
struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // 4 bytes per pixel

  RgbaImage() = default;
  RgbaImage(int w, int h, Rgba fill = {0, 0, 0, 0});

  std::size_t offset(int x, int y) const {
    return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
  }
  Rgba at(int x, int y) const {
    const std::size_t o = offset(x, y);
    return {rgba[o], rgba[o + 1], rgba[o + 2], rgba[o + 3]};
  }
  void set(int x, int y, Rgba c) {
    const std::size_t o = offset(x, y);
    rgba[o] = c.r;
    rgba[o + 1] = c.g;
    rgba[o + 2] = c.b;
    rgba[o + 3] = c.a;
  }
  // Source-over compositing of `c` with its alpha scaled by `coverage` in [0, 1]. Ignores
  // pixels outside the image.
  void blend(int x, int y, Rgba c, double coverage = 1.0);
  bool opaque() const;  // every alpha is 255
};

// PNG bytes of the image: RGB when every pixel is opaque (smaller), RGBA otherwise; fixed zlib
// settings and no time chunk. Throws Error for an empty image or a libpng failure.
std::string encode_png(const RgbaImage& image);
// Writes encode_png(image) to `path`; throws Error naming the file when it cannot be written.
void write_png_file(const RgbaImage& image, const std::string& path);
// Standard base64 (RFC 4648, with padding).
std::string base64_encode(std::string_view bytes);

// The built-in bitmap font: 5x7 glyphs (2 more rows for descenders) in a 6 x 10 cell, printable
// ASCII; anything else is drawn as '?'.
struct BitmapFont {
  static constexpr int kAdvance = 6;     // cell width, glyph + 1 column of spacing
  static constexpr int kLineHeight = 10; // cell height: 7 rows, 2 descender rows, 1 spacing
  static constexpr int kAscent = 7;      // rows above the baseline
  // Rows (bit 4 = leftmost column) of a character's glyph: 9 rows, the last two below the
  // baseline.
  static const std::array<std::uint8_t, 9>& glyph(char c);
};

// Drawing on an RgbaImage in pixel coordinates (x right, y down, pixel (i, j) covers
// [i, i+1) x [j, j+1)), clipped to a rectangle. Shapes are anti-aliased by their exact
// coverage of each pixel centre's neighbourhood (distance-based, one-pixel ramp).
class Canvas {
 public:
  explicit Canvas(RgbaImage& image);

  // Restricts drawing to [x0, x1) x [y0, y1) (in pixels); reset_clip() to the whole image.
  void set_clip(double x0, double y0, double x1, double y1);
  void reset_clip();

  void fill_rect(double x0, double y0, double x1, double y1, Rgba c);
  // A polyline of the given width; overlapping parts are painted once (coverage is the
  // maximum over segments, then composited), so translucent lines do not darken at joints.
  void stroke_polyline(const std::vector<Vec2>& points, double width, Rgba c, bool dashed = false);
  void fill_disc(const Vec2& centre, double radius, Rgba c);
  void stroke_circle(const Vec2& centre, double radius, double width, Rgba c);
  // Convex polygon fill (cells of rotated grids, arrow heads).
  void fill_convex_polygon(const std::vector<Vec2>& points, Rgba c);
  // Text with its baseline at y; anchor 0 = start, 0.5 = middle, 1 = end; `scale` multiplies
  // the 6 x 10 font cell. A halo (outline in `halo` colour, 1 scaled pixel) when halo.a > 0.
  void text(const Vec2& at, std::string_view s, Rgba c, int scale = 1, double anchor = 0.0, Rgba halo = {0, 0, 0, 0});
  static double text_width(std::string_view s, int scale) {
    return static_cast<double>(s.size()) * BitmapFont::kAdvance * scale - (s.empty() ? 0 : scale);
  }

 private:
  void glyph_pass(const Vec2& origin, std::string_view s, Rgba c, int scale, int dx, int dy);
  RgbaImage& image_;
  int cx0_ = 0, cy0_ = 0, cx1_ = 0, cy1_ = 0;  // clip, integer pixel bounds
  std::vector<std::uint8_t> coverage_;         // scratch for stroke_polyline
};

}  // namespace starnav::viz
