#include "starnav/viz/raster.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav::viz {

// ---------------------------------------------------------------------------------------------
// RgbaImage

RgbaImage::RgbaImage(int w, int h, Rgba fill) : width(w), height(h) {
  if (w < 0 || h < 0) throw Error("image size must not be negative", {}, 0, "image");
  rgba.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  for (std::size_t i = 0; i < rgba.size(); i += 4) {
    rgba[i] = fill.r;
    rgba[i + 1] = fill.g;
    rgba[i + 2] = fill.b;
    rgba[i + 3] = fill.a;
  }
}

void RgbaImage::blend(int x, int y, Rgba c, double coverage) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const double sa = c.a / 255.0 * std::clamp(coverage, 0.0, 1.0);
  if (sa <= 0.0) return;
  std::uint8_t* p = &rgba[offset(x, y)];
  if (sa >= 1.0) {  // opaque: replaces
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
    p[3] = 255;
    return;
  }
  const double da = p[3] / 255.0;
  const double oa = sa + da * (1.0 - sa);
  auto mix = [&](std::uint8_t s, std::uint8_t d) {
    const double v = (s * sa + d * da * (1.0 - sa)) / oa;
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
  };
  p[0] = mix(c.r, p[0]);
  p[1] = mix(c.g, p[1]);
  p[2] = mix(c.b, p[2]);
  p[3] = static_cast<std::uint8_t>(std::lround(oa * 255.0));
}

bool RgbaImage::opaque() const {
  for (std::size_t i = 3; i < rgba.size(); i += 4)
    if (rgba[i] != 255) return false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// PNG

namespace {

// libpng reports errors by longjmp; the function that calls setjmp holds only trivially
// destructible locals, and every C++ object it touches lives in its caller.
struct PngWriteState {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::string* out = nullptr;
  char message[256] = {};
};

void png_error_handler(png_structp png, png_const_charp msg) {
  auto* state = static_cast<PngWriteState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", msg ? msg : "libpng error");
  png_longjmp(png, 1);
}
void png_warning_handler(png_structp, png_const_charp) {}

void png_write_to_string(png_structp png, png_bytep data, png_size_t length) {
  auto* state = static_cast<PngWriteState*>(png_get_io_ptr(png));
  state->out->append(reinterpret_cast<const char*>(data), length);
}
void png_flush_nothing(png_structp) {}

bool png_encode_rows(PngWriteState* state, int width, int height, bool with_alpha, png_bytepp rows) {
  if (setjmp(png_jmpbuf(state->png))) return false;
  png_set_write_fn(state->png, state, png_write_to_string, png_flush_nothing);
  png_set_IHDR(state->png, state->info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               with_alpha ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(state->png, 6);
  png_set_rows(state->png, state->info, rows);
  png_write_png(state->png, state->info, PNG_TRANSFORM_IDENTITY, nullptr);
  return true;
}

}  // namespace

std::string encode_png(const RgbaImage& image) {
  if (image.width <= 0 || image.height <= 0) throw Error("cannot encode an empty image as PNG", {}, 0, "image");
  const bool with_alpha = !image.opaque();
  const int channels = with_alpha ? 4 : 3;
  std::vector<std::uint8_t> packed;
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  if (with_alpha) {
    for (int y = 0; y < image.height; ++y)
      rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.rgba.data() + image.offset(0, y));
  } else {
    packed.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3);
    for (std::size_t i = 0, j = 0; i < image.rgba.size(); i += 4, j += 3) {
      packed[j] = image.rgba[i];
      packed[j + 1] = image.rgba[i + 1];
      packed[j + 2] = image.rgba[i + 2];
    }
    for (int y = 0; y < image.height; ++y)
      rows[static_cast<std::size_t>(y)] =
          packed.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) * channels;
  }
  std::string out;
  PngWriteState state;
  state.out = &out;
  state.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, png_error_handler, png_warning_handler);
  if (!state.png) throw Error("libpng: cannot create a write struct", {}, 0, "image");
  state.info = png_create_info_struct(state.png);
  bool ok = state.info != nullptr;
  if (ok) ok = png_encode_rows(&state, image.width, image.height, with_alpha, rows.data());
  png_destroy_write_struct(&state.png, state.info ? &state.info : nullptr);
  if (!ok) throw Error(std::string("libpng: ") + (state.message[0] ? state.message : "cannot encode"), {}, 0, "image");
  return out;
}

void write_png_file(const RgbaImage& image, const std::string& path) { write_file_atomically(path, encode_png(image)); }

std::string base64_encode(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (static_cast<std::uint8_t>(bytes[i]) << 16) | (static_cast<std::uint8_t>(bytes[i + 1]) << 8) |
                            static_cast<std::uint8_t>(bytes[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(kAlphabet[(v >> 6) & 63]);
    out.push_back(kAlphabet[v & 63]);
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t v = static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i])) << 16;
    if (rest == 2) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(rest == 2 ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The bitmap font. One glyph per line: the character, then its rows top to bottom ('#' ink),
// 7 rows above the baseline and up to 2 below.

namespace {

constexpr std::string_view kFontSource = R"FONT(
  ..... ..... ..... ..... ..... ..... .....
! ..#.. ..#.. ..#.. ..#.. ..#.. ..... ..#..
" .#.#. .#.#. ..... ..... ..... ..... .....
# .#.#. .#.#. ##### .#.#. ##### .#.#. .#.#.
$ ..#.. .#### #.#.. .###. ..#.# ####. ..#..
% ##... ##..# ...#. ..#.. .#... #..## ...##
& .##.. #..#. #.#.. .#... #.#.# #..#. .##.#
' ..#.. ..#.. ..... ..... ..... ..... .....
( ...#. ..#.. .#... .#... .#... ..#.. ...#.
) .#... ..#.. ...#. ...#. ...#. ..#.. .#...
* ..... ..#.. #.#.# .###. #.#.# ..#.. .....
+ ..... ..#.. ..#.. ##### ..#.. ..#.. .....
, ..... ..... ..... ..... ..... ..#.. ..#.. .#...
- ..... ..... ..... ##### ..... ..... .....
. ..... ..... ..... ..... ..... .##.. .##..
/ ..... ....# ...#. ..#.. .#... #.... .....
0 .###. #...# #..## #.#.# ##..# #...# .###.
1 ..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###.
2 .###. #...# ....# ...#. ..#.. .#... #####
3 ##### ...#. ..#.. ...#. ....# #...# .###.
4 ...#. ..##. .#.#. #..#. ##### ...#. ...#.
5 ##### #.... ####. ....# ....# #...# .###.
6 ..##. .#... #.... ####. #...# #...# .###.
7 ##### ....# ...#. ..#.. .#... .#... .#...
8 .###. #...# #...# .###. #...# #...# .###.
9 .###. #...# #...# .#### ....# ...#. .##..
: ..... .##.. .##.. ..... .##.. .##.. .....
; ..... .##.. .##.. ..... .##.. ..#.. .#...
< ...#. ..#.. .#... #.... .#... ..#.. ...#.
= ..... ..... ##### ..... ##### ..... .....
> .#... ..#.. ...#. ....# ...#. ..#.. .#...
? .###. #...# ....# ...#. ..#.. ..... ..#..
@ .###. #...# ....# .##.# #.#.# #.#.# .###.
A .###. #...# #...# ##### #...# #...# #...#
B ####. #...# #...# ####. #...# #...# ####.
C .###. #...# #.... #.... #.... #...# .###.
D ###.. #..#. #...# #...# #...# #..#. ###..
E ##### #.... #.... ####. #.... #.... #####
F ##### #.... #.... ####. #.... #.... #....
G .###. #...# #.... #.### #...# #...# .####
H #...# #...# #...# ##### #...# #...# #...#
I .###. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
J ..### ...#. ...#. ...#. ...#. #..#. .##..
K #...# #..#. #.#.. ##... #.#.. #..#. #...#
L #.... #.... #.... #.... #.... #.... #####
M #...# ##.## #.#.# #.#.# #...# #...# #...#
N #...# #...# ##..# #.#.# #..## #...# #...#
O .###. #...# #...# #...# #...# #...# .###.
P ####. #...# #...# ####. #.... #.... #....
Q .###. #...# #...# #...# #.#.# #..#. .##.#
R ####. #...# #...# ####. #.#.. #..#. #...#
S .#### #.... #.... .###. ....# ....# ####.
T ##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
U #...# #...# #...# #...# #...# #...# .###.
V #...# #...# #...# #...# #...# .#.#. ..#..
W #...# #...# #...# #.#.# #.#.# #.#.# .#.#.
X #...# #...# .#.#. ..#.. .#.#. #...# #...#
Y #...# #...# .#.#. ..#.. ..#.. ..#.. ..#..
Z ##### ....# ...#. ..#.. .#... #.... #####
[ .###. .#... .#... .#... .#... .#... .###.
\ ..... #.... .#... ..#.. ...#. ....# .....
] .###. ...#. ...#. ...#. ...#. ...#. .###.
^ ..#.. .#.#. #...# ..... ..... ..... .....
_ ..... ..... ..... ..... ..... ..... #####
` .#... ..#.. ..... ..... ..... ..... .....
a ..... ..... .###. ....# .#### #...# .####
b #.... #.... #.##. ##..# #...# #...# ####.
c ..... ..... .###. #.... #.... #...# .###.
d ....# ....# .##.# #..## #...# #...# .####
e ..... ..... .###. #...# ##### #.... .###.
f ..##. .#..# .#... ###.. .#... .#... .#...
g ..... ..... .#### #...# #...# .#### ....# #...# .###.
h #.... #.... #.##. ##..# #...# #...# #...#
i ..#.. ..... .##.. ..#.. ..#.. ..#.. .###.
j ...#. ..... ..##. ...#. ...#. ...#. ...#. #..#. .##..
k #.... #.... #..#. #.#.. ##... #.#.. #..#.
l .##.. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
m ..... ..... ##.#. #.#.# #.#.# #.#.# #.#.#
n ..... ..... #.##. ##..# #...# #...# #...#
o ..... ..... .###. #...# #...# #...# .###.
p ..... ..... ####. #...# #...# #...# ####. #.... #....
q ..... ..... .#### #...# #...# #...# .#### ....# ....#
r ..... ..... #.##. ##..# #.... #.... #....
s ..... ..... .#### #.... .###. ....# ####.
t .#... .#... ###.. .#... .#... .#..# ..##.
u ..... ..... #...# #...# #...# #..## .##.#
v ..... ..... #...# #...# #...# .#.#. ..#..
w ..... ..... #...# #...# #.#.# #.#.# .#.#.
x ..... ..... #...# .#.#. ..#.. .#.#. #...#
y ..... ..... #...# #...# #...# .#### ....# #...# .###.
z ..... ..... ##### ...#. ..#.. .#... #####
{ ...#. ..#.. ..#.. .#... ..#.. ..#.. ...#.
| ..#.. ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
} .#... ..#.. ..#.. ...#. ..#.. ..#.. .#...
~ ..... ..... .#... #.#.# ...#. ..... .....
)FONT";

using Glyph = std::array<std::uint8_t, 9>;

struct FontTable {
  std::array<Glyph, 128> glyphs{};
  FontTable() {
    std::size_t pos = 0;
    while (pos < kFontSource.size()) {
      std::size_t end = kFontSource.find('\n', pos);
      if (end == std::string_view::npos) end = kFontSource.size();
      const std::string_view line = kFontSource.substr(pos, end - pos);
      pos = end + 1;
      if (line.size() < 2) continue;
      const auto c = static_cast<unsigned char>(line[0]);
      Glyph g{};
      std::size_t row = 0;
      for (std::size_t i = 2; i + 5 <= line.size() && row < g.size(); i += 6, ++row) {
        std::uint8_t bits = 0;
        for (std::size_t k = 0; k < 5; ++k)
          if (line[i + k] == '#') bits = static_cast<std::uint8_t>(bits | (1u << (4 - k)));
        g[row] = bits;
      }
      if (c < 128) glyphs[c] = g;
    }
  }
};

const FontTable& font_table() {
  static const FontTable table;
  return table;
}

}  // namespace

const std::array<std::uint8_t, 9>& BitmapFont::glyph(char c) {
  const auto u = static_cast<unsigned char>(c);
  const FontTable& t = font_table();
  if (u < 32 || u > 126) return t.glyphs[static_cast<unsigned char>('?')];
  return t.glyphs[u];
}

// ---------------------------------------------------------------------------------------------
// Canvas

namespace {

double clamp01(double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); }

// floor and ceil of a pixel coordinate, clamped to +-2^30 (NaN to the low end): a picture is under
// 32768 pixels a side, so a clamped value is off the canvas and no conversion overflows.
constexpr double kFarPixel = 1073741824.0;
int clamp_px(double v, double (*to_whole)(double)) {
  if (!(v > -kFarPixel)) return -static_cast<int>(kFarPixel);
  if (v >= kFarPixel) return static_cast<int>(kFarPixel);
  return static_cast<int>(to_whole(v));
}
int floor_px(double v) { return clamp_px(v, [](double x) { return std::floor(x); }); }
int ceil_px(double v) { return clamp_px(v, [](double x) { return std::ceil(x); }); }
int round_px(double v) { return clamp_px(v, [](double x) { return static_cast<double>(std::lround(x)); }); }

// The part [t0, t1] of the segment a + t (b - a), t in [0, 1], inside the box [lo, hi]
// (Liang-Barsky); false when none is.
bool clip_segment(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    const double p[2] = {-d[k], d[k]}, q[2] = {a[k] - lo[k], hi[k] - a[k]};
    for (int side = 0; side < 2; ++side) {
      if (p[side] == 0.0) {
        if (q[side] < 0.0) return false;  // parallel to this edge and outside it
        continue;
      }
      const double t = q[side] / p[side];
      if (p[side] < 0.0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
  }
  return t0 <= t1;
}

// The visible part p-q of the segment a-b in the box, both ends computed from the original end
// nearer to the box (from a far end every digit the near one needs would be lost); t0 is where p
// lies on a-b. False when nothing of it is visible, or when both ends were too far for the
// rounding to place it.
bool visible_part(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi, Vec2& p, Vec2& q, double& t0) {
  const Vec2 centre = (lo + hi) / 2.0;
  double u0 = 0.0, u1 = 1.0;
  if ((a - centre).cwiseAbs().maxCoeff() <= (b - centre).cwiseAbs().maxCoeff()) {
    if (!clip_segment(a, b, lo, hi, u0, u1)) return false;
    p = a + (b - a) * u0;
    q = a + (b - a) * u1;
    t0 = u0;
  } else {
    if (!clip_segment(b, a, lo, hi, u0, u1)) return false;
    p = b + (a - b) * u1;
    q = b + (a - b) * u0;
    t0 = 1.0 - u1;
  }
  const Vec2 slack = Vec2::Constant(1.0);
  const auto near = [&](const Vec2& v) { return (v.array() >= (lo - slack).array()).all() && (v.array() <= (hi + slack).array()).all(); };
  return near(p) && near(q);
}

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  double t = len2 > 0.0 ? (p - a).dot(ab) / len2 : 0.0;
  t = clamp01(t);
  return (p - (a + t * ab)).norm();
}

}  // namespace

Canvas::Canvas(RgbaImage& image) : image_(image) { reset_clip(); }

void Canvas::set_clip(double x0, double y0, double x1, double y1) {
  cx0_ = std::max(0, floor_px(x0));
  cy0_ = std::max(0, floor_px(y0));
  cx1_ = std::min(image_.width, ceil_px(x1));
  cy1_ = std::min(image_.height, ceil_px(y1));
}

void Canvas::reset_clip() {
  cx0_ = cy0_ = 0;
  cx1_ = image_.width;
  cy1_ = image_.height;
}

void Canvas::fill_rect(double x0, double y0, double x1, double y1, Rgba c) {
  if (x1 < x0) std::swap(x0, x1);
  if (y1 < y0) std::swap(y0, y1);
  const int ix0 = std::max(cx0_, floor_px(x0));
  const int iy0 = std::max(cy0_, floor_px(y0));
  const int ix1 = std::min(cx1_, ceil_px(x1));
  const int iy1 = std::min(cy1_, ceil_px(y1));
  for (int y = iy0; y < iy1; ++y) {
    const double cy = std::min(y + 1.0, y1) - std::max<double>(y, y0);
    for (int x = ix0; x < ix1; ++x) {
      const double cx = std::min(x + 1.0, x1) - std::max<double>(x, x0);
      image_.blend(x, y, c, clamp01(cx) * clamp01(cy));
    }
  }
}

void Canvas::stroke_polyline(const std::vector<Vec2>& points, double width, Rgba c, bool dashed) {
  if (points.empty() || !(width > 0.0)) return;
  const double half = width / 2.0;
  const int w = cx1_ - cx0_, h = cy1_ - cy0_;
  if (w <= 0 || h <= 0) return;
  coverage_.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  std::vector<std::size_t> touched;
  auto paint_segment = [&](const Vec2& a, const Vec2& b) {
    if (!a.allFinite() || !b.allFinite()) return;
    const int x0 = std::max(cx0_, floor_px(std::min(a.x(), b.x()) - half - 1));
    const int x1 = std::min(cx1_, ceil_px(std::max(a.x(), b.x()) + half + 1));
    const int y0 = std::max(cy0_, floor_px(std::min(a.y(), b.y()) - half - 1));
    const int y1 = std::min(cy1_, ceil_px(std::max(a.y(), b.y()) + half + 1));
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const double d = distance_to_segment({x + 0.5, y + 0.5}, a, b);
        const double cov = clamp01(half + 0.5 - d);
        if (cov <= 0.0) continue;
        const std::size_t i = static_cast<std::size_t>(y - cy0_) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x - cx0_);
        const auto v = static_cast<std::uint8_t>(std::lround(cov * 255.0));
        if (coverage_[i] == 0) touched.push_back(i);
        coverage_[i] = std::max(coverage_[i], v);
      }
    }
  };
  // Segments are cut to the clip box grown by the stroke's reach, so that a segment running far
  // off the canvas (a wild pose in a trajectory) costs what its visible part costs.
  const Vec2 lo(cx0_ - half - 2.0, cy0_ - half - 2.0), hi(cx1_ + half + 2.0, cy1_ + half + 2.0);
  if (points.size() == 1) {
    paint_segment(points[0], points[0]);
  } else if (!dashed) {
    for (std::size_t i = 1; i < points.size(); ++i) {
      Vec2 p, q;
      double t0 = 0.0;
      if (points[i - 1].allFinite() && points[i].allFinite() && visible_part(points[i - 1], points[i], lo, hi, p, q, t0))
        paint_segment(p, q);
    }
  } else {
    // Dashes of 4 widths with gaps of 2 widths (at least 3 and 2 pixels), continued across vertices.
    const double dash = std::max(3.0, 4.0 * width), gap = std::max(2.0, 2.0 * width), period = dash + gap;
    double phase = 0.0;  // position within the dash + gap period
    for (std::size_t i = 1; i < points.size(); ++i) {
      const Vec2 a = points[i - 1], b = points[i];
      const double len = std::hypot(b.x() - a.x(), b.y() - a.y());  // no overflow of the squares at 1e300
      if (!std::isfinite(len)) continue;
      Vec2 p, q;
      double t0 = 0.0;
      if (len > 0.0 && visible_part(a, b, lo, hi, p, q, t0)) {
        // The pattern enters the visible part where the whole segment would have it.
        const double end = (q - p).norm();
        double at = std::fmod(phase + t0 * len, period), s = 0.0;
        while (s < end) {
          const bool on = at < dash;
          const double step = std::min(end - s, on ? dash - at : period - at);
          if (on) paint_segment(p + (q - p) * (s / end), p + (q - p) * ((s + step) / end));
          s += step;
          at += step;
          if (at >= period) at -= period;
        }
      }
      phase = std::fmod(phase + len, period);
    }
  }
  std::sort(touched.begin(), touched.end());  // deterministic order (blending is per pixel anyway)
  for (const std::size_t i : touched) {
    const int x = cx0_ + static_cast<int>(i % static_cast<std::size_t>(w));
    const int y = cy0_ + static_cast<int>(i / static_cast<std::size_t>(w));
    image_.blend(x, y, c, coverage_[i] / 255.0);
  }
}

void Canvas::fill_disc(const Vec2& centre, double radius, Rgba c) {
  if (!centre.allFinite() || !(radius > 0.0)) return;
  const int x0 = std::max(cx0_, floor_px(centre.x() - radius - 1));
  const int x1 = std::min(cx1_, ceil_px(centre.x() + radius + 1));
  const int y0 = std::max(cy0_, floor_px(centre.y() - radius - 1));
  const int y1 = std::min(cy1_, ceil_px(centre.y() + radius + 1));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const double d = (Vec2(x + 0.5, y + 0.5) - centre).norm();
      const double cov = clamp01(radius + 0.5 - d);
      if (cov > 0.0) image_.blend(x, y, c, cov);
    }
}

void Canvas::stroke_circle(const Vec2& centre, double radius, double width, Rgba c) {
  if (!centre.allFinite() || !(radius > 0.0) || !(width > 0.0)) return;
  const double half = width / 2.0;
  const double outer = radius + half + 1;
  const int x0 = std::max(cx0_, floor_px(centre.x() - outer));
  const int x1 = std::min(cx1_, ceil_px(centre.x() + outer));
  const int y0 = std::max(cy0_, floor_px(centre.y() - outer));
  const int y1 = std::min(cy1_, ceil_px(centre.y() + outer));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const double d = std::abs((Vec2(x + 0.5, y + 0.5) - centre).norm() - radius);
      const double cov = clamp01(half + 0.5 - d);
      if (cov > 0.0) image_.blend(x, y, c, cov);
    }
}

void Canvas::fill_convex_polygon(const std::vector<Vec2>& points, Rgba c) {
  if (points.size() < 3) return;
  double minx = points[0].x(), maxx = minx, miny = points[0].y(), maxy = miny;
  for (const Vec2& p : points) {
    if (!p.allFinite()) return;
    minx = std::min(minx, p.x());
    maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y());
    maxy = std::max(maxy, p.y());
  }
  // Orientation-independent: signed distances to every edge, normalised to the inside.
  double area2 = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2& a = points[i];
    const Vec2& b = points[(i + 1) % points.size()];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  if (area2 == 0.0) return;
  const double sign = area2 > 0 ? 1.0 : -1.0;
  const int x0 = std::max(cx0_, floor_px(minx));
  const int x1 = std::min(cx1_, ceil_px(maxx));
  const int y0 = std::max(cy0_, floor_px(miny));
  const int y1 = std::min(cy1_, ceil_px(maxy));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Vec2 p(x + 0.5, y + 0.5);
      double inside = 1e9;  // distance to the nearest edge, negative outside
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec2& a = points[i];
        const Vec2& b = points[(i + 1) % points.size()];
        const Vec2 e = b - a;
        const double len = e.norm();
        if (len == 0.0) continue;
        const double d = sign * (e.x() * (p.y() - a.y()) - e.y() * (p.x() - a.x())) / len;
        inside = std::min(inside, d);
      }
      const double cov = clamp01(inside + 0.5);
      if (cov > 0.0) image_.blend(x, y, c, cov);
    }
}

void Canvas::glyph_pass(const Vec2& origin, std::string_view s, Rgba c, int scale, int dx, int dy) {
  // origin: top-left of the first glyph cell, in whole pixels
  const int ox = round_px(origin.x()) + dx;
  const int oy = round_px(origin.y()) + dy;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto& g = BitmapFont::glyph(s[i]);
    const int gx = ox + static_cast<int>(i) * BitmapFont::kAdvance * scale;
    for (int row = 0; row < 9; ++row) {
      if (!g[static_cast<std::size_t>(row)]) continue;
      for (int col = 0; col < 5; ++col) {
        if (!(g[static_cast<std::size_t>(row)] & (1u << (4 - col)))) continue;
        for (int sy = 0; sy < scale; ++sy)
          for (int sx = 0; sx < scale; ++sx) {
            const int x = gx + col * scale + sx, y = oy + row * scale + sy;
            if (x >= cx0_ && x < cx1_ && y >= cy0_ && y < cy1_) image_.blend(x, y, c, 1.0);
          }
      }
    }
  }
}

void Canvas::text(const Vec2& at, std::string_view s, Rgba c, int scale, double anchor, Rgba halo) {
  if (s.empty() || !at.allFinite()) return;
  scale = std::max(1, scale);
  const double w = text_width(s, scale);
  const Vec2 origin(at.x() - anchor * w, at.y() - BitmapFont::kAscent * scale);
  if (halo.a > 0) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dx || dy) glyph_pass(origin, s, halo, scale, dx * scale, dy * scale);
  }
  glyph_pass(origin, s, c, scale, 0, 0);
}

}  // namespace starnav::viz
