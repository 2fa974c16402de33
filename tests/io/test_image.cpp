// PGM and PNG reading/writing: hand-built files with hand-known pixel values, every PNG colour
// type (built by the independent encoder in png_test_encoder.hpp), exact 16-bit round trips.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/png_test_encoder.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/image.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::bytes_of;
using test::encode_png;
using test::PngSpec;

std::vector<std::uint16_t> values(std::initializer_list<int> v) { return {v.begin(), v.end()}; }

TEST(PgmTest, AsciiP2WithCommentsEverywhereInTheHeader) {
  const std::string text =
      "P2 # magic\n"
      "# a whole comment line\n"
      "3 # width\n"
      "2\n"
      "# before maxval\n"
      "15\n"
      "0 1 2\n"
      "13  14\t15\n";
  const GrayImage img = parse_pgm(text, "hand.pgm");
  EXPECT_EQ(img.width, 3);
  EXPECT_EQ(img.height, 2);
  EXPECT_EQ(img.max_value, 15);
  EXPECT_EQ(img.channels, 1);
  EXPECT_EQ(img.pixels, values({0, 1, 2, 13, 14, 15}));
  EXPECT_TRUE(img.alpha.empty());
  EXPECT_EQ(img.at(2, 1), 15);
}

TEST(PgmTest, BinaryP5EightBitWithComment) {
  const std::string bytes = std::string("P5\n# CREATOR: hand\n4 1\n255\n") + bytes_of({0, 205, 254, 255});
  const GrayImage img = parse_pgm(bytes, "hand.pgm");
  EXPECT_EQ(img.width, 4);
  EXPECT_EQ(img.height, 1);
  EXPECT_EQ(img.max_value, 255);
  EXPECT_EQ(img.pixels, values({0, 205, 254, 255}));
}

TEST(PgmTest, BinaryP5SixteenBitIsBigEndian) {
  const std::string bytes = std::string("P5 2 2 65535\n") + bytes_of({0x01, 0x02, 0xFF, 0xFE, 0x00, 0x00, 0xFF, 0xFF});
  const GrayImage img = parse_pgm(bytes, "hand16.pgm");
  EXPECT_EQ(img.max_value, 65535);
  EXPECT_EQ(img.pixels, values({0x0102, 0xFFFE, 0, 0xFFFF}));
}

TEST(PgmTest, MaxvalAbove255UsesTwoBytesPerSample) {
  // maxval 1000 > 255: two bytes per sample even though it is not 65535.
  const std::string bytes = std::string("P5\n1 2\n1000\n") + bytes_of({0x03, 0xE8, 0x00, 0x07});
  const GrayImage img = parse_pgm(bytes, "m1000.pgm");
  EXPECT_EQ(img.max_value, 1000);
  EXPECT_EQ(img.pixels, values({1000, 7}));
}

TEST(PgmTest, RasterBytesThatLookLikeCommentsOrSpacesAreData) {
  // '#' (35), ' ' (32) and '\n' (10) inside a P5 raster are pixel values, not syntax.
  const std::string bytes = std::string("P5\n3 1\n255\n") + bytes_of({'#', ' ', '\n'});
  EXPECT_EQ(parse_pgm(bytes, "x.pgm").pixels, values({35, 32, 10}));
}

TEST(PgmTest, Faults) {
  EXPECT_THROW(parse_pgm("P6\n1 1\n255\n\x01", "a.pgm"), Error);
  EXPECT_THROW(parse_pgm("P5\n1 1\n0\n\x01", "a.pgm"), Error);
  EXPECT_THROW(parse_pgm("P5\n1 1\n65536\n\x01", "a.pgm"), Error);
  EXPECT_THROW(parse_pgm("P5\n2 2\n255\n\x01\x02\x03", "a.pgm"), Error);  // 3 of 4 bytes
  EXPECT_THROW(parse_pgm("P2\n2 2\n255\n1 2 3", "a.pgm"), Error);         // 3 of 4 samples
  EXPECT_THROW(parse_pgm("P2\n2 1\n10\n1 11", "a.pgm"), Error);           // sample above maxval
  EXPECT_THROW(parse_pgm("P2\n2 1\n10\n1 x", "a.pgm"), Error);            // not a number
  EXPECT_THROW(parse_pgm("P5\n0 4\n255\n", "a.pgm"), Error);              // zero width
  EXPECT_THROW(parse_pgm("P5\n-3 4\n255\n", "a.pgm"), Error);
  EXPECT_THROW(parse_pgm("P5\n65536 65536\n255\n\x01", "a.pgm"), Error);  // > 2^31 pixels
  EXPECT_THROW(parse_pgm("P5\n40000 40000\n255\n\x01", "a.pgm"), Error);  // huge claim, tiny file
  EXPECT_THROW(parse_pgm("P5\n99999999999 1\n255\n", "a.pgm"), Error);
  try {
    parse_pgm("P5\n1 1\n0\n\x01", "where.pgm");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("where.pgm: maxval: ", 0), 0u) << e.what();
  }
}

TEST(PgmTest, WriteThenReadRoundTripsEightAndSixteenBit) {
  test::ScratchDir dir;
  GrayImage img8;
  img8.width = 3;
  img8.height = 2;
  img8.max_value = 255;
  img8.pixels = values({0, 1, 128, 205, 254, 255});
  write_pgm(img8, dir.file("a.pgm"));
  EXPECT_EQ(test::read_text(dir.file("a.pgm")), std::string("P5\n3 2\n255\n") + bytes_of({0, 1, 128, 205, 254, 255}));
  EXPECT_EQ(read_gray_image(dir.file("a.pgm")).pixels, img8.pixels);

  GrayImage img16 = img8;
  img16.max_value = 65535;
  img16.pixels = values({0, 1, 256, 0x1234, 0xFFFE, 0xFFFF});
  write_pgm(img16, dir.file("b.pgm"));
  const GrayImage back = read_gray_image(dir.file("b.pgm"));
  EXPECT_EQ(back.max_value, 65535);
  EXPECT_EQ(back.pixels, img16.pixels);
}

TEST(PngTest, EightBitGrey) {
  PngSpec spec{3, 2, 8, 0, {bytes_of({0, 100, 255}), bytes_of({1, 2, 3})}, {}, {}};
  const GrayImage img = parse_png(encode_png(spec), "g8.png");
  EXPECT_EQ(img.width, 3);
  EXPECT_EQ(img.height, 2);
  EXPECT_EQ(img.max_value, 255);
  EXPECT_EQ(img.channels, 1);
  EXPECT_EQ(img.pixels, values({0, 100, 255, 1, 2, 3}));
}

TEST(PngTest, SixteenBitGreyIsExact) {
  PngSpec spec{2, 2, 16, 0, {bytes_of({0x01, 0x02, 0xFF, 0xFF}), bytes_of({0x00, 0x00, 0x80, 0x01})}, {}, {}};
  const GrayImage img = parse_png(encode_png(spec), "g16.png");
  EXPECT_EQ(img.max_value, 65535);
  EXPECT_EQ(img.pixels, values({0x0102, 0xFFFF, 0, 0x8001}));
}

TEST(PngTest, LowBitDepthGreyIsScaledToEightBit) {
  // 1-bit: 0 -> 0, 1 -> 255; 2-bit: v -> v * 85; 4-bit: v -> v * 17 (the PNG spec's scaling).
  PngSpec one{8, 1, 1, 0, {bytes_of({0b10100001})}, {}, {}};
  EXPECT_EQ(parse_png(encode_png(one), "b1.png").pixels, values({255, 0, 255, 0, 0, 0, 0, 255}));
  PngSpec two{4, 1, 2, 0, {bytes_of({0b00011011})}, {}, {}};
  EXPECT_EQ(parse_png(encode_png(two), "b2.png").pixels, values({0, 85, 170, 255}));
  PngSpec four{2, 1, 4, 0, {bytes_of({0x3F})}, {}, {}};
  EXPECT_EQ(parse_png(encode_png(four), "b4.png").pixels, values({51, 255}));
}

TEST(PngTest, GreyAlpha) {
  PngSpec spec{2, 1, 8, 4, {bytes_of({10, 255, 200, 0})}, {}, {}};
  const GrayImage img = parse_png(encode_png(spec), "ga.png");
  EXPECT_EQ(img.channels, 2);
  EXPECT_EQ(img.pixels, values({10, 200}));
  EXPECT_EQ(img.alpha, values({255, 0}));
}

TEST(PngTest, RgbIsAveragedAndRawChannelsAreKept) {
  PngSpec spec{2, 1, 8, 2, {bytes_of({30, 60, 90, 255, 0, 1})}, {}, {}};
  const std::string png = encode_png(spec);
  const GrayImage img = parse_png(png, "rgb.png");
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.pixels, values({60, 85}));  // (30+60+90)/3 = 60; 256/3 = 85.33 -> 85
  EXPECT_TRUE(img.alpha.empty());
  const RasterImage raster = parse_png_raster(png, "rgb.png");
  EXPECT_EQ(raster.channels, 3);
  EXPECT_EQ(raster.sample(1, 0, 0), 255);
  EXPECT_EQ(raster.sample(1, 0, 2), 1);
}

TEST(PngTest, RgbaAndSixteenBitRgb) {
  PngSpec rgba{1, 1, 8, 6, {bytes_of({10, 20, 31, 77})}, {}, {}};
  const GrayImage a = parse_png(encode_png(rgba), "rgba.png");
  EXPECT_EQ(a.channels, 4);
  EXPECT_EQ(a.pixels, values({20}));  // 61/3 = 20.33
  EXPECT_EQ(a.alpha, values({77}));
  PngSpec rgb16{1, 1, 16, 2, {bytes_of({0xFF, 0xFF, 0x00, 0x00, 0x00, 0x02})}, {}, {}};
  const GrayImage b = parse_png(encode_png(rgb16), "rgb16.png");
  EXPECT_EQ(b.max_value, 65535);
  EXPECT_EQ(b.pixels, values({21846}));  // 65537/3 = 21845.67 -> 21846
}

TEST(PngTest, PaletteExpandsToRgbAndTrnsToAlpha) {
  PngSpec spec{3, 1, 8, 3, {bytes_of({0, 1, 2})}, bytes_of({0, 0, 0, 255, 255, 255, 10, 20, 30}), {}};
  const GrayImage img = parse_png(encode_png(spec), "pal.png");
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.pixels, values({0, 255, 20}));
  spec.trns = bytes_of({255, 0});  // entry 0 opaque, entry 1 transparent, entry 2 opaque (default)
  const GrayImage with_alpha = parse_png(encode_png(spec), "palt.png");
  EXPECT_EQ(with_alpha.channels, 4);
  EXPECT_EQ(with_alpha.alpha, values({255, 0, 255}));
  // A 2-bit palette image: indices packed four to a byte.
  PngSpec packed{4, 1, 2, 3, {bytes_of({0b00011000})}, bytes_of({0, 0, 0, 90, 90, 90, 200, 200, 200}), {}};
  EXPECT_EQ(parse_png(encode_png(packed), "pal2.png").pixels, values({0, 90, 200, 0}));
}

TEST(PngTest, GreyTrnsBecomesAlpha) {
  PngSpec spec{2, 1, 8, 0, {bytes_of({7, 9})}, {}, bytes_of({0, 7})};  // grey 7 is transparent
  const GrayImage img = parse_png(encode_png(spec), "gt.png");
  EXPECT_EQ(img.channels, 2);
  EXPECT_EQ(img.pixels, values({7, 9}));
  EXPECT_EQ(img.alpha, values({0, 255}));
}

TEST(PngTest, WritePngRoundTripsEverySixteenBitValue) {
  test::ScratchDir dir;
  GrayImage img;
  img.width = 256;
  img.height = 256;
  img.max_value = 65535;
  img.pixels.resize(65536);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<std::uint16_t>(i * 40503u);
  write_png(img, dir.file("e.png"));
  const GrayImage back = read_gray_image(dir.file("e.png"));
  EXPECT_EQ(back.width, 256);
  EXPECT_EQ(back.height, 256);
  EXPECT_EQ(back.max_value, 65535);
  EXPECT_EQ(back.channels, 1);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(PngTest, WritePngEightBitAndNonSquare) {
  test::ScratchDir dir;
  GrayImage img;
  img.width = 5;
  img.height = 2;
  img.max_value = 255;
  img.pixels = values({0, 1, 2, 3, 4, 250, 251, 252, 253, 255});
  write_png(img, dir.file("n.png"));
  const GrayImage back = read_gray_image(dir.file("n.png"));
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.max_value, 255);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(PngTest, WriteRejectsInconsistentImages) {
  test::ScratchDir dir;
  GrayImage img;
  img.width = 2;
  img.height = 2;
  img.max_value = 255;
  img.pixels = values({1, 2, 3});  // one short
  EXPECT_THROW(write_png(img, dir.file("x.png")), Error);
  EXPECT_THROW(write_pgm(img, dir.file("x.pgm")), Error);
  img.pixels = values({1, 2, 3, 300});  // above max_value
  EXPECT_THROW(write_png(img, dir.file("x.png")), Error);
  img.pixels = values({1, 2, 3, 4});
  img.max_value = 1000;  // PNG holds 8 or 16 bit only
  EXPECT_THROW(write_png(img, dir.file("x.png")), Error);
  EXPECT_NO_THROW(write_pgm(img, dir.file("x.pgm")));
  img.max_value = 255;
  EXPECT_THROW(write_png(img, dir.file("no_such_dir/x.png")), Error);
}

TEST(PngTest, CorruptionIsAnErrorNotACrash) {
  PngSpec spec{4,
               4,
               8,
               0,
               {bytes_of({1, 2, 3, 4}), bytes_of({5, 6, 7, 8}), bytes_of({9, 10, 11, 12}), bytes_of({13, 14, 15, 16})},
               {},
               {}};
  const std::string good = encode_png(spec);
  ASSERT_NO_THROW(parse_png(good, "good.png"));
  // Every truncation of the file must be refused (never a partial image).
  for (std::size_t n = 0; n < good.size(); ++n) EXPECT_THROW(parse_png(good.substr(0, n), "cut.png"), Error) << n;
  // Flipping any single byte after the signature breaks a CRC or the zlib stream; either way an
  // Error (ancillary-chunk CRC damage would be a warning, but this file has only critical chunks).
  for (std::size_t i = 8; i < good.size(); ++i) {
    std::string bad = good;
    bad[i] = static_cast<char>(bad[i] ^ 0x40);
    EXPECT_THROW(parse_png(bad, "flip.png"), Error) << "byte " << i;
  }
  // A huge claimed size in a tiny file is refused before allocating.
  PngSpec huge{40000, 40000, 8, 0, {std::string(40000, '\0')}, {}, {}};
  EXPECT_THROW(parse_png(encode_png(huge), "huge.png"), Error);
}

TEST(ImageTest, ReadDispatchesOnMagicBytesNotName) {
  test::ScratchDir dir;
  PngSpec spec{1, 1, 8, 0, {bytes_of({42})}, {}, {}};
  test::write_text(dir.file("actually_png.pgm"), encode_png(spec));
  EXPECT_EQ(read_gray_image(dir.file("actually_png.pgm")).pixels, values({42}));
  test::write_text(dir.file("actually_pgm.png"), "P2 1 1 255 43\n");
  EXPECT_EQ(read_gray_image(dir.file("actually_pgm.png")).pixels, values({43}));
  test::write_text(dir.file("jpeg.png"), "\xFF\xD8\xFF\xE0 not an image we read");
  EXPECT_THROW(read_gray_image(dir.file("jpeg.png")), Error);
  test::write_text(dir.file("empty.pgm"), "");
  EXPECT_THROW(read_gray_image(dir.file("empty.pgm")), Error);
  EXPECT_THROW(read_gray_image(dir.file("missing.pgm")), Error);
  EXPECT_THROW(read_gray_image(dir.path().string()), Error);
}

TEST(ImageTest, SharedTestmapPngIsTenByTenRgb) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/ros_maps/ros1_map_server_testmap/testmap.png");
  const RasterImage img = read_raster_image(test::shared_path("datasets/ros_maps/ros1_map_server_testmap/testmap.png"));
  EXPECT_EQ(img.width, 10);
  EXPECT_EQ(img.height, 10);
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.max_value, 255);
}

}  // namespace
}  // namespace starnav
