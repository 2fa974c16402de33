// `starnav map info --json` on every map under ../shared/, checked against the files' own headers
// (and cell counts computed here straight from the bytes), plus exit codes and error lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "support/test_support.hpp"

namespace fs = std::filesystem;
using starnav::test::run_cli;

namespace {

std::vector<fs::path> files_under(const std::string& dir, const std::string& ext) {
  std::vector<fs::path> out;
  if (dir.empty()) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ext) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

nlohmann::json info_json(const fs::path& file) {
  const auto r = run_cli({"map", "info", file.string(), "--json"});
  EXPECT_EQ(r.exit_code, 0) << file << "\n" << r.err;
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST(MapInfoCli, EveryMovingAiMapMatchesItsHeaderAndCharacters) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  const auto maps = files_under(starnav::test::shared_path("benchmarks/movingai"), ".map");
  ASSERT_GE(maps.size(), 40u);
  for (const auto& path : maps) {
    // Independent count: header numbers and passable characters straight from the text.
    std::istringstream in(starnav::test::read_text(path.string()));
    std::string line, key;
    long height = -1, width = -1, free = 0, blocked = 0;
    bool in_map = false;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!in_map) {
        std::istringstream ls(line);
        ls >> key;
        if (key == "height") ls >> height;
        if (key == "width") ls >> width;
        if (key == "map") in_map = true;
        continue;
      }
      for (char c : line) (c == '.' || c == 'G' || c == 'S') ? ++free : ++blocked;
    }
    const auto j = info_json(path);
    EXPECT_EQ(j["format"], "movingai") << path;
    EXPECT_EQ(j["width"], width) << path;
    EXPECT_EQ(j["height"], height) << path;
    EXPECT_EQ(j["free"], free) << path;
    EXPECT_EQ(j["occupied"], blocked) << path;
    EXPECT_EQ(j["unknown"], 0) << path;
    EXPECT_EQ(j["resolution_m"], 1.0);
  }
}

TEST(MapInfoCli, EveryRosMapMatchesItsImageHeaderAndTrinaryCounts) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/ros_maps");
  const auto yamls = files_under(starnav::test::shared_path("datasets/ros_maps"), ".yaml");
  ASSERT_GE(yamls.size(), 8u);
  for (const auto& yaml : yamls) {
    const auto j = info_json(yaml);
    EXPECT_EQ(j["format"], "ros_map") << yaml;
    const std::size_t total = j["free"].get<std::size_t>() + j["occupied"].get<std::size_t>() + j["unknown"].get<std::size_t>();
    EXPECT_EQ(total, j["width"].get<std::size_t>() * j["height"].get<std::size_t>()) << yaml;
    // For binary 8-bit PGMs recompute map_server's trinary classification from the bytes.
    fs::path pgm = yaml;
    pgm.replace_extension(".pgm");
    if (!fs::exists(pgm)) continue;
    const std::string bytes = starnav::test::read_text(pgm.string());
    std::istringstream hs(bytes);
    std::string magic;
    long w = 0, h = 0, maxval = 0;
    hs >> magic;
    auto next_number = [&hs](long& v) {
      while (hs >> std::ws && hs.peek() == '#') {
        std::string c;
        std::getline(hs, c);
      }
      hs >> v;
    };
    next_number(w);
    next_number(h);
    next_number(maxval);
    ASSERT_EQ(magic, "P5") << pgm;
    ASSERT_EQ(maxval, 255) << pgm;
    EXPECT_EQ(j["width"], w) << yaml;
    EXPECT_EQ(j["height"], h) << yaml;
    const std::size_t data_start = static_cast<std::size_t>(hs.tellg()) + 1;
    ASSERT_EQ(bytes.size() - data_start, static_cast<std::size_t>(w * h)) << pgm;
    // Thresholds from the YAML text (all shared maps have negate 0 and trinary mode).
    const std::string ytext = starnav::test::read_text(yaml.string());
    std::smatch m;
    ASSERT_TRUE(std::regex_search(ytext, m, std::regex("occupied_thresh:\\s*([0-9.]+)")));
    const double occupied_thresh = std::stod(m[1]);
    ASSERT_TRUE(std::regex_search(ytext, m, std::regex("free_thresh:\\s*([0-9.]+)")));
    const double free_thresh = std::stod(m[1]);
    long free = 0, occupied = 0, unknown = 0;
    for (std::size_t i = data_start; i < bytes.size(); ++i) {
      const double p = (255.0 - static_cast<unsigned char>(bytes[i])) / 255.0;
      if (p > occupied_thresh) ++occupied;
      else if (p < free_thresh) ++free;
      else ++unknown;
    }
    EXPECT_EQ(j["free"], free) << yaml;
    EXPECT_EQ(j["occupied"], occupied) << yaml;
    EXPECT_EQ(j["unknown"], unknown) << yaml;
  }
}

TEST(MapInfoCli, EveryAscDemMatchesItsHeader) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/dem");
  const auto ascs = files_under(starnav::test::shared_path("datasets/dem"), ".asc");
  ASSERT_GE(ascs.size(), 5u);
  for (const auto& asc : ascs) {
    std::istringstream in(starnav::test::read_text(asc.string()));
    std::string key;
    long ncols = -1, nrows = -1;
    for (int i = 0; i < 6 && in >> key; ++i) {
      std::string value;
      in >> value;
      std::transform(key.begin(), key.end(), key.begin(), ::tolower);
      if (key == "ncols") ncols = std::stol(value);
      if (key == "nrows") nrows = std::stol(value);
    }
    const auto j = info_json(asc);
    EXPECT_EQ(j["format"], "asc");
    EXPECT_EQ(j["width"], ncols) << asc;
    EXPECT_EQ(j["height"], nrows) << asc;
    EXPECT_LE(j["z_min_m"].get<double>(), j["z_max_m"].get<double>());
  }
}

TEST(MapInfoCli, GeoTiffSizesMatchSources) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/dem");
  // Sizes (cols x rows) and elevation ranges as datasets/dem/SOURCES.md lists them.
  struct Expect {
    const char* file;
    int w, h;
    double zmin, zmax;
  };
  const Expect expected[] = {{"datasets/dem/pysheds/dem.tif", 367, 359, 147, 298},
                             {"datasets/dem/terra/elev.tif", 95, 90, 141, 547},
                             {"datasets/dem/terra/elev_vinschgau.tif", 252, 194, 388, 3863}};
  for (const auto& e : expected) {
    const std::string path = starnav::test::shared_path(e.file);
    if (path.empty()) continue;
    const auto info = run_cli({"map", "info", path, "--json"});
    if (!starnav::test::expect_geotiff()) {
      // Without GDAL: one error line saying so, exit 2.
      EXPECT_EQ(info.exit_code, 2);
      EXPECT_NE(info.err.find("GeoTIFF support needs GDAL"), std::string::npos) << info.err;
      continue;
    }
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto j = nlohmann::json::parse(info.out);
    EXPECT_EQ(j["width"], e.w) << path;
    EXPECT_EQ(j["height"], e.h) << path;
    EXPECT_NEAR(j["z_min_m"].get<double>(), e.zmin, 1.0) << path;
    EXPECT_NEAR(j["z_max_m"].get<double>(), e.zmax, 1.0) << path;
  }
}

TEST(MapCli, ExitCodesAndErrorLine) {
  starnav::test::ScratchDir dir;
  const auto missing = run_cli({"map", "info", dir.file("nope.map")});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(missing.err.rfind("starnav: error: " + dir.file("nope.map"), 0) == 0) << missing.err;
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;

  const auto usage = run_cli({"map", "info"});
  EXPECT_EQ(usage.exit_code, 2);
  const auto unknown = run_cli({"frobnicate"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(run_cli({"--help"}).exit_code, 0);
  EXPECT_EQ(run_cli({"map", "--help"}).exit_code, 0);
  EXPECT_EQ(run_cli({"map", "info", "--help"}).exit_code, 0);
  const auto version = run_cli({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.out.find("starnav "), std::string::npos);
}

TEST(MapCli, ConvertMovingAiToRosAndBackKeepsTheMap) {
  starnav::test::ScratchDir dir;
  const std::string src = std::string(STARNAV_SOURCE_DIR) + "/scenarios/maps/office.map";
  ASSERT_EQ(run_cli({"map", "convert", src, dir.file("office.yaml")}).exit_code, 0);
  // Never overwrite without --force.
  const auto again = run_cli({"map", "convert", src, dir.file("office.yaml")});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  ASSERT_EQ(run_cli({"map", "convert", dir.file("office.yaml"), dir.file("back.map")}).exit_code, 0);
  // The office map only uses '.', '@' and 'T'; going through an occupancy grid keeps free vs
  // blocked and the row order (T becomes @).
  std::string original = starnav::test::read_text(src);
  std::replace(original.begin(), original.end(), 'T', '@');
  EXPECT_EQ(starnav::test::read_text(dir.file("back.map")), original);
  const auto a = nlohmann::json::parse(run_cli({"map", "info", src, "--json"}).out);
  const auto b = nlohmann::json::parse(run_cli({"map", "info", dir.file("office.yaml"), "--json"}).out);
  EXPECT_EQ(a["free"], b["free"]);
  EXPECT_EQ(a["occupied"], b["occupied"]);
}
