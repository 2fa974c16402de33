// The malformed-file corpus of the map and image readers (tests/data/bad/, files with the prefixes
// movingai_, scen_, ros_, pgm_, png_): every file must fail with a starnav::Error whose what() is
// one line starting with the faulty file's path and naming the problem. Nothing may crash, hang
// or return a map. Other prefixes in that folder belong to other readers' tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/image.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/io/ros_map.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

enum class Reader { MovingAiMap, MovingAiScenario, RosMap, Image };

struct BadFile {
  const char* name;  // under tests/data/bad/
  Reader reader;
  const char* contains;          // a substring the message must contain (the field or the problem)
  const char* blamed = nullptr;  // the file the error must name, when not `name` itself
};

const BadFile kBadFiles[] = {
    // MovingAI maps
    {"movingai_wrong_row_length.map", Reader::MovingAiMap, ":6: map: map row 1 has 3 characters, width is 4"},
    {"movingai_bad_char.map", Reader::MovingAiMap, ":6: map: invalid terrain character 'x' at column 3"},
    {"movingai_missing_height.map", Reader::MovingAiMap, ":2: height: expected 'height N'"},
    {"movingai_height_zero.map", Reader::MovingAiMap, ":2: height: must be positive"},
    {"movingai_negative_width.map", Reader::MovingAiMap, ":3: width: expected a positive integer, found '-4'"},
    {"movingai_width_not_a_number.map", Reader::MovingAiMap, ":3: width: expected a positive integer"},
    {"movingai_too_few_rows.map", Reader::MovingAiMap, ":7: map: file ends after 2 of 3 map rows"},
    {"movingai_extra_row.map", Reader::MovingAiMap, ":8: map: unexpected text after the 3 map rows"},
    {"movingai_bad_type_line.map", Reader::MovingAiMap, ":1: type: expected 'type octile'"},
    {"movingai_missing_map_line.map", Reader::MovingAiMap, ":4: map: expected 'map'"},
    {"movingai_huge_dimensions.map", Reader::MovingAiMap, ":2: height: map too large"},
    {"movingai_empty.map", Reader::MovingAiMap, ":1: type: empty file"},
    {"movingai_hex_width.map", Reader::MovingAiMap, ":3: width: expected a positive integer, found '0x5'"},
    // MovingAI scenarios
    {"scen_bad_version.map.scen", Reader::MovingAiScenario, ":1: version: expected 'version 1'"},
    {"scen_missing_version.map.scen", Reader::MovingAiScenario, ":1: version:"},
    {"scen_too_few_fields.map.scen", Reader::MovingAiScenario, ":2: expected 9 tab-separated fields"},
    {"scen_start_outside.map.scen", Reader::MovingAiScenario, ":2: start_x: start x 5 outside the map width 5"},
    {"scen_goal_not_a_number.map.scen", Reader::MovingAiScenario, ":2: goal_y: expected a non-negative integer"},
    {"scen_negative_length.map.scen", Reader::MovingAiScenario, ":2: optimal_length:"},
    {"scen_length_not_a_number.map.scen", Reader::MovingAiScenario, ":2: optimal_length: expected a non-negative"},
    {"scen_blank_line_inside.map.scen", Reader::MovingAiScenario, ":4: blank line 3 inside the problem list"},
    {"scen_hex_start.map.scen", Reader::MovingAiScenario, ":2: start_x: expected a non-negative integer"},
    // map_server YAML
    {"ros_missing_resolution.yaml", Reader::RosMap, ": resolution: required key is missing"},
    {"ros_negative_resolution.yaml", Reader::RosMap, ":2: resolution: must be positive"},
    {"ros_resolution_not_a_number.yaml", Reader::RosMap, ":2: resolution: expected a number, found 'fine'"},
    {"ros_missing_image_key.yaml", Reader::RosMap, ": image: required key is missing"},
    {"ros_image_not_found.yaml", Reader::RosMap, ": image: image file"},
    {"ros_truncated.yaml", Reader::RosMap, ": pixels: truncated pixel data", "ros_truncated.pgm"},
    {"ros_bad_origin.yaml", Reader::RosMap, ":3: origin: must be a list of 3 numbers"},
    {"ros_origin_not_finite.yaml", Reader::RosMap, ":3: origin: must be finite"},
    {"ros_thresholds_inverted.yaml", Reader::RosMap, ": free_thresh: free_thresh (0.65) must be below occupied_thresh"},
    {"ros_occupied_thresh_above_one.yaml", Reader::RosMap, ":5: occupied_thresh: must be in 0..1"},
    {"ros_bad_mode.yaml", Reader::RosMap, ":7: mode: must be trinary, scale or raw"},
    {"ros_bad_negate.yaml", Reader::RosMap, ":4: negate: must be 0, 1, true or false"},
    {"ros_yaml_syntax.yaml", Reader::RosMap, "YAML syntax error"},
    {"ros_duplicate_key.yaml", Reader::RosMap, ":7: resolution: duplicate key"},
    {"ros_resolution_hex.yaml", Reader::RosMap, ":2: resolution: expected a number, found '0x10'"},
    {"ros_not_a_mapping.yaml", Reader::RosMap, "YAML top level must be a mapping"},
    // Aliases: nine nested levels of ten (10^9 nodes expanded) and an alias inside its own anchor.
    {"ros_alias_bomb.yaml", Reader::RosMap, ":13: holds more than 200000 YAML nodes once its aliases are expanded"},
    {"ros_alias_cycle.yaml", Reader::RosMap, ":4: origin[2]: an alias inside the node its anchor names"},
    {"ros_truncated.pgm", Reader::Image, ": pixels: truncated pixel data"},
    // PGM
    {"pgm_bad_magic.pgm", Reader::Image, ": magic: not a PGM file"},
    {"pgm_maxval_zero.pgm", Reader::Image, ": maxval: maxval must be 1..65535, got 0"},
    {"pgm_maxval_too_large.pgm", Reader::Image, ": maxval: maxval must be 1..65535, got 70000"},
    {"pgm_truncated_header.pgm", Reader::Image, ": height: file ends before the height"},
    {"pgm_huge_dimensions.pgm", Reader::Image, ": pixels: truncated pixel data: 40000 x 40000"},
    {"pgm_too_many_pixels.pgm", Reader::Image, "image too large"},
    {"pgm_ascii_bad_sample.pgm", Reader::Image, ": pixels: expected whitespace after the number"},
    {"pgm_value_above_maxval.pgm", Reader::Image, ": pixels: pixel 1 value 16 exceeds maxval 15"},
    {"pgm_zero_width.pgm", Reader::Image, ": width: image size must be positive"},
    {"pgm_truncated_16bit.pgm", Reader::Image, ": pixels: truncated pixel data"},
    // PNG
    {"png_corrupt.png", Reader::Image, "corrupt PNG: bad adaptive filter value"},
    {"png_bad_crc.png", Reader::Image, "corrupt PNG: IHDR: CRC error"},
    {"png_truncated.png", Reader::Image, "corrupt PNG: chunk 'IDAT' claims 28 bytes but only 24 remain"},
    {"png_bad_signature.png", Reader::Image, "unrecognised image format"},
    {"png_huge_dimensions.png", Reader::Image, "IHDR: 40000 x 40000 pixels decode to more than the 1073741824 bytes"},
    {"png_too_many_pixels.png", Reader::Image, "image too large"},
    {"png_huge_text_chunk.png", Reader::Image, "corrupt PNG: chunk 'tEXt' claims 2000000000 bytes"},
    {"png_bad_zlib_data.png", Reader::Image, "corrupt PNG: IDAT: invalid"},
    {"png_invalid_bit_depth.png", Reader::Image, "corrupt PNG: Invalid IHDR data"},
    {"png_zero_width.png", Reader::Image, "width: image size must be positive, got 0 x 4"},
};

void read_with(Reader reader, const std::string& path) {
  switch (reader) {
    case Reader::MovingAiMap:
      read_movingai_map(path);
      break;
    case Reader::MovingAiScenario:
      read_movingai_scenario(path);
      break;
    case Reader::RosMap:
      read_ros_map(path);
      break;
    case Reader::Image:
      read_gray_image(path);
      break;
  }
}

TEST(BadFilesTest, EachFileFailsWithAOneLineErrorNamingTheFileAndTheProblem) {
  for (const BadFile& bad : kBadFiles) {
    SCOPED_TRACE(bad.name);
    const std::string path = test::test_data(std::string("bad/") + bad.name);
    ASSERT_TRUE(fs::exists(path));
    const std::string blamed = test::test_data(std::string("bad/") + (bad.blamed ? bad.blamed : bad.name));
    try {
      read_with(bad.reader, path);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(blamed, 0), 0u) << what;
      EXPECT_EQ(e.file(), blamed);
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.find('\r'), std::string::npos) << what;
      EXPECT_NE(what.find(bad.contains), std::string::npos) << what;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a starnav::Error: " << e.what();
    }
  }
}

TEST(BadFilesTest, TableCoversEveryFileWithOurPrefixes) {
  std::set<std::string> listed;
  for (const BadFile& bad : kBadFiles) {
    EXPECT_TRUE(listed.insert(bad.name).second) << "listed twice: " << bad.name;
  }
  std::size_t ours = 0;
  for (const auto& entry : fs::directory_iterator(test::test_data("bad"))) {
    const std::string name = entry.path().filename().string();
    bool our_prefix = false;
    for (const char* prefix : {"movingai_", "scen_", "ros_", "pgm_", "png_"})
      if (name.rfind(prefix, 0) == 0) our_prefix = true;
    if (!our_prefix) continue;
    ++ours;
    EXPECT_EQ(listed.count(name), 1u) << name << " has no row in kBadFiles";
  }
  EXPECT_EQ(ours, listed.size());
  EXPECT_GE(ours, 20u);
}

// Every prefix of good files is either still good (a .map may lose its final newline) or a
// clean Error naming the file: no crash, no hang, no partial map.
TEST(BadFilesTest, EveryTruncationOfGoodFilesIsHandled) {
  test::ScratchDir dir;
  GrayImage image;
  image.width = 3;
  image.height = 2;
  image.max_value = 65535;
  image.pixels = {0, 1, 2, 300, 40000, 65535};
  write_pgm(image, dir.file("good16.pgm"));
  write_png(image, dir.file("good16.png"));
  image.max_value = 255;
  image.pixels = {0, 1, 2, 30, 40, 255};
  write_pgm(image, dir.file("good8.pgm"));
  write_png(image, dir.file("good8.png"));
  struct Good {
    std::string source;
    Reader reader;
    std::size_t droppable_tail;  // bytes that may be cut without harm
  };
  const std::vector<Good> goods = {
      {test::test_data("movingai_tiny.map"), Reader::MovingAiMap, 1},
      {dir.file("good16.pgm"), Reader::Image, 0},
      {dir.file("good16.png"), Reader::Image, 0},
      {dir.file("good8.pgm"), Reader::Image, 0},
      {dir.file("good8.png"), Reader::Image, 0},
  };
  for (const Good& good : goods) {
    const std::string text = test::read_text(good.source);
    ASSERT_FALSE(text.empty());
    ASSERT_NO_THROW(read_with(good.reader, good.source));
    for (std::size_t n = 0; n < text.size(); ++n) {
      const std::string_view cut = std::string_view(text).substr(0, n);
      try {
        // In memory: the same parsers the file readers use, without a file per cut.
        if (good.reader == Reader::MovingAiMap)
          parse_movingai_map(cut, "cut");
        else
          parse_gray_image(cut, "cut");
        EXPECT_GE(n + good.droppable_tail, text.size()) << good.source << " cut at " << n << " was accepted";
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("cut", 0), 0u) << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace starnav
