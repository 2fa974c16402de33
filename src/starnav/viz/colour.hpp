#pragma once
// Colours for pictures: 8-bit sRGB with straight (not premultiplied) alpha, the palettes starnav
// draws maps with, and a perceptually ordered ramp for heights.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace starnav::viz {

struct Rgba {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  std::uint8_t a = 255;
  friend bool operator==(const Rgba&, const Rgba&) = default;
};

// A colour channel value rounded to the nearest byte, clamped to [0, 255].
std::uint8_t channel_byte(double v);

// The same colour with its alpha multiplied by `opacity` (clamped to [0, 1]).
Rgba with_opacity(Rgba c, double opacity);

// "#rrggbb" (alpha dropped), the form SVG attributes take.
std::string to_hex(Rgba c);

// "#rgb", "#rrggbb", "#rrggbbaa" or a name (black, white, grey/gray, red, green, blue, orange,
// yellow, cyan, magenta, purple, brown, pink, sky, vermillion, none = transparent). Throws
// Error (field "colour") for anything else.
Rgba parse_colour(std::string_view text);

// Okabe & Ito's colour-blind-safe qualitative palette (without black), cycled: for telling
// several paths or robots apart.
Rgba categorical_colour(std::size_t i);

// Viridis (van der Walt & Smith, matplotlib's default, CC0), piecewise linear through 11 stops;
// t is clamped to [0, 1]; dark blue-violet at 0, yellow at 1.
Rgba viridis(double t);

// How occupancy values look: 0 free white, 100 occupied black, values between as shades of grey
// (255 * (100 - v) / 100, like RViz's map display and map_server's scale mode), unknown (-1)
// mid-grey.
struct OccupancyPalette {
  Rgba free{255, 255, 255, 255};
  Rgba occupied{0, 0, 0, 255};
  Rgba unknown{128, 128, 128, 255};
};
Rgba occupancy_colour(std::int8_t value, const OccupancyPalette& palette = {});

}  // namespace starnav::viz
