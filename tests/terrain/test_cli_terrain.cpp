// starnav terrain generate: files equal the library's output, metadata sidecar, errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "starnav/io/elevation_io.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "support/test_support.hpp"

namespace {

using namespace starnav;
using test::run_cli;
using test::ScratchDir;

TEST(CliTerrain, HillsAscEqualsTheLibrary) {
  ScratchDir dir;
  const std::string out = dir.file("hills.asc");
  const auto r = run_cli({"terrain", "generate", "--kind", "hills", "--size-m", "6,4", "--resolution", "0.1", "--seed",
                          "7", "--amplitude", "1.5", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  HillsOptions o;
  o.width_m = 6;
  o.height_m = 4;
  o.resolution = 0.1;
  o.seed = 7;
  o.amplitude = 1.5;
  const ElevationMap want = generate_hills(o);
  const LoadedMap got = load_map(out);
  ASSERT_TRUE(got.is_elevation());
  EXPECT_EQ(got.elevation().heights(), want.heights());  // ASC keeps every digit
  const auto meta = nlohmann::json::parse(test::read_text(out + ".terrain.json"));
  EXPECT_EQ(meta["kind"], "hills");
  EXPECT_EQ(meta["seed"], 7);
  EXPECT_EQ(meta["width"], 60);
  EXPECT_EQ(meta["amplitude"], 1.5);
  // Not overwritten without --force; overwritten with it, identical bytes (deterministic).
  const std::string first = test::read_text(out);
  const auto again = run_cli({"terrain", "generate", "--kind", "hills", "--size-m", "6,4", "--resolution", "0.1",
                              "--seed", "7", "--amplitude", "1.5", "--out", out});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  const auto forced = run_cli({"terrain", "generate", "--kind", "hills", "--size-m", "6,4", "--resolution", "0.1",
                               "--seed", "7", "--amplitude", "1.5", "--out", out, "--force"});
  EXPECT_EQ(forced.exit_code, 0);
  EXPECT_EQ(test::read_text(out), first);
}

TEST(CliTerrain, RoadYamlWithSigma2AndFeatures) {
  ScratchDir dir;
  const std::string out = dir.file("road.yaml");
  const auto r = run_cli({"terrain", "generate", "--kind", "road", "--class", "d", "--method", "paper", "--size-m",
                          "8,6", "--resolution", "0.1", "--seed", "3", "--pit", "2,2,1,0.5", "--mound", "6,4,0.8,0.3",
                          "--out", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto meta = nlohmann::json::parse(test::read_text(out + ".terrain.json"));
  EXPECT_EQ(nlohmann::json::parse(r.out), meta);
  RoadOptions o;
  o.width_m = 8;
  o.height_m = 6;
  o.resolution = 0.1;
  o.road_class = 'D';
  o.method = RoadMethod::Paper;
  o.seed = 3;
  o.features.push_back({TerrainFeature::Kind::Pit, Vec2(2, 2), 1.0, 0.5});
  o.features.push_back({TerrainFeature::Kind::Mound, Vec2(6, 4), 0.8, 0.3});
  const RoadTerrain want = generate_road(o);
  EXPECT_EQ(meta["class"], "D");
  EXPECT_EQ(meta["method"], "paper");
  EXPECT_DOUBLE_EQ(meta["sigma2_m2"].get<double>(), want.spectrum.sigma2);
  EXPECT_DOUBLE_EQ(meta["band_used_per_m"][0].get<double>(), want.spectrum.n_low);
  EXPECT_EQ(meta["features"].size(), 2u);
  EXPECT_EQ(meta["features"][0]["kind"], "pit");
  // 16-bit PNG: heights within one quantisation step of the range.
  const ElevationMap got = load_map(out).elevation();
  const auto range = want.map.height_range();
  const double step = (range->max - range->min) / 65535.0;
  for (std::size_t i = 0; i < got.cell_count(); ++i) ASSERT_NEAR(got.heights()[i], want.map.heights()[i], step);
}

TEST(CliTerrain, UnityRawExport) {
  ScratchDir dir;
  const std::string out = dir.file("road.raw");
  const auto r = run_cli({"terrain", "generate", "--kind", "road", "--size-m", "3.2,3.2", "--resolution", "0.1",
                          "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const ElevationMap got = read_unity_raw(out);
  EXPECT_EQ(got.width(), 32);
}

using test::BadFlagCase;

TEST(CliTerrain, BadFlagsNameTheFlag) {
  ScratchDir dir;
  const std::string out = dir.file("t.asc");
  const std::vector<std::string> base = {"terrain", "generate", "--out", out};
  const std::vector<BadFlagCase> cases = {
      {{"--kind", "mountains", "--size-m", "1,1", "--resolution", "0.1"}, "--kind"},
      {{"--kind", "road", "--class", "Z", "--size-m", "10,10", "--resolution", "0.1"}, "--class"},
      {{"--kind", "road", "--class", "CD", "--size-m", "10,10", "--resolution", "0.1"}, "--class"},
      {{"--kind", "road", "--method", "fft", "--size-m", "10,10", "--resolution", "0.1"}, "--method"},
      {{"--kind", "hills", "--class", "C", "--size-m", "10,10", "--resolution", "0.1"}, "--class"},
      {{"--kind", "road", "--amplitude", "2", "--size-m", "10,10", "--resolution", "0.1"}, "--amplitude"},
      {{"--kind", "hills", "--size-m", "10", "--resolution", "0.1"}, "--size-m"},
      {{"--kind", "hills", "--size-m", "-1,3", "--resolution", "0.1"}, "--size-m"},
      {{"--kind", "hills", "--size-m", "0.01,3", "--resolution", "0.1"}, "--size-m"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "0"}, "--resolution"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "abc"}, "--resolution"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "0.1", "--seed", "-3"}, "--seed"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "0.1", "--amplitude", "x"}, "--amplitude"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "0.1", "--pit", "1,2,3"}, "--pit"},
      {{"--kind", "hills", "--size-m", "10,10", "--resolution", "0.1", "--mound", "1,2,0,1"}, "--mound"},
      {{"--kind", "road", "--size-m", "0.3,0.3", "--resolution", "0.1"}, "--size-m"},
      {{"--kind", "road", "--size-m", "10,10", "--resolution", "0.1", "--band", "2,1"}, "--band"},
      {{"--kind", "road", "--size-m", "10,10", "--resolution", "0.1", "--intervals", "0"}, "--intervals"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = base;
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << c.flag << ": " << r.err;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
    EXPECT_FALSE(test::fs::exists(out)) << c.flag;
  }
  const auto fmt = run_cli({"terrain", "generate", "--kind", "hills", "--size-m", "2,2", "--resolution", "0.1", "--out",
                            dir.file("t.map")});
  EXPECT_EQ(fmt.exit_code, 2);
  EXPECT_NE(fmt.err.find("--out"), std::string::npos) << fmt.err;
}

}  // namespace
