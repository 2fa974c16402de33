#include "starnav/viz/colour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav::viz {

namespace {


int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

struct NamedColour {
  std::string_view name;
  Rgba colour;
};

constexpr std::array<NamedColour, 18> kNamed{{
    {"black", {0, 0, 0, 255}},
    {"white", {255, 255, 255, 255}},
    {"grey", {128, 128, 128, 255}},
    {"gray", {128, 128, 128, 255}},
    {"red", {213, 0, 0, 255}},
    {"green", {0, 158, 115, 255}},
    {"blue", {0, 114, 178, 255}},
    {"orange", {230, 159, 0, 255}},
    {"yellow", {240, 228, 66, 255}},
    {"cyan", {0, 190, 210, 255}},
    {"magenta", {204, 0, 204, 255}},
    {"purple", {128, 64, 160, 255}},
    {"brown", {140, 86, 45, 255}},
    {"pink", {204, 121, 167, 255}},
    {"sky", {86, 180, 233, 255}},
    {"vermillion", {213, 94, 0, 255}},
    {"none", {0, 0, 0, 0}},
    {"transparent", {0, 0, 0, 0}},
}};

// Okabe & Ito (2008), "Color Universal Design", without black.
constexpr std::array<Rgba, 7> kCategorical{{
    {213, 94, 0, 255},    // vermillion
    {0, 114, 178, 255},   // blue
    {0, 158, 115, 255},   // bluish green
    {230, 159, 0, 255},   // orange
    {204, 121, 167, 255}, // reddish purple
    {86, 180, 233, 255},  // sky blue
    {240, 228, 66, 255},  // yellow
}};

// Viridis sampled at t = 0, 0.1, ..., 1.
constexpr std::array<Rgba, 11> kViridis{{
    {0x44, 0x01, 0x54, 255},
    {0x48, 0x24, 0x75, 255},
    {0x41, 0x44, 0x87, 255},
    {0x35, 0x5f, 0x8d, 255},
    {0x2a, 0x78, 0x8e, 255},
    {0x21, 0x91, 0x8c, 255},
    {0x22, 0xa8, 0x84, 255},
    {0x44, 0xbf, 0x70, 255},
    {0x7a, 0xd1, 0x51, 255},
    {0xbd, 0xdf, 0x26, 255},
    {0xfd, 0xe7, 0x25, 255},
}};

}  // namespace

std::uint8_t channel_byte(double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); }

Rgba with_opacity(Rgba c, double opacity) {
  if (!(opacity > 0.0)) opacity = 0.0;  // also NaN
  c.a = channel_byte(c.a * std::min(opacity, 1.0));
  return c;
}

std::string to_hex(Rgba c) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s = "#";
  for (std::uint8_t v : {c.r, c.g, c.b}) {
    s.push_back(kDigits[v >> 4]);
    s.push_back(kDigits[v & 15]);
  }
  return s;
}

Rgba parse_colour(std::string_view text) {
  const std::string shown(text);
  if (!text.empty() && text.front() == '#') {
    const std::string_view h = text.substr(1);
    std::array<int, 8> d{};
    bool ok = h.size() == 3 || h.size() == 6 || h.size() == 8;
    for (std::size_t i = 0; ok && i < h.size(); ++i) ok = (d[i] = hex_digit(h[i])) >= 0;
    if (!ok) throw Error("'" + shown + "' is not a colour (#rgb, #rrggbb, #rrggbbaa or a name)", {}, 0, "colour");
    if (h.size() == 3)
      return {static_cast<std::uint8_t>(d[0] * 17), static_cast<std::uint8_t>(d[1] * 17),
              static_cast<std::uint8_t>(d[2] * 17), 255};
    Rgba c{static_cast<std::uint8_t>(d[0] * 16 + d[1]), static_cast<std::uint8_t>(d[2] * 16 + d[3]),
           static_cast<std::uint8_t>(d[4] * 16 + d[5]), 255};
    if (h.size() == 8) c.a = static_cast<std::uint8_t>(d[6] * 16 + d[7]);
    return c;
  }
  std::string lower(text);
  for (char& ch : lower) ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
  for (const auto& n : kNamed)
    if (n.name == lower) return n.colour;
  throw Error("'" + shown + "' is not a colour (#rgb, #rrggbb, #rrggbbaa or a name)", {}, 0, "colour");
}

Rgba categorical_colour(std::size_t i) { return kCategorical[i % kCategorical.size()]; }

Rgba viridis(double t) {
  if (!(t > 0.0)) t = 0.0;  // also NaN
  if (t > 1.0) t = 1.0;
  const double x = t * 10.0;
  const auto i = static_cast<std::size_t>(std::min(9.0, std::floor(x)));
  const double f = x - static_cast<double>(i);
  const Rgba a = kViridis[i], b = kViridis[i + 1];
  return {channel_byte(a.r + (b.r - a.r) * f), channel_byte(a.g + (b.g - a.g) * f), channel_byte(a.b + (b.b - a.b) * f), 255};
}

Rgba occupancy_colour(std::int8_t value, const OccupancyPalette& palette) {
  if (value < 0) return palette.unknown;
  const double t = std::min<int>(value, 100) / 100.0;  // 0 free .. 1 occupied
  const Rgba f = palette.free, o = palette.occupied;
  return {channel_byte(f.r + (o.r - f.r) * t), channel_byte(f.g + (o.g - f.g) * t), channel_byte(f.b + (o.b - f.b) * t),
          channel_byte(f.a + (o.a - f.a) * t)};
}

}  // namespace starnav::viz
