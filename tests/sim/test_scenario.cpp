// Scenario files: the E1 file's values, defaults, every error path (field and line named),
// truncated and garbage input, the command script, and building the world from a scenario.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/test_support.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {
namespace {

using test::kE1;

// A small valid scenario; tests edit it line by line.
const char* kBase =
    "name: base\n"                                          // 1
    "world:\n"                                              // 2
    "  terrain:\n"                                          // 3
    "    generate: {kind: flat, size_m: [10, 6], resolution_m: 0.1, z_m: 0.3}\n"  // 4
    "  obstacles:\n"                                        // 5
    "    - name: crate\n"                                   // 6
    "      kind: box\n"                                     // 7
    "      position_m: [5, 3]\n"                            // 8
    "      size_m: [0.4, 0.6, 0.5]\n"                       // 9
    "      yaw_deg: 30\n"                                   // 10
    "    - {name: post, kind: cylinder, position_m: [7, 1, 0.1], radius_m: 0.2, height_m: 1.0}\n"  // 11
    "robot:\n"                                              // 12
    "  start: {x_m: 1, y_m: 3, yaw_deg: 90}\n"              // 13
    "sim: {dt_s: 0.02, seed: 5}\n"                          // 14
    "commands:\n"                                           // 15
    "  - {duration_s: 2, vx_mps: 0.3}\n"                    // 16
    "  - {until_s: 5, wz_radps: 0.5}\n";                    // 17

std::string replace_line(const std::string& text, int line, const std::string& with) {
  std::string out;
  int n = 1;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string l = text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    out += (n == line ? with : l) + "\n";
    ++n;
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  return out;
}

// Parses and expects an Error naming this field and line (and the file).
void expect_error(const std::string& yaml, const std::string& field, int line, const std::string& words = {}) {
  try {
    parse_scenario(yaml, "case.yaml");
    ADD_FAILURE() << "no error for field " << field << " in:\n" << yaml;
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "case.yaml") << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    if (!words.empty()) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
}

TEST(Scenario, E1FileHasThePlatformRobotAndSensor) {
  const ScenarioSpec s = load_scenario(kE1);
  EXPECT_EQ(s.name, "e1_terrain_platform");
  ASSERT_EQ(s.obstacles.size(), 4u);
  EXPECT_EQ(s.obstacles[0].kind, "round_convex");
  EXPECT_EQ(s.obstacles[1].kind, "slope_step");
  EXPECT_EQ(s.obstacles[2].kind, "undulating_ground");
  EXPECT_EQ(s.obstacles[3].kind, "gravel");
  for (const auto& o : s.obstacles) EXPECT_DOUBLE_EQ(o.position.y(), 2.0);
  EXPECT_EQ(s.terrain.kind, ScenarioTerrain::Kind::Flat);
  EXPECT_DOUBLE_EQ(s.terrain.hills.width_m, 15.0);
  EXPECT_DOUBLE_EQ(s.terrain.hills.height_m, 4.0);
  EXPECT_EQ(s.vehicle.robot.drive, DriveKind::Mecanum);
  EXPECT_DOUBLE_EQ(s.start.x, 0.5);
  EXPECT_DOUBLE_EQ(s.start.y, 2.0);
  ASSERT_TRUE(s.lidar);
  EXPECT_EQ(s.lidar->config.lines(), 16);
  EXPECT_EQ(s.lidar->config.beams, 360);  // 1 deg over 360 deg
  EXPECT_NEAR(rad_to_deg(s.lidar->config.elevations.front()), 15.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.lidar->config.range_max, 30.0);
  ASSERT_EQ(s.commands.size(), 1u);
  EXPECT_DOUBLE_EQ(s.commands[0].twist.vx, 0.2);
  EXPECT_DOUBLE_EQ(s.duration_s, 70.0);
  ASSERT_EQ(s.reference_line.size(), 2u);
}

TEST(Scenario, BaseParsesWithDefaultsAndScript) {
  const ScenarioSpec s = parse_scenario(kBase, "dir/base.yaml");
  EXPECT_DOUBLE_EQ(s.dt_s, 0.02);
  EXPECT_EQ(s.seed, 5u);
  EXPECT_DOUBLE_EQ(s.duration_s, 5.0);  // the script's end
  EXPECT_NEAR(s.start.yaw, kPi / 2, 1e-12);
  EXPECT_FALSE(s.lidar);
  EXPECT_TRUE(s.bumper);
  // Robot defaults: the paper's Mecanum robot.
  EXPECT_DOUBLE_EQ(s.vehicle.robot.half_track_m, 0.225);
  EXPECT_DOUBLE_EQ(s.vehicle.robot.half_wheelbase_m, 0.200);
  // The script: piecewise constant, zero after the end.
  EXPECT_EQ(s.segment_at(0.0), 0);
  EXPECT_EQ(s.segment_at(1.999), 0);
  EXPECT_EQ(s.segment_at(2.0), 1);
  EXPECT_EQ(s.segment_at(4.999), 1);
  EXPECT_EQ(s.segment_at(5.0), -1);
  EXPECT_DOUBLE_EQ(s.command_at(1.0).vx, 0.3);
  EXPECT_DOUBLE_EQ(s.command_at(3.0).wz, 0.5);
  EXPECT_DOUBLE_EQ(s.command_at(3.0).vx, 0.0);
  EXPECT_DOUBLE_EQ(s.command_at(9.0).wz, 0.0);
}

TEST(Scenario, ObstaclesStandOnTheTerrain) {
  const ScenarioSpec s = parse_scenario(kBase, "base.yaml");
  const WorldDescription d = build_world(s);
  ASSERT_TRUE(d.terrain);
  ASSERT_EQ(d.obstacles.size(), 2u);
  // The crate's bottom is on the ground at z = 0.3: centre 0.25 above it; yaw 30 deg.
  const Box& b = std::get<Box>(d.obstacles[0].parts.at(0));
  EXPECT_NEAR(b.center.z(), 0.3 + 0.25, 1e-12);
  EXPECT_NEAR(b.center.x(), 5.0, 1e-12);
  EXPECT_NEAR(b.yaw, deg_to_rad(30.0), 1e-12);
  // The post's z is given: 0.1, not the ground.
  const Cylinder& c = std::get<Cylinder>(d.obstacles[1].parts.at(0));
  EXPECT_NEAR(c.base.z(), 0.1, 1e-12);
  EXPECT_EQ(d.obstacles[1].name, "post");
}

TEST(Scenario, MotionsKeepTheObstacleHeightUnlessGiven) {
  const std::string yaml =
      "world:\n  terrain:\n    generate: {kind: flat, size_m: [10, 10], z_m: 0.5}\n"
      "  obstacles:\n"
      "    - name: walker\n      kind: cylinder\n      position_m: [1, 1]\n      radius_m: 0.2\n      height_m: 1\n"
      "      appear_s: 2\n      waypoints:\n        - {t_s: 2, position_m: [1, 1]}\n        - {t_s: 6, position_m: [5, 1, 0.9]}\n"
      "    - {name: mover, kind: sphere, position_m: [2, 2], radius_m: 0.1, velocity_mps: [0.5, 0]}\n"
      "sim: {duration_s: 1}\n";
  const WorldDescription d = build_world(parse_scenario(yaml, "m.yaml"));
  const Obstacle& w = d.obstacles.at(0);
  ASSERT_EQ(w.waypoints.size(), 2u);
  EXPECT_NEAR(w.waypoints[0].position.z(), 0.5, 1e-12);  // the ground under position_m
  EXPECT_NEAR(w.waypoints[1].position.z(), 0.9, 1e-12);
  EXPECT_DOUBLE_EQ(w.appear, 2.0);
  EXPECT_NEAR(w.anchor_at(4.0).x(), 3.0, 1e-12);
  const Obstacle& m = d.obstacles.at(1);
  EXPECT_NEAR(m.anchor_at(2.0).x(), 3.0, 1e-12);
  EXPECT_NEAR(m.velocity.z(), 0.0, 1e-12);
}

TEST(Scenario, TerrainFileIsRelativeToTheScenario) {
  test::ScratchDir dir;
  std::filesystem::create_directories(dir.path() / "maps");
  // A 4 x 3 ASCII grid at 0.5 m with a known height.
  test::write_text(dir.file("maps/ground.asc"),
                   "ncols 4\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 0.5\nNODATA_value -9999\n"
                   "1 1 1 1\n1 1 1 1\n1 1 1 1\n");
  const std::string yaml =
      "world:\n  terrain: {file: maps/ground.asc}\n  obstacles:\n    - {kind: sphere, position_m: [1, 0.7], radius_m: 0.1}\n"
      "sim: {duration_s: 1}\n";
  test::write_text(dir.file("s.yaml"), yaml);
  const ScenarioSpec s = load_scenario(dir.file("s.yaml"));
  const WorldDescription d = build_world(s);
  ASSERT_TRUE(d.terrain);
  EXPECT_EQ(d.terrain->width(), 4);
  const Sphere& sp = std::get<Sphere>(d.obstacles.at(0).parts.at(0));
  EXPECT_NEAR(sp.center.z(), 1.0 + 0.1, 1e-12);  // lowest point on the ground
  EXPECT_EQ(d.obstacles[0].name, "sphere_0");

  // A missing file names the scenario, the line and the field.
  test::write_text(dir.file("bad.yaml"), "world:\n  terrain:\n    file: maps/nothing.asc\nsim: {duration_s: 1}\n");
  const ScenarioSpec b = load_scenario(dir.file("bad.yaml"));
  try {
    build_world(b);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), dir.file("bad.yaml"));
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "world.terrain.file");
  }
}

TEST(Scenario, GeneratedTerrainAndGravelFollowTheSeedUnlessPinned) {
  const std::string yaml =
      "world:\n  terrain:\n    generate: {kind: hills, size_m: [6, 6], resolution_m: 0.2}\n"
      "  obstacles:\n    - {kind: gravel, position_m: [3, 3], count: 20}\n"
      "    - {kind: gravel, position_m: [2, 2], count: 20, seed: 9}\n"
      "sim: {duration_s: 1}\n";
  ScenarioSpec a = parse_scenario(yaml, "g.yaml");
  ScenarioSpec b = a;
  b.seed = 1;
  const WorldDescription wa = build_world(a), wa2 = build_world(a), wb = build_world(b);
  EXPECT_TRUE(*wa.terrain == *wa2.terrain);
  EXPECT_FALSE(*wa.terrain == *wb.terrain);
  const auto first_x = [](const WorldDescription& w, int i) {
    return std::visit([](const auto& p) -> double {
      using T = std::decay_t<decltype(p)>;
      if constexpr (std::is_same_v<T, Box>) return p.center.x();
      else if constexpr (std::is_same_v<T, Sphere>) return p.center.x();
      else return 0.0;
    }, w.obstacles[static_cast<std::size_t>(i)].parts.at(0));
  };
  EXPECT_NE(first_x(wa, 0), first_x(wb, 0));  // follows the scenario seed
  EXPECT_EQ(first_x(wa, 1), first_x(wb, 1));  // pinned by its own seed
}

TEST(Scenario, UnknownKeysAreNamedWithTheirLine) {
  expect_error(replace_line(kBase, 1, "nmae: base"), "nmae", 1, "unknown key");
  expect_error(replace_line(kBase, 10, "      colour: red"), "world.obstacles[0].colour", 10, "unknown key");
  expect_error(replace_line(kBase, 13, "  start: {x_m: 1, y_m: 3, yaw: 90}"), "robot.start.yaw", 13, "unknown key");
  expect_error(replace_line(kBase, 14, "sim: {dt_s: 0.02, sed: 5}"), "sim.sed", 14);
  expect_error(replace_line(kBase, 16, "  - {duration_s: 2, v_mps: 0.3}"), "commands[0].v_mps", 16);
  expect_error(replace_line(kBase, 4, "    generate: {kind: flat, size_m: [10, 6], z: 1}"), "world.terrain.generate.z", 4);
  // A key valid for another kind is unknown here.
  expect_error(replace_line(kBase, 10, "      radius_m: 0.3"), "world.obstacles[0].radius_m", 10, "unknown key");
}

TEST(Scenario, WrongTypesAreNamedWithTheirLine) {
  expect_error(replace_line(kBase, 9, "      size_m: big"), "world.obstacles[0].size_m", 9, "list of 3 numbers");
  expect_error(replace_line(kBase, 9, "      size_m: [1, 2]"), "world.obstacles[0].size_m", 9, "found 2");
  expect_error(replace_line(kBase, 9, "      size_m: [1, x, 2]"), "world.obstacles[0].size_m[1]", 9, "expected a number");
  expect_error(replace_line(kBase, 10, "      yaw_deg: [30]"), "world.obstacles[0].yaw_deg", 10, "expected a number");
  expect_error(replace_line(kBase, 14, "sim: {dt_s: 0.02, seed: -5}"), "sim.seed", 14, "non-negative integer");
  expect_error(replace_line(kBase, 14, "sim: {dt_s: .inf}"), "sim.dt_s", 14, "finite");
  expect_error(replace_line(kBase, 13, "  start: 5"), "robot.start", 13, "mapping");
  expect_error(replace_line(replace_line(kBase, 13, ""), 12, "robot: [1, 2]"), "robot", 12, "mapping");
  expect_error(replace_line(replace_line(replace_line(kBase, 17, ""), 16, ""), 15, "commands: {vx_mps: 1}"), "commands",
               15, "list");
  expect_error("world:\n  obstacles: 3\nsim: {duration_s: 1}\n", "world.obstacles", 2, "list");
}

TEST(Scenario, OutOfRangeValuesAreNamedWithTheirLine) {
  expect_error(replace_line(kBase, 9, "      size_m: [0.4, -0.6, 0.5]"), "world.obstacles[0].size_m", 9, "> 0");
  expect_error(replace_line(kBase, 11, "    - {kind: cylinder, position_m: [7, 1], radius_m: 0, height_m: 1}"),
               "world.obstacles[1].radius_m", 11, "> 0");
  expect_error(replace_line(kBase, 14, "sim: {dt_s: -0.01}"), "sim.dt_s", 14, "must be in (0, 1], found '-0.01'");
  expect_error(replace_line(kBase, 4, "    generate: {kind: flat, size_m: [10, -6]}"), "world.terrain.generate.size_m", 4);
  expect_error(replace_line(kBase, 4, "    generate: {kind: flat, size_m: [10, 6], resolution_m: 0}"),
               "world.terrain.generate.resolution_m", 4);
  expect_error(replace_line(kBase, 13, "  wheel_radius_m: -0.1"), "robot.wheel_radius_m", 13, "> 0");
  expect_error(replace_line(kBase, 17, "  - {until_s: 1, wz_radps: 0.5}"), "commands[1].until_s", 17, "later");
  expect_error(replace_line(kBase, 10, "      disappear_s: 0"), "world.obstacles[0].disappear_s", 10, "later");
}

TEST(Scenario, MissingRequiredKeysAreNamed) {
  // The mapping's line: where the key should have been.
  expect_error(replace_line(kBase, 9, ""), "world.obstacles[0].size_m", 6, "required");
  expect_error(replace_line(kBase, 7, ""), "world.obstacles[0].kind", 6, "required");
  expect_error(replace_line(kBase, 8, ""), "world.obstacles[0].position_m", 6, "required");
  expect_error(replace_line(kBase, 4, "    generate: {size_m: [10, 6]}"), "world.terrain.generate.kind", 4, "required");
  expect_error("sim: {duration_s: 1}\n", "world", 1, "required");
  expect_error("world: {}\n", "sim.duration_s", 1, "required");
  expect_error(replace_line(kBase, 16, "  - {vx_mps: 0.3}"), "commands[0]", 16, "duration_s or until_s");
}

TEST(Scenario, ConflictsAndBadNamesAreNamed) {
  expect_error(replace_line(kBase, 7, "      kind: pyramid"), "world.obstacles[0].kind", 7, "unknown value 'pyramid' (box, cylinder,");
  expect_error(replace_line(kBase, 11, "    - {name: crate, kind: sphere, position_m: [7, 1], radius_m: 0.2}"),
               "world.obstacles[1].name", 11, "duplicate");
  expect_error(replace_line(replace_line(kBase, 4, ""), 3, "  terrain: {file: a.asc, generate: {kind: flat, size_m: [1, 1]}}"),
               "world.terrain", 3, "exactly one");
  expect_error(replace_line(kBase, 16, "  - {duration_s: 2, until_s: 3}"), "commands[0]", 16, "exactly one");
  expect_error(replace_line(kBase, 14, "sim: {dt_s: 0.02, dt_s: 0.01}"), "sim.dt_s", 14, "duplicate");
  expect_error(replace_line(kBase, 12, "motion_mode: sideways\nrobot:"), "motion_mode", 12, "unknown value 'sideways' (auto, turn_then_drive");
  const std::string moving = std::string(kBase) + "outputs: {point_clouds: {format: las}}\n";
  expect_error(moving, "outputs.point_clouds.format", 18, "unknown value 'las' (ply, pcd, none)");
  expect_error(std::string(kBase) + "outputs: {point_clouds: {format: ply}}\n", "outputs.point_clouds", 18, "lidar");
  expect_error(std::string(kBase) + "sensors: {lidar: {preset: vlp99}}\n", "sensors.lidar.preset", 18, "unknown LiDAR");
  expect_error(std::string(kBase) + "sensors: {encoders: {scale_error: [0.01, 0.7, 0, 0]}}\n", "sensors.encoders.scale_error", 18, "[-0.5, 0.5]");
  {
    // One value per wheel: the drive decides how many, so the simulation checks the count.
    const ScenarioSpec two = parse_scenario(std::string(kBase) + "sensors: {encoders: {scale_error: [0.01, -0.01]}}\n", "case.yaml");
    const std::string what = test::error_of([&] { Simulation sim(two); });
    EXPECT_NE(what.find("case.yaml:18:"), std::string::npos) << what;
    EXPECT_NE(what.find("sensors.encoders.scale_error"), std::string::npos) << what;
    EXPECT_NE(what.find("the drive has 4 wheels"), std::string::npos) << what;
  }
  expect_error(std::string(kBase) + "sensors: {lidar: {preset: vlp16, range_max_m: 0.1}}\n", "sensors.lidar.range_max_m", 18);
  expect_error(std::string(kBase) + "robot2: {}\n", "robot2", 18, "unknown key");
  // Waypoints: velocity and waypoints together, times not increasing.
  expect_error(replace_line(kBase, 10, "      velocity_mps: [1, 0]\n      waypoints: [{t_s: 0, position_m: [1, 1]}]"),
               "world.obstacles[0].waypoints", 11, "either");
  expect_error(replace_line(kBase, 10,
                            "      waypoints:\n        - {t_s: 1, position_m: [1, 1]}\n        - {t_s: 1, position_m: [2, 1]}"),
               "world.obstacles[0].waypoints[1].t_s", 12, "increase");
}

TEST(Scenario, SyntaxErrorsNameTheLine) {
  try {
    parse_scenario("world:\n  terrain: [1, 2\nsim: {}\n", "s.yaml");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "s.yaml");
    EXPECT_GT(e.line(), 0);
  }
  expect_error("", "", 1, "empty");
  expect_error("- 1\n- 2\n", "", 1, "mapping");
}

// Truncated and mangled documents: an Error or a valid scenario, never anything else.
TEST(Scenario, TruncatedAndGarbageInputGivesErrorNotCrash) {
  const std::string text = test::read_text(kE1);
  ASSERT_FALSE(text.empty());
  int errors = 0, parsed = 0;
  const auto attempt = [&](const std::string& doc) {
    try {
      const ScenarioSpec s = parse_scenario(doc, "fuzz.yaml");
      ++parsed;
      (void)s;
    } catch (const Error&) {
      ++errors;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a starnav::Error: " << e.what() << "\n" << doc;
    }
  };
  for (std::size_t n = 0; n < text.size(); n += 7) attempt(text.substr(0, n));
  attempt(text);
  Rng rng(42);
  for (int i = 0; i < 400; ++i) {
    std::string doc = text;
    const int edits = static_cast<int>(rng.uniform_int(1, 6));
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(doc.size()) - 1));
      switch (rng.uniform_int(0, 2)) {
        case 0: doc[at] = static_cast<char>(rng.uniform_int(1, 255)); break;
        case 1: doc.erase(at, static_cast<std::size_t>(rng.uniform_int(1, 20))); break;
        default: {
          static const std::string kSyntax = "-:[]{}#&*!|>'\"%@`,?\t\n0123456789";
          doc.insert(doc.begin() + static_cast<std::ptrdiff_t>(at),
                     kSyntax[static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(kSyntax.size()) - 1))]);
        }
      }
    }
    attempt(doc);
  }
  for (int i = 0; i < 100; ++i) {
    std::string doc;
    const int len = static_cast<int>(rng.uniform_int(0, 200));
    for (int k = 0; k < len; ++k) doc.push_back(static_cast<char>(rng.uniform_int(1, 255)));
    attempt(doc);
  }
  EXPECT_GT(errors, 100);
  EXPECT_GT(parsed, 0);  // the whole file at least
}

}  // namespace
}  // namespace starnav

// Found by fuzz_scenario (fuzz/crashers/fuzz_scenario/): each is a clear error now, or cheap.
namespace starnav {
namespace {

const char* kSmall = R"(world:
  terrain:
    generate: {kind: flat, size_m: [4.0, 4.0], resolution_m: 0.1}
sim: {dt_s: 0.01, duration_s: 5.0}
)";

TEST(ScenarioLimits, CommandTimesThatOverflowOrVanishAreRefused) {
  const std::string base = kSmall;
  expect_error(base + "commands:\n  - {duration_s: 1e308}\n  - {duration_s: 1e308}\n", "commands[1].duration_s", 7, "overflows");
  expect_error(base + "commands:\n  - {duration_s: 1e20}\n  - {duration_s: 1}\n", "commands[1].duration_s", 7, "too short");
}

TEST(ScenarioLimits, LidarResolutionFinerThanTheBeamLimitIsRefused) {
  const std::string base = kSmall;
  expect_error(base + "sensors:\n  lidar: {preset: vlp16, horizontal_resolution_deg: 0.0001}\n",
               "sensors.lidar.horizontal_resolution_deg", 6, "0.00036");
  const ScenarioSpec ok = parse_scenario(base + "sensors:\n  lidar: {preset: vlp16, horizontal_resolution_deg: 0.36}\n", "ok.yaml");
  ASSERT_TRUE(ok.lidar);
  EXPECT_EQ(ok.lidar->config.beams, 1000);
}

TEST(ScenarioLimits, LidarWithTooManyRaysPerScanIsRefused) {
  const std::string base = kSmall;
  // 360,000 beams x 16 lines = 5.76 M rays, above kMaxLidarRaysPerScan (4,194,304).
  expect_error(base + "sensors:\n  lidar: {preset: vlp16, horizontal_resolution_deg: 0.001}\n", "sensors.lidar.beams",
               6, "rays per scan");
  expect_error(base + "sensors:\n  lidar: {beams: 1000000, elevations_deg: [2, 1, 0, -1, -2]}\n",
               "sensors.lidar.beams", 6, "rays per scan");
  EXPECT_NO_THROW(parse_scenario(base + "sensors:\n  lidar: {beams: 1000000, elevations_deg: [1, 0, -1, -2]}\n", "ok.yaml"));
}

TEST(ScenarioLimits, TerrainWithTooManyCellsIsRefusedBeforeAnythingIsAllocated) {
  expect_error(replace_line(kSmall, 3, "    generate: {kind: flat, size_m: [2000.0, 2000.0], resolution_m: 0.05}"),
               "world.terrain.generate.size_m", 3, "at most 16000000");
  // 4000 x 4000 cells is the limit itself.
  EXPECT_NO_THROW(parse_scenario(replace_line(kSmall, 3, "    generate: {kind: flat, size_m: [400.0, 400.0], resolution_m: 0.1}"), "ok.yaml"));
}

TEST(ScenarioLimits, GravelPiecesOverAllFieldsAreLimited) {
  // Ten fields of 100,000 pieces are allowed (each is one line of YAML); an eleventh is not.
  auto field = [](int k, int count) {
    return "    - {name: g" + std::to_string(k) + ", kind: gravel, position_m: [1.5, 2.0], count: " + std::to_string(count) +
           "}\n";
  };
  std::string obstacles = "  obstacles:\n";
  for (int k = 0; k < 10; ++k) obstacles += field(k, 100000);
  const std::string tail = "sim: {dt_s: 0.01, duration_s: 5.0}";
  EXPECT_NO_THROW(parse_scenario(replace_line(kSmall, 4, obstacles + tail), "ok.yaml"));
  expect_error(replace_line(kSmall, 4, obstacles + field(10, 1) + tail), "world.obstacles[10].count", 15,
               "at most 1000000");
}

TEST(ScenarioLimits, GravelKeepsItsCountThoughTheParserChecksOnePiece) {
  // The parser validates a gravel field with one piece (a 100,000-piece field repeated by YAML
  // aliases made parsing take minutes); the spec keeps the count and build_world makes them all.
  const std::string yaml = replace_line(kSmall, 4,
                                        "  obstacles:\n"
                                        "    - {name: g0, kind: gravel, position_m: [1.5, 2.0], count: 2000}\n"
                                        "    - {name: g1, kind: gravel, position_m: [2.5, 2.0], count: 3000}\n"
                                        "sim: {dt_s: 0.01, duration_s: 5.0}");
  const ScenarioSpec s = parse_scenario(yaml, "gravel.yaml");
  ASSERT_EQ(s.obstacles.size(), 2u);
  EXPECT_EQ(std::get<Gravel>(s.obstacles[0].shape).count, 2000);
  const WorldDescription w = build_world(s);
  ASSERT_EQ(w.obstacles.size(), 2u);
  EXPECT_EQ(w.obstacles[0].parts.size(), 2000u);
  EXPECT_EQ(w.obstacles[1].parts.size(), 3000u);
}


TEST(ScenarioOverrides, SetAnyKeyBeforeTheScenarioIsRead) {
  const std::vector<ScenarioOverride> o = {parse_scenario_override("sim.duration_s=2.5"),
                                           parse_scenario_override("robot.start.yaw_deg=90"),
                                           parse_scenario_override("navigation.goal.x_m=3"),
                                           parse_scenario_override("navigation.follower.look_ahead_m=0.4")};
  const ScenarioSpec s = load_scenario(test::scenario_path("e4_dynamic_dead_end.yaml"), o);
  EXPECT_EQ(s.duration_s, 2.5);
  EXPECT_NEAR(s.start.yaw, kPi / 2, 1e-12);
  EXPECT_EQ(s.navigation->goal.x(), 3.0);
  bool found = false;
  for (const ParamSetting& v : s.navigation->settings)
    if (v.key == "follower.look_ahead_m") {
      found = true;
      EXPECT_EQ(v.value, "0.4");
      EXPECT_EQ(v.line, 0);  // from the command line: no line in the file
      EXPECT_EQ(v.field, "navigation.follower.look_ahead_m (--set)");
    }
  EXPECT_TRUE(found);
  // Lists too: a YAML value.
  const ScenarioOverride list = parse_scenario_override("world.terrain.generate.size_m=[4.0, 3.0]");
  EXPECT_NO_THROW(load_scenario(kE1, std::vector<ScenarioOverride>{list}));
}

TEST(ScenarioOverrides, BadOverridesAreOneLineErrorsNamingTheKey) {
  EXPECT_EQ(test::error_of([] { parse_scenario_override("no_equals_sign"); }).find("--set"), 0u);
  EXPECT_EQ(test::error_of([] { parse_scenario_override("=3"); }).find("--set"), 0u);
  const auto err = [](const std::string& text) {
    return test::error_of([&] { load_scenario(kE1, std::vector<ScenarioOverride>{parse_scenario_override(text)}); });
  };
  EXPECT_NE(err("sim.duration_s=-1").find("sim.duration_s (--set): must be > 0"), std::string::npos) << err("sim.duration_s=-1");
  EXPECT_NE(err("sim.nonesuch=1").find("sim.nonesuch (--set)"), std::string::npos) << err("sim.nonesuch=1");
  EXPECT_NE(err("sim.dt_s.x=1").find("'dt_s' is not a section"), std::string::npos) << err("sim.dt_s.x=1");
  EXPECT_NE(err("Sim..x=1").find("dotted lower_snake_case"), std::string::npos);
  EXPECT_NE(err("sim.duration_s=[1").find("not a YAML value"), std::string::npos);
}

}  // namespace
}  // namespace starnav
