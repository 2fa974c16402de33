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

// Read PGM or PNG (decided by the file's magic bytes, not its name). Throws Error naming the
// file for a missing, truncated or malformed image.
GrayImage read_gray_image(const std::string& path);
GrayImage parse_pgm(std::string_view bytes, const std::string& source);
GrayImage parse_png(std::string_view bytes, const std::string& source);

// Write a 1-channel image; max_value 255 gives 8 bit, 65535 gives 16 bit.
void write_pgm(const GrayImage& image, const std::string& path);  // binary P5
void write_png(const GrayImage& image, const std::string& path);

}  // namespace starnav
