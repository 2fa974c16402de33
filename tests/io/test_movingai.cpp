// MovingAI .map and .scen: hand-written fixtures with known contents, and every benchmark file
// under ../shared/benchmarks/movingai/ parsed, checked against its own header and line counts
// (computed here from the raw text), and round-tripped.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/movingai.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

using test::error_of;

TEST(MovingAiMapTest, ParsesHandWrittenFixture) {
  const MovingAiMap map = read_movingai_map(test::test_data("movingai_tiny.map"));
  EXPECT_EQ(map.type, "octile");
  EXPECT_EQ(map.width, 5);
  EXPECT_EQ(map.height, 3);
  ASSERT_EQ(map.cells.size(), 15u);
  // Row 0 ".G@S." row 1 "OTW.." row 2 "....."
  EXPECT_EQ(map.at(0, 0), '.');
  EXPECT_EQ(map.at(1, 0), 'G');
  EXPECT_EQ(map.at(2, 0), '@');
  EXPECT_EQ(map.at(3, 0), 'S');
  EXPECT_EQ(map.at(0, 1), 'O');
  EXPECT_EQ(map.at(1, 1), 'T');
  EXPECT_EQ(map.at(2, 1), 'W');
  EXPECT_EQ(map.at(4, 2), '.');

  const OccupancyGrid grid = map.to_occupancy();
  EXPECT_TRUE(grid.geometry().y_down);
  EXPECT_EQ(grid.resolution(), 1.0);
  EXPECT_EQ(grid(0, 0), 0);
  EXPECT_EQ(grid(1, 0), 0);    // G passable
  EXPECT_EQ(grid(2, 0), 100);  // @
  EXPECT_EQ(grid(3, 0), 0);    // S passable
  EXPECT_EQ(grid(0, 1), 100);  // O
  EXPECT_EQ(grid(1, 1), 100);  // T
  EXPECT_EQ(grid(2, 1), 100);  // W
  EXPECT_EQ(grid.counts().occupied, 4u);
  EXPECT_EQ(grid.counts().free, 11u);
}

TEST(MovingAiMapTest, LineEndingsAndTrailingBlankLines) {
  const std::string lf = "type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n";
  const MovingAiMap expected = parse_movingai_map(lf, "lf.map");
  EXPECT_EQ(parse_movingai_map("type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n.@.\r\n...\r\n", "crlf.map"), expected);
  EXPECT_EQ(parse_movingai_map("type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n.@.\r\n...", "crlf_nofinal.map"),
            expected);
  EXPECT_EQ(parse_movingai_map("type octile\nheight 2\nwidth 3\nmap\n.@.\n...", "nofinal.map"), expected);
  EXPECT_EQ(parse_movingai_map(lf + "\n\n\r\n", "blanks.map"), expected);
  EXPECT_EQ(format_movingai_map(expected), lf);
}

TEST(MovingAiMapTest, FaultsNameTheLine) {
  const std::string head = "type octile\nheight 2\nwidth 3\nmap\n";
  EXPECT_EQ(error_of([&] { parse_movingai_map(head + ".@.\n..\n", "f.map"); }).rfind("f.map:6: map: ", 0), 0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map(head + ".@.\n.x.\n", "f.map"); }).rfind("f.map:6: map: ", 0), 0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map(head + ".@.\n", "f.map"); }).rfind("f.map:6: map: ", 0), 0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map(head + ".@.\n...\n...\n", "f.map"); }).rfind("f.map:7: map: ", 0), 0u);
  EXPECT_EQ(error_of([&] {
              parse_movingai_map("type octile\nwidth 3\nheight 2\nmap\n", "f.map");
            }).rfind("f.map:2: height: ", 0),
            0u);
  EXPECT_EQ(error_of([&] {
              parse_movingai_map("type octile\nheight 2\nwidth 3\nmapp\n", "f.map");
            }).rfind("f.map:4: map: ", 0),
            0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map("", "f.map"); }).rfind("f.map:1: type: ", 0), 0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map("height 2\n", "f.map"); }).rfind("f.map:1: type: ", 0), 0u);
  EXPECT_EQ(error_of([&] { parse_movingai_map("type octile\nheight 1x\n", "f.map"); }).rfind("f.map:2: height: ", 0),
            0u);
  EXPECT_EQ(error_of([&] {
              parse_movingai_map("type octile\nheight 2\nwidth 99999999999\n", "f.map");
            }).rfind("f.map:3: width: ", 0),
            0u);
  // 2^31 cells or more: refused from the header, before reading (or allocating) any row.
  EXPECT_NE(
      error_of([&] { parse_movingai_map("type octile\nheight 65536\nwidth 32768\nmap\n", "f.map"); }).find("too large"),
      std::string::npos);
  // A stray CR is not a line ending: not in a row, nor in the type word.
  EXPECT_THROW(parse_movingai_map("type octile\r\r\nheight 2\nwidth 3\nmap\n.@.\n...\n", "f.map"), Error);
  EXPECT_THROW(parse_movingai_map(head + ".\r.\n...\n", "f.map"), Error);
  // Text after the last row.
  EXPECT_THROW(parse_movingai_map(head + ".@.\n...\nx\n", "f.map"), Error);
}

TEST(MovingAiMapTest, FromOccupancyFlipsMetricGridsOnly) {
  GridGeometry g;
  g.width = 2;
  g.height = 2;
  OccupancyGrid metric(g, kFreeOccupancy);
  metric(0, 1) = 100;  // top-left in a metric (y up) grid
  metric(1, 0) = -1;   // bottom-right: unknown is not free
  const MovingAiMap m = MovingAiMap::from_occupancy(metric);
  EXPECT_EQ(std::string(m.cells.begin(), m.cells.end()), "@..@");
  const MovingAiMap round = MovingAiMap::from_occupancy(m.to_occupancy());
  EXPECT_EQ(round.cells, m.cells);  // index grids keep their rows
}

TEST(MovingAiMapTest, WriteAndReadBack) {
  test::ScratchDir dir;
  const MovingAiMap map = read_movingai_map(test::test_data("movingai_tiny.map"));
  write_movingai_map(map, dir.file("copy.map"));
  EXPECT_EQ(read_movingai_map(dir.file("copy.map")), map);
  EXPECT_EQ(test::read_text(dir.file("copy.map")), test::read_text(test::test_data("movingai_tiny.map")));
}

TEST(MovingAiScenarioTest, ThreeFlavours) {
  const std::string hog2 =
      "version 1\n"
      "0\tmaps/dao/x.map\t5\t3\t0\t0\t4\t2\t4.82843\n"
      "1\tmaps/dao/x.map\t5\t3\t4\t2\t4\t2\t0\n";
  const MovingAiScenario a = parse_movingai_scenario(hog2, "a.scen");
  EXPECT_EQ(a.version, "1");
  EXPECT_FALSE(a.space_separated);
  ASSERT_EQ(a.entries.size(), 2u);
  EXPECT_EQ(a.entries[0].map, "maps/dao/x.map");
  EXPECT_EQ(a.entries[0].map_width, 5);
  EXPECT_EQ(a.entries[0].map_height, 3);
  EXPECT_EQ(a.entries[0].goal_x, 4);
  EXPECT_EQ(a.entries[0].goal_y, 2);
  EXPECT_DOUBLE_EQ(a.entries[0].optimal_length, 4.82843);
  EXPECT_EQ(a.entries[0].optimal_length_text, "4.82843");
  EXPECT_FALSE(a.entries[1].unsolvable());  // start == goal, length 0
  EXPECT_EQ(format_movingai_scenario(a), hog2);

  const std::string bg = "version 1.0\n61 maps/bgmaps/AR.map 512 512 210 395 87 201 244.95\n";
  const MovingAiScenario b = parse_movingai_scenario(bg, "b.scen");
  EXPECT_EQ(b.version, "1.0");
  EXPECT_TRUE(b.space_separated);
  ASSERT_EQ(b.entries.size(), 1u);
  EXPECT_EQ(b.entries[0].bucket, 61);
  EXPECT_EQ(b.entries[0].start_x, 210);
  EXPECT_EQ(b.entries[0].start_y, 395);
  EXPECT_EQ(b.entries[0].optimal_length_text, "244.95");
  EXPECT_EQ(format_movingai_scenario(b), bg);

  const std::string newer = "version 1\n0\tBerlin.map\t256\t256\t248\t165\t249\t164\t2.00000000\n\n";
  const MovingAiScenario c = parse_movingai_scenario(newer, "c.scen");
  EXPECT_EQ(c.entries[0].map, "Berlin.map");
  EXPECT_EQ(c.trailing_blank_lines, 1);
  EXPECT_EQ(format_movingai_scenario(c), newer);
}

TEST(MovingAiScenarioTest, ChangedLengthIsWrittenFromTheNumber) {
  MovingAiScenario s = parse_movingai_scenario("version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\t1.41421\n", "s.scen");
  s.entries[0].optimal_length = 2.5;
  EXPECT_EQ(format_movingai_scenario(s), "version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\t2.50000000\n");
  s.entries[0].optimal_length_text.clear();
  EXPECT_EQ(format_movingai_scenario(s), "version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\t2.50000000\n");
}

TEST(MovingAiScenarioTest, UnsolvableMarker) {
  const MovingAiScenario s = parse_movingai_scenario("version 1\n0\tm.map\t4\t4\t0\t0\t3\t3\t0\n", "s.scen");
  EXPECT_TRUE(s.entries[0].unsolvable());
}

TEST(MovingAiScenarioTest, FaultsNameTheLineAndField) {
  auto err = [](const std::string& text) { return error_of([&] { parse_movingai_scenario(text, "s.scen"); }); };
  EXPECT_EQ(err("version 2\n").rfind("s.scen:1: version: ", 0), 0u);
  EXPECT_EQ(err("").rfind("s.scen:1: version: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\n").rfind("s.scen:2: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\tx\t1\t1\t1\n").rfind("s.scen:2: start_y: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t-1\t1\t1\t1\n").rfind("s.scen:2: start_y: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\tnan\n").rfind("s.scen:2: optimal_length: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\t-1\n").rfind("s.scen:2: optimal_length: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t4\t0\t1\t1\t1\n").rfind("s.scen:2: start_x: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t0\t1\t9\t1\n").rfind("s.scen:2: goal_y: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t0\t4\t0\t0\t0\t0\t1\n").rfind("s.scen:2: width: ", 0), 0u);
  EXPECT_EQ(err("version 1\n0\tm.map\t4\t4\t0\t0\t1\t1\t1\n\n0\tm.map\t4\t4\t0\t0\t1\t1\t1\n").rfind("s.scen:4: ", 0),
            0u);
}

// ---------------------------------------------------------------------------------------------
// Every benchmark file

std::vector<fs::path> benchmark_files(const std::string& extension) {
  std::vector<fs::path> files;
  const std::string root = test::shared_path("benchmarks/movingai");
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.size() > extension.size() &&
        name.compare(name.size() - extension.size(), extension.size(), extension) == 0)
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// CRLF -> LF, and a final newline where the last row had none (the street maps).
std::string normalise_line_endings(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') continue;
    out.push_back(text[i]);
  }
  if (!out.empty() && out.back() == '\r') out.back() = '\n';
  if (!out.empty() && out.back() != '\n') out.push_back('\n');
  return out;
}

// The header number `key` read straight from the text.
int header_value(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + " ", 0) == 0) return std::stoi(line.substr(key.size() + 1));
  }
  return -1;
}

TEST(MovingAiBenchmarkTest, EveryMapParsesMatchesItsHeaderAndRoundTrips) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  const std::vector<fs::path> maps = benchmark_files(".map");
  EXPECT_EQ(maps.size(), 50u);  // SOURCES.md: 50 map/scenario pairs
  for (const fs::path& path : maps) {
    SCOPED_TRACE(path.string());
    const std::string text = test::read_text(path.string());
    const MovingAiMap map = read_movingai_map(path.string());
    EXPECT_EQ(map.width, header_value(text, "width"));
    EXPECT_EQ(map.height, header_value(text, "height"));
    EXPECT_EQ(map.cells.size(), static_cast<std::size_t>(map.width) * map.height);
    // Independent count of passable characters in the raw text (after the 4 header lines).
    std::size_t header_end = 0;
    for (int i = 0; i < 4; ++i) header_end = text.find('\n', header_end) + 1;
    const std::size_t passable_in_text =
        static_cast<std::size_t>(std::count_if(text.begin() + static_cast<std::ptrdiff_t>(header_end), text.end(),
                                               [](char c) { return c == '.' || c == 'G' || c == 'S'; }));
    EXPECT_EQ(map.to_occupancy().counts().free, passable_in_text);
    EXPECT_EQ(format_movingai_map(map), normalise_line_endings(text));
  }
}

TEST(MovingAiBenchmarkTest, EveryScenarioParsesMatchesItsMapAndRoundTrips) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  const std::vector<fs::path> scens = benchmark_files(".map.scen");
  EXPECT_EQ(scens.size(), 50u);
  std::map<std::string, int> flavours;
  std::size_t total_entries = 0;
  for (const fs::path& path : scens) {
    SCOPED_TRACE(path.string());
    const std::string text = test::read_text(path.string());
    const MovingAiScenario scen = read_movingai_scenario(path.string());
    // Entry count = non-empty lines minus the version line, counted from the raw text.
    std::size_t non_empty_lines = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) ++non_empty_lines;
    EXPECT_EQ(scen.entries.size() + 1, non_empty_lines);
    total_entries += scen.entries.size();

    // The matching map: the scenario file name without ".scen".
    std::string map_path = path.string();
    map_path.resize(map_path.size() - 5);
    const MovingAiMap map = read_movingai_map(map_path);
    const std::string map_file = path.filename().string().substr(0, path.filename().string().size() - 5);
    const OccupancyGrid grid = map.to_occupancy();
    std::size_t blocked_endpoints = 0;
    for (const ScenarioEntry& e : scen.entries) {
      ASSERT_EQ(e.map_width, map.width);
      ASSERT_EQ(e.map_height, map.height);
      ASSERT_EQ(fs::path(e.map).filename().string(), map_file);
      if (grid(e.start_x, e.start_y) != 0 || grid(e.goal_x, e.goal_y) != 0) ++blocked_endpoints;
    }
    EXPECT_EQ(blocked_endpoints, 0u);  // SOURCES.md: start and goal passable on every line
    ++flavours[scen.version + (scen.space_separated ? " spaces" : " tabs")];
    EXPECT_EQ(scen.space_separated, path.parent_path().filename() == "bg512");
    EXPECT_EQ(format_movingai_scenario(scen), text);  // every scenario file here uses LF
  }
  EXPECT_EQ(flavours["1.0 spaces"], 6);
  EXPECT_EQ(flavours["1 tabs"], 44);
  EXPECT_GT(total_entries, 100000u);
}

TEST(MovingAiBenchmarkTest, KnownFacts) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  // SOURCES.md: brc201d lists 10 problems with length 0 whose start differs from the goal.
  const MovingAiScenario brc = read_movingai_scenario(test::shared_path("benchmarks/movingai/dao/brc201d.map.scen"));
  EXPECT_EQ(brc.entries.size(), 2173u);
  EXPECT_EQ(
      std::count_if(brc.entries.begin(), brc.entries.end(), [](const ScenarioEntry& e) { return e.unsolvable(); }), 10);
  // Boston_0_256 has one zero-length problem whose start equals its goal.
  const MovingAiScenario boston =
      read_movingai_scenario(test::shared_path("benchmarks/movingai/street/Boston_0_256.map.scen"));
  EXPECT_EQ(std::count_if(boston.entries.begin(), boston.entries.end(),
                          [](const ScenarioEntry& e) {
                            return e.optimal_length == 0.0 && e.start_x == e.goal_x && e.start_y == e.goal_y;
                          }),
            1);
  const MovingAiMap arena = read_movingai_map(test::shared_path("benchmarks/movingai/dao/arena.map"));
  EXPECT_EQ(arena.width, 49);
  EXPECT_EQ(arena.height, 49);
}

}  // namespace
}  // namespace starnav
