#pragma once
// MovingAI grid benchmark formats (Sturtevant 2012): `.map` and `.scen` (version 1 and the
// bg512 "version 1.0" space-separated flavour). See docs/formats.md.
#include <string>
#include <string_view>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// A MovingAI map with every terrain character kept, so a map round-trips exactly.
struct MovingAiMap {
  std::string type = "octile";
  int width = 0;
  int height = 0;
  std::vector<char> cells;  // row-major, row 0 = first map row (top), as in the file

  char at(int x, int y) const { return cells[static_cast<std::size_t>(y) * width + x]; }
  // '.', 'G', 'S' are passable; '@', 'O', 'T', 'W' blocked (conventions.md).
  static bool passable(char c) { return c == '.' || c == 'G' || c == 'S'; }
  static bool valid_char(char c) { return passable(c) || c == '@' || c == 'O' || c == 'T' || c == 'W'; }

  // Index grid (resolution 1, origin 0, y_down): passable -> 0, blocked -> 100.
  OccupancyGrid to_occupancy() const;
  // Free cells (by thresholds) -> '.', everything else -> '@'.
  static MovingAiMap from_occupancy(const OccupancyGrid& grid, const OccupancyThresholds& t = {});

  friend bool operator==(const MovingAiMap&, const MovingAiMap&) = default;
};

// Parses map text; `source` names the file in errors. Accepts LF and CRLF line endings and a
// missing final newline. Throws Error(FILE:LINE: FIELD: ...) on any fault.
MovingAiMap parse_movingai_map(std::string_view text, const std::string& source);
MovingAiMap read_movingai_map(const std::string& path);
std::string format_movingai_map(const MovingAiMap& map);  // LF line endings
void write_movingai_map(const MovingAiMap& map, const std::string& path);

struct ScenarioEntry {
  int bucket = 0;
  std::string map;  // as written in the file (may be a path)
  int map_width = 0;
  int map_height = 0;
  int start_x = 0;
  int start_y = 0;
  int goal_x = 0;
  int goal_y = 0;
  double optimal_length = 0.0;
  std::string optimal_length_text;  // the length exactly as written, so files round-trip

  // Length 0 with start != goal: an unsolvable problem (SOURCES.md of the benchmarks).
  bool unsolvable() const { return optimal_length == 0.0 && (start_x != goal_x || start_y != goal_y); }
  friend bool operator==(const ScenarioEntry&, const ScenarioEntry&) = default;
};

struct MovingAiScenario {
  std::string version = "1";  // "1" or "1.0"
  bool space_separated = false;  // the bg512 flavour
  std::vector<ScenarioEntry> entries;
  // Empty lines after the last problem (three hog2 dao files have them), kept for round trips.
  int trailing_blank_lines = 0;
  friend bool operator==(const MovingAiScenario&, const MovingAiScenario&) = default;
};

MovingAiScenario parse_movingai_scenario(std::string_view text, const std::string& source);
MovingAiScenario read_movingai_scenario(const std::string& path);
std::string format_movingai_scenario(const MovingAiScenario& scen);
// Throws Error(scen_path, field "width/height") when a problem was written for a map of another
// size than `map_name`'s width x height: its cells would mean other places.
void check_scenario_map_size(const MovingAiScenario& scen, const std::string& scen_path, int map_width, int map_height,
                             const std::string& map_name);
void write_movingai_scenario(const MovingAiScenario& scen, const std::string& path);

}  // namespace starnav
