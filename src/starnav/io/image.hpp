#pragma once
// Greyscale raster I/O for map images: PGM (P2 and P5, 8 and 16 bit) and PNG (8 and 16 bit grey,
// grey+alpha, RGB, RGBA, palette). Rows are stored top row first, as in the files.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace starnav {

struct GrayImage {
  int width = 0;
  int height = 0;
  int max_value = 255;       // 255 or 65535 (PGM maxval may be anything 1..65535)
  int channels = 1;          // channels in the source file (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA)
  // For 1-channel images: the grey value. For colour images: the values map_server uses,
  // i.e. the channels averaged (alpha kept separately).
  std::vector<std::uint16_t> pixels;  // row-major, top row first
  std::vector<std::uint16_t> alpha;   // empty unless the file has an alpha channel

  std::uint16_t at(int x, int row) const { return pixels[static_cast<std::size_t>(row) * width + x]; }
};

// Every channel of an image as stored (after palette/tRNS/low-bit-depth expansion): what
// map_server-exact loaders need, since averaging colour into a GrayImage rounds.
struct RasterImage {
  int width = 0;
  int height = 0;
  int max_value = 255;                 // PNG: 255 or 65535; PGM: its maxval
  int channels = 1;                    // 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA (palette images expand to 3 or 4)
  std::vector<std::uint16_t> samples;  // interleaved, row-major, top row first

  std::uint16_t sample(int x, int row, int channel) const {
    return samples[(static_cast<std::size_t>(row) * width + x) * channels + channel];
  }
};

RasterImage read_raster_image(const std::string& path);
// PGM or PNG from bytes in memory, decided by the magic bytes; `source` names it in errors.
RasterImage parse_raster_image(std::string_view bytes, const std::string& source);
RasterImage parse_pgm_raster(std::string_view bytes, const std::string& source);
RasterImage parse_png_raster(std::string_view bytes, const std::string& source);
// Colour channels averaged (rounded to nearest) into `pixels`, alpha copied into `alpha`.
GrayImage to_gray_image(const RasterImage& raster);

// Read PGM or PNG (decided by the file's magic bytes, not its name). Throws Error naming the
// file for a missing, truncated or malformed image.
GrayImage read_gray_image(const std::string& path);
GrayImage parse_gray_image(std::string_view bytes, const std::string& source);  // PGM or PNG by magic
GrayImage parse_pgm(std::string_view bytes, const std::string& source);
GrayImage parse_png(std::string_view bytes, const std::string& source);

// Write a 1-channel image; max_value 255 gives 8 bit, 65535 gives 16 bit.
void write_pgm(const GrayImage& image, const std::string& path);  // binary P5
void write_png(const GrayImage& image, const std::string& path);
// Any channel count 1..4 (grey, grey+alpha, RGB, RGBA); max_value 255 or 65535.
void write_png_raster(const RasterImage& image, const std::string& path);

}  // namespace starnav
