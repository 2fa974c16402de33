#include "starnav/io/image.hpp"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/io/file_bytes.hpp"

namespace starnav {

namespace {

// Largest number of pixels an image may have (conventions: at most 2^31 cells).
constexpr std::uint64_t kMaxPixels = 2147483647ULL;
// Largest ancillary PNG chunk (text, ICC profile...) libpng may buffer; maps carry none this big.
constexpr png_alloc_size_t kMaxAncillaryChunkBytes = 16u << 20;

void check_pixel_count(std::uint64_t width, std::uint64_t height, const std::string& source) {
  if (width == 0 || height == 0)
    throw Error("image size must be positive, got " + std::to_string(width) + " x " + std::to_string(height), source, 0,
                width == 0 ? "width" : "height");
  if (width > kMaxPixels || height > kMaxPixels || width * height > kMaxPixels)
    throw Error(
        "image too large (" + std::to_string(width) + " x " + std::to_string(height) + " pixels, at most 2^31 - 1)",
        source);
}

// ---------------------------------------------------------------------------------------------
// PGM

bool is_pgm_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

class PgmScanner {
 public:
  PgmScanner(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  // Skips whitespace and `#` comments (which run to the end of the line).
  void skip_space_and_comments() {
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (is_pgm_space(c)) {
        ++pos_;
      } else if (c == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
      } else {
        break;
      }
    }
  }

  // A non-negative decimal number; `field` names it in errors.
  std::uint64_t number(const char* field) {
    skip_space_and_comments();
    if (pos_ >= bytes_.size()) throw Error("file ends before the " + std::string(field), source_, 0, field);
    const char first = bytes_[pos_];
    if (first < '0' || first > '9')
      throw Error("expected a non-negative integer, found '" + printable(first) + "'", source_, 0, field);
    std::uint64_t value = 0;
    while (pos_ < bytes_.size() && bytes_[pos_] >= '0' && bytes_[pos_] <= '9') {
      value = value * 10 + static_cast<std::uint64_t>(bytes_[pos_] - '0');
      if (value > 0xFFFFFFFFULL) throw Error("number too large", source_, 0, field);
      ++pos_;
    }
    if (pos_ < bytes_.size() && !is_pgm_space(bytes_[pos_]) && bytes_[pos_] != '#')
      throw Error("expected whitespace after the number, found '" + printable(bytes_[pos_]) + "'", source_, 0, field);
    return value;
  }

  std::size_t pos() const { return pos_; }
  void advance(std::size_t n) { pos_ += n; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  bool at_end() const { return pos_ >= bytes_.size(); }
  char peek() const { return bytes_[pos_]; }

  static std::string printable(char c) {
    if (c >= 0x20 && c < 0x7f) return std::string(1, c);
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(c));
    return buf;
  }

 private:
  std::string_view bytes_;
  const std::string& source_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------------------------
// PNG via libpng's classic API. libpng reports errors by longjmp; to keep that well defined the
// functions that call setjmp hold only trivially destructible locals and never own C++ objects:
// the caller allocates every buffer between the header pass and the pixel pass.

// Where the error callback leaves libpng's message (the error pointer of both directions).
struct PngErrorSink {
  char message[256] = {};
};

struct PngReadState {
  PngErrorSink errors;
  png_structp png = nullptr;
  png_infop info = nullptr;
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  // Header results (after the expansion transforms).
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int file_bit_depth = 0;
  int file_color_type = 0;
  int out_bit_depth = 0;
  int out_channels = 0;
  std::size_t out_rowbytes = 0;
  std::size_t file_rowbytes = 0;
};

extern "C" void starnav_png_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngErrorSink*>(png_get_error_ptr(png));
  if (sink) {
    std::snprintf(sink->message, sizeof sink->message, "%s", message ? message : "libpng error");
    for (char& c : sink->message)
      if (c == '\n' || c == '\r') c = ' ';  // errors are one line
  }
  png_longjmp(png, 1);
}

extern "C" void starnav_png_warning(png_structp, png_const_charp) {}  // warnings are not faults

extern "C" void starnav_png_read_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* state = static_cast<PngReadState*>(png_get_io_ptr(png));
  if (length > state->size - state->pos) png_error(png, "file is truncated");
  std::memcpy(out, state->data + state->pos, length);
  state->pos += length;
}

// Reads the header and sets up expansion to 8 or 16 bit grey / grey+alpha / RGB / RGBA.
bool png_read_header_and_setup(PngReadState* state) {
  if (setjmp(png_jmpbuf(state->png))) return false;
  png_set_read_fn(state->png, state, starnav_png_read_memory);
  png_read_info(state->png, state->info);
  state->width = png_get_image_width(state->png, state->info);
  state->height = png_get_image_height(state->png, state->info);
  state->file_bit_depth = png_get_bit_depth(state->png, state->info);
  state->file_color_type = png_get_color_type(state->png, state->info);
  state->file_rowbytes = png_get_rowbytes(state->png, state->info);
  if (state->file_color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(state->png);
  if (state->file_color_type == PNG_COLOR_TYPE_GRAY && state->file_bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(state->png);
  if (png_get_valid(state->png, state->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(state->png);
  png_set_interlace_handling(state->png);
  png_read_update_info(state->png, state->info);
  state->out_bit_depth = png_get_bit_depth(state->png, state->info);
  state->out_channels = png_get_channels(state->png, state->info);
  state->out_rowbytes = png_get_rowbytes(state->png, state->info);
  return true;
}

bool png_read_pixels(PngReadState* state, png_bytepp rows) {
  if (setjmp(png_jmpbuf(state->png))) return false;
  png_read_image(state->png, rows);
  png_read_end(state->png, nullptr);
  return true;
}

struct PngWriteState {
  PngErrorSink errors;
  png_structp png = nullptr;
  png_infop info = nullptr;
};

bool png_write_all(PngWriteState* state, std::FILE* file, png_uint_32 width, png_uint_32 height, int bit_depth,
                   int color_type, png_bytepp rows) {
  if (setjmp(png_jmpbuf(state->png))) return false;
  png_init_io(state->png, file);
  png_set_IHDR(state->png, state->info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(state->png, state->info);
  png_write_image(state->png, rows);
  png_write_end(state->png, nullptr);
  return true;
}

void check_writable_gray(const GrayImage& image, const std::string& path) {
  check_pixel_count(static_cast<std::uint64_t>(std::max(image.width, 0)),
                    static_cast<std::uint64_t>(std::max(image.height, 0)), path);
  if (image.max_value < 1 || image.max_value > 65535)
    throw Error("max_value must be 1..65535, got " + std::to_string(image.max_value), path, 0, "max_value");
  const std::size_t expected = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (image.pixels.size() != expected)
    throw Error("image has " + std::to_string(image.pixels.size()) + " pixels, expected " + std::to_string(expected),
                path);
  for (const std::uint16_t v : image.pixels)
    if (v > image.max_value)
      throw Error("pixel value " + std::to_string(v) + " exceeds max_value " + std::to_string(image.max_value), path);
}

// Walks the chunk list before libpng sees it: libpng allocates an ancillary chunk's claimed
// length before reading it, so a few bytes claiming a 2 GB text chunk must be refused here.
void check_png_chunk_lengths(std::string_view bytes, const std::string& source) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t pos = 8;  // after the signature
  while (pos + 8 <= bytes.size()) {
    const std::uint64_t length = (std::uint64_t{p[pos]} << 24) | (std::uint64_t{p[pos + 1]} << 16) |
                                 (std::uint64_t{p[pos + 2]} << 8) | std::uint64_t{p[pos + 3]};
    std::string type;
    for (std::size_t i = 4; i < 8; ++i) {
      const unsigned char c = p[pos + i];
      type += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
    }
    const std::uint64_t left = bytes.size() - pos - 8;
    if (length > 0x7FFFFFFFu || length + 4 > left)  // data + CRC must fit in the file
      throw Error("corrupt PNG: chunk '" + type + "' claims " + std::to_string(length) + " bytes but only " +
                      std::to_string(left) + " remain (truncated file?)",
                  source);
    pos += 12 + static_cast<std::size_t>(length);
    if (type == "IEND") return;
  }
  // A missing IEND or a partial chunk header is left to libpng, which reports it as truncation.
}

}  // namespace

// ---------------------------------------------------------------------------------------------

RasterImage parse_pgm_raster(std::string_view bytes, const std::string& source) {
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '2' && bytes[1] != '5'))
    throw Error("not a PGM file (magic must be P2 or P5)", source, 0, "magic");
  const bool binary = bytes[1] == '5';
  PgmScanner scan(bytes, source);
  scan.advance(2);
  if (!scan.at_end() && !is_pgm_space(scan.peek()) && scan.peek() != '#')
    throw Error("not a PGM file (magic must be P2 or P5)", source, 0, "magic");
  const std::uint64_t width = scan.number("width");
  const std::uint64_t height = scan.number("height");
  const std::uint64_t maxval = scan.number("maxval");
  check_pixel_count(width, height, source);
  if (maxval < 1 || maxval > 65535)
    throw Error("maxval must be 1..65535, got " + std::to_string(maxval), source, 0, "maxval");

  const std::uint64_t pixel_count = width * height;
  RasterImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.max_value = static_cast<int>(maxval);
  image.channels = 1;

  if (binary) {
    // Exactly one whitespace byte separates maxval from the raster.
    if (scan.at_end()) throw Error("file ends before the pixel data", source, 0, "pixels");
    if (!is_pgm_space(scan.peek()))
      throw Error("expected one whitespace byte before the pixel data", source, 0, "maxval");
    scan.advance(1);
    const std::uint64_t bytes_per_sample = maxval > 255 ? 2 : 1;
    const std::uint64_t needed = pixel_count * bytes_per_sample;
    if (scan.remaining() < needed)
      throw Error("truncated pixel data: " + std::to_string(width) + " x " + std::to_string(height) + " needs " +
                      std::to_string(needed) + " bytes, file has " + std::to_string(scan.remaining()),
                  source, 0, "pixels");
    image.samples.resize(pixel_count);
    const auto* raster = reinterpret_cast<const unsigned char*>(bytes.data() + scan.pos());
    for (std::uint64_t i = 0; i < pixel_count; ++i) {
      const std::uint16_t v = bytes_per_sample == 2
                                  ? static_cast<std::uint16_t>((raster[2 * i] << 8) | raster[2 * i + 1])  // big-endian
                                  : raster[i];
      if (v > maxval)
        throw Error(
            "pixel " + std::to_string(i) + " value " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval),
            source, 0, "pixels");
      image.samples[i] = v;
    }
  } else {
    // Every ASCII sample takes at least one digit and one separator (except the last): a tiny
    // file cannot claim a huge raster.
    if (pixel_count > scan.remaining() / 2 + 1)
      throw Error("truncated pixel data: " + std::to_string(width) + " x " + std::to_string(height) +
                      " samples cannot fit in the " + std::to_string(scan.remaining()) + " bytes left",
                  source, 0, "pixels");
    image.samples.resize(pixel_count);
    for (std::uint64_t i = 0; i < pixel_count; ++i) {
      scan.skip_space_and_comments();
      if (scan.at_end())
        throw Error(
            "truncated pixel data: " + std::to_string(i) + " of " + std::to_string(pixel_count) + " samples present",
            source, 0, "pixels");
      const std::uint64_t v = scan.number("pixels");
      if (v > maxval)
        throw Error(
            "pixel " + std::to_string(i) + " value " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval),
            source, 0, "pixels");
      image.samples[i] = static_cast<std::uint16_t>(v);
    }
  }
  return image;
}

RasterImage parse_png_raster(std::string_view bytes, const std::string& source) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    throw Error("not a PNG file (bad signature)", source, 0, "signature");

  check_png_chunk_lengths(bytes, source);

  PngReadState state;
  state.data = reinterpret_cast<const unsigned char*>(bytes.data());
  state.size = bytes.size();
  state.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state.errors, starnav_png_error, starnav_png_warning);
  if (!state.png) throw Error("cannot initialise libpng", source);
  state.info = png_create_info_struct(state.png);
  if (!state.info) {
    png_destroy_read_struct(&state.png, nullptr, nullptr);
    throw Error("cannot initialise libpng", source);
  }
  // Also caps what a compressed text or ICC chunk may inflate to.
  png_set_chunk_malloc_max(state.png, kMaxAncillaryChunkBytes);
  // Destroys the libpng structures on every way out of this function.
  struct Cleanup {
    PngReadState& s;
    ~Cleanup() { png_destroy_read_struct(&s.png, &s.info, nullptr); }
  } cleanup{state};

  if (!png_read_header_and_setup(&state)) throw Error(std::string("corrupt PNG: ") + state.errors.message, source);
  check_pixel_count(state.width, state.height, source);
  if (state.out_bit_depth != 8 && state.out_bit_depth != 16)
    throw Error("unsupported PNG bit depth " + std::to_string(state.out_bit_depth), source, 0, "bit_depth");
  if (state.out_channels < 1 || state.out_channels > 4)
    throw Error("unsupported PNG channel count " + std::to_string(state.out_channels), source, 0, "channels");
  // Deflate cannot compress better than about 1032:1, so a tiny file cannot hold a huge raster:
  // refuse before allocating. (+1 per row for the filter byte.)
  const std::uint64_t raw_bytes = (static_cast<std::uint64_t>(state.file_rowbytes) + 1) * state.height;
  if (raw_bytes > static_cast<std::uint64_t>(bytes.size()) * 1032 + 4096)
    throw Error("truncated or corrupt PNG: " + std::to_string(state.width) + " x " + std::to_string(state.height) +
                    " pixels cannot be stored in " + std::to_string(bytes.size()) + " bytes",
                source);

  // The decoded rows and the samples kept from them are what the compressed data inflates to.
  const std::uint64_t decoded = static_cast<std::uint64_t>(state.out_rowbytes) * state.height +
                                std::uint64_t{2} * state.width * state.height * state.out_channels;
  if (decoded > kMaxDecompressedBytes)
    throw Error(std::to_string(state.width) + " x " + std::to_string(state.height) + " pixels of " +
                    std::to_string(state.out_channels) + " channel(s) decode to " + std::to_string(decoded) +
                    " bytes, more than the " + std::to_string(kMaxDecompressedBytes) + " decompressed data may take",
                source, 0, "IHDR");

  std::vector<unsigned char> buffer(state.out_rowbytes * state.height);
  std::vector<png_bytep> rows(state.height);
  for (png_uint_32 r = 0; r < state.height; ++r)
    rows[r] = buffer.data() + static_cast<std::size_t>(r) * state.out_rowbytes;
  if (!png_read_pixels(&state, rows.data())) throw Error(std::string("corrupt PNG: ") + state.errors.message, source);

  RasterImage image;
  image.width = static_cast<int>(state.width);
  image.height = static_cast<int>(state.height);
  image.channels = state.out_channels;
  image.max_value = state.out_bit_depth == 16 ? 65535 : 255;
  const std::size_t sample_count = static_cast<std::size_t>(state.width) * state.height * state.out_channels;
  image.samples.resize(sample_count);
  const std::size_t samples_per_row = static_cast<std::size_t>(state.width) * state.out_channels;
  for (std::size_t r = 0; r < state.height; ++r) {
    const unsigned char* row = rows[r];
    std::uint16_t* out = image.samples.data() + r * samples_per_row;
    if (state.out_bit_depth == 16) {
      for (std::size_t i = 0; i < samples_per_row; ++i)
        out[i] = static_cast<std::uint16_t>((row[2 * i] << 8) | row[2 * i + 1]);  // PNG is big-endian
    } else {
      for (std::size_t i = 0; i < samples_per_row; ++i) out[i] = row[i];
    }
  }
  return image;
}

RasterImage parse_raster_image(std::string_view bytes, const std::string& source) {
  if (bytes.empty()) throw Error("empty file, not an image", source);
  if (bytes.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) == 0)
    return parse_png_raster(bytes, source);
  if (bytes[0] == 'P') return parse_pgm_raster(bytes, source);
  throw Error("unrecognised image format (expected PGM P2/P5 or PNG)", source, 0, "magic");
}

RasterImage read_raster_image(const std::string& path) {
  const InputFileScope reading_path(path);
  // The magic, and for a PNG its IHDR chunk (the size, depth and colour type), decide before the
  // rest is read: a file that is no image, or a PNG whose pixels decode to more than
  // kMaxDecompressedBytes, costs its first bytes only.
  const auto check_head = [&](std::string_view head, std::uint64_t /*size*/) {
    if (head.empty()) throw Error("empty file, not an image", path);
    const bool png = head.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(head.data()), 0, 8) == 0;
    if (!png) {
      if (head[0] != 'P') throw Error("unrecognised image format (expected PGM P2/P5 or PNG)", path, 0, "magic");
      return;
    }
    if (head.size() < 26 || head.substr(12, 4) != "IHDR") return;  // libpng says what is wrong
    const auto be32 = [&](std::size_t at) {
      const auto* p = reinterpret_cast<const unsigned char*>(head.data()) + at;
      return (std::uint64_t{p[0]} << 24) | (std::uint64_t{p[1]} << 16) | (std::uint64_t{p[2]} << 8) | std::uint64_t{p[3]};
    };
    const std::uint64_t width = be32(16), height = be32(20);
    check_pixel_count(width, height, path);
    // At least one byte per pixel decoded and two per sample kept (see parse_png_raster).
    if (width * height * 3 > kMaxDecompressedBytes)
      throw Error(std::to_string(width) + " x " + std::to_string(height) + " pixels decode to more than the " +
                      std::to_string(kMaxDecompressedBytes) + " bytes decompressed data may take",
                  path, 0, "IHDR");
  };
  return parse_raster_image(read_input_file(path, kMaxInputFileBytes, 64, check_head), path);
}

GrayImage to_gray_image(const RasterImage& raster) {
  GrayImage gray;
  gray.width = raster.width;
  gray.height = raster.height;
  gray.max_value = raster.max_value;
  gray.channels = raster.channels;
  const std::size_t n = static_cast<std::size_t>(raster.width) * static_cast<std::size_t>(raster.height);
  const int c = raster.channels;
  const bool has_alpha = c == 2 || c == 4;
  const int colour_channels = has_alpha ? c - 1 : c;
  gray.pixels.resize(n);
  if (has_alpha) gray.alpha.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t* px = raster.samples.data() + i * static_cast<std::size_t>(c);
    std::uint32_t sum = 0;
    for (int k = 0; k < colour_channels; ++k) sum += px[k];
    // Average rounded to nearest; exact for grey images.
    gray.pixels[i] = static_cast<std::uint16_t>((sum + static_cast<std::uint32_t>(colour_channels) / 2) /
                                                static_cast<std::uint32_t>(colour_channels));
    if (has_alpha) gray.alpha[i] = px[c - 1];
  }
  return gray;
}

GrayImage read_gray_image(const std::string& path) { return to_gray_image(read_raster_image(path)); }
GrayImage parse_gray_image(std::string_view bytes, const std::string& source) {
  return to_gray_image(parse_raster_image(bytes, source));
}
GrayImage parse_pgm(std::string_view bytes, const std::string& source) {
  return to_gray_image(parse_pgm_raster(bytes, source));
}
GrayImage parse_png(std::string_view bytes, const std::string& source) {
  return to_gray_image(parse_png_raster(bytes, source));
}

void write_pgm(const GrayImage& image, const std::string& path) {
  check_writable_gray(image, path);
  std::string out = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n" +
                    std::to_string(image.max_value) + "\n";
  const bool two_bytes = image.max_value > 255;
  out.reserve(out.size() + image.pixels.size() * (two_bytes ? 2 : 1));
  for (const std::uint16_t v : image.pixels) {
    if (two_bytes) out.push_back(static_cast<char>(v >> 8));  // big-endian, as the PGM spec says
    out.push_back(static_cast<char>(v & 0xFF));
  }
  write_file_bytes(path, out);
}

void write_png(const GrayImage& image, const std::string& path) {
  check_writable_gray(image, path);
  RasterImage raster;
  raster.width = image.width;
  raster.height = image.height;
  raster.max_value = image.max_value;
  raster.channels = 1;
  raster.samples = image.pixels;
  write_png_raster(raster, path);
}

void write_png_raster(const RasterImage& image, const std::string& path) {
  check_pixel_count(static_cast<std::uint64_t>(std::max(image.width, 0)),
                    static_cast<std::uint64_t>(std::max(image.height, 0)), path);
  if (image.max_value != 255 && image.max_value != 65535)
    throw Error("PNG output needs max_value 255 (8 bit) or 65535 (16 bit), got " + std::to_string(image.max_value),
                path, 0, "max_value");
  if (image.channels < 1 || image.channels > 4)
    throw Error("PNG output needs 1 to 4 channels, got " + std::to_string(image.channels), path, 0, "channels");
  const std::size_t samples_per_row = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.channels);
  if (image.samples.size() != samples_per_row * static_cast<std::size_t>(image.height))
    throw Error("image has " + std::to_string(image.samples.size()) + " samples, expected " +
                    std::to_string(samples_per_row * static_cast<std::size_t>(image.height)),
                path);
  for (const std::uint16_t v : image.samples)
    if (v > image.max_value)
      throw Error("sample value " + std::to_string(v) + " exceeds max_value " + std::to_string(image.max_value), path);

  const bool sixteen = image.max_value == 65535;
  const std::size_t rowbytes = samples_per_row * (sixteen ? 2 : 1);
  std::vector<unsigned char> buffer(rowbytes * static_cast<std::size_t>(image.height));
  for (std::size_t i = 0; i < image.samples.size(); ++i) {
    if (sixteen) {
      buffer[2 * i] = static_cast<unsigned char>(image.samples[i] >> 8);  // PNG is big-endian
      buffer[2 * i + 1] = static_cast<unsigned char>(image.samples[i] & 0xFF);
    } else {
      buffer[i] = static_cast<unsigned char>(image.samples[i]);
    }
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (std::size_t r = 0; r < rows.size(); ++r) rows[r] = buffer.data() + r * rowbytes;
  static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGB_ALPHA};

  // Encoded in memory, then written by the one output layer (whole or not at all).
  char* buffer_bytes = nullptr;
  std::size_t buffer_size = 0;
  std::FILE* file = ::open_memstream(&buffer_bytes, &buffer_size);
  if (!file) throw Error(std::string("cannot encode: ") + std::strerror(errno), path);
  struct FreeBuffer {
    char*& p;
    ~FreeBuffer() { std::free(p); }
  } free_buffer{buffer_bytes};
  PngWriteState state;
  state.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state.errors, starnav_png_error, starnav_png_warning);
  if (state.png) state.info = png_create_info_struct(state.png);
  const bool ok =
      state.png && state.info &&
      png_write_all(&state, file, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height),
                    sixteen ? 16 : 8, kColorTypes[image.channels - 1], rows.data());
  png_destroy_write_struct(&state.png, &state.info);
  const bool closed = std::fclose(file) == 0;
  if (!ok)
    throw Error(std::string("cannot write PNG: ") + (state.errors.message[0] ? state.errors.message : "libpng error"),
                path);
  if (!closed) throw Error("cannot encode PNG", path);
  write_file_atomically(path, std::string_view(buffer_bytes, buffer_size));
}

}  // namespace starnav
