// starnav slam make-benchmark and slam relations: the SLAM benchmark of scale (docs/slam.md,
// "Large buildings"): generated building floors with a route through them, and relation files
// made from a simulated log's truth by the Freiburg benchmark's rule.
//
//   starnav slam make-benchmark --kind grid|ladder|courtyard --seed S --out DIR [--length-km L] [--speed V] [--scan-rate HZ]
//                          [--wheel-scale-error PCT] [--force] [--json]
//   starnav slam relations LOG --out FILE [--key-distance M] [--loop-distance M] [--loop-travel M] [--loop-every N] [--force]
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "log_flags.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/harness/slam_report.hpp"
#include "starnav/sim/building_generator.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct MakeBenchmarkOptions {
  std::string kind = "grid";
  std::uint64_t seed = 0;
  double length_km = 3.0;
  double speed_mps = 0.6;
  double scan_rate_hz = 5.0;
  double wheel_scale_error_pct = 0.5;
  double shut_doors = 0.2;
  std::string out;
  bool force = false, json = false;
};

void run_make_benchmark(const MakeBenchmarkOptions& o, Context& ctx) {
  BuildingOptions b;
  b.kind = parse_building_kind(o.kind, "--kind");
  b.seed = o.seed;
  b.shut_door_probability = o.shut_doors;
  if (!(o.length_km > 0.0 && o.length_km <= 100.0)) throw Error("must be in (0, 100] km", {}, 0, "--length-km");
  if (!(o.speed_mps > 0.0 && o.speed_mps <= 0.95)) throw Error("must be in (0, 0.95] m/s (the robot's top speed is 0.99 m/s)", {}, 0, "--speed");
  if (!(o.scan_rate_hz > 0.0 && o.scan_rate_hz <= 50.0)) throw Error("must be in (0, 50] Hz (the LMS151's rate)", {}, 0, "--scan-rate");
  if (!(o.wheel_scale_error_pct >= 0.0 && o.wheel_scale_error_pct <= 10.0)) throw Error("must be in [0, 10] %", {}, 0, "--wheel-scale-error");
  if (!(o.shut_doors >= 0.0 && o.shut_doors <= 1.0)) throw Error("must be in [0, 1]", {}, 0, "--shut-doors");
  const std::string name = std::string("building_") + building_kind_name(b.kind) + "_" + std::to_string(o.seed);
  const fs::path dir(o.out);
  if (fs::exists(dir) && !fs::is_directory(dir)) throw Error("is not a directory", o.out, 0, "--out");
  const fs::path scenario = dir / (name + ".yaml"), map_yaml = dir / (name + "_map.yaml");
  for (const fs::path& p : {scenario, map_yaml})
    if (fs::exists(p) && !o.force) throw Error("exists already (use --force to overwrite)", p.string(), 0, "--out");
  const BuildingFloor floor = generate_building(b);
  const BuildingRoute route = building_route(floor, o.length_km * 1000.0);
  BuildingScenarioOptions s;
  s.name = name;
  s.map_file = map_yaml.filename().string();
  s.seed = o.seed;
  s.speed_mps = o.speed_mps;
  s.scan_rate_hz = o.scan_rate_hz;
  s.wheel_scale_error = o.wheel_scale_error_pct / 100.0;
  const OutputFolder out_folder(o.out, "--out");
  const OutputListing listing(o.out);
  write_ros_map(floor.map, map_yaml.string());
  write_text_file(scenario.string(), building_scenario_yaml(floor, route, s), "--out");
  const double width = floor.map.width() * floor.map.resolution(), height = floor.map.height() * floor.map.resolution();
  const double lap = route_length_m(route.waypoints);
  if (o.json) {
    nlohmann::ordered_json j;
    j["name"] = name;
    j["kind"] = building_kind_name(b.kind);
    j["seed"] = o.seed;
    j["size_m"] = {width, height};
    j["loops"] = floor.blocks.size();
    j["rooms"] = floor.rooms.size();
    j["room_size_m"] = {floor.room_size_m.x(), floor.room_size_m.y()};
    j["corridor_width_m"] = floor.corridor_width_m;
    j["wheel_scale_error"] = building_wheel_scale_errors(s);
    j["waypoints"] = route.waypoints.size();
    j["laps"] = route.laps;
    j["route_m"] = lap * route.laps;
    j["scenario"] = scenario.string();
    j["map"] = map_yaml.string();
    std::cout << j.dump() << "\n";
  } else {
    std::cout << name << ": " << format_fixed(width, 1) << " m x " << format_fixed(height, 1) << " m, " << floor.blocks.size() << " loops, "
              << floor.rooms.size() << " identical rooms (" << format_fixed(floor.room_size_m.x(), 2) << " m x "
              << format_fixed(floor.room_size_m.y(), 2) << " m), corridors " << format_fixed(floor.corridor_width_m, 2) << " m wide; route "
              << route.laps << " x " << format_fixed(lap, 0) << " m of straight legs\n";
    std::cout << "next: starnav sim " << scenario.string() << " --out " << (dir / name).string() << "\n"
              << "      starnav slam relations " << (dir / name / "log.clf").string() << " --out " << (dir / name / "log.relations").string()
              << "\n"
              << "      starnav bench slam --data " << o.out << " --relations " << o.out << " --logs " << name << "\n";
    listing.print(false, false);
  }
  ctx.exit_code = 0;
}

// A flag's sign, checked as the command line is read (before any file is): "must be > 0".
CLI::Validator sign_rule(bool zero_allowed) {
  return CLI::Validator(
      [zero_allowed](std::string& text) -> std::string {
        const std::optional<double> v = parse_real_text(text);
        if (v && (zero_allowed ? *v >= 0.0 : *v > 0.0)) return {};
        return std::string("must be ") + (zero_allowed ? ">= 0" : "> 0") + ", got '" + text + "'";
      },
      "", "");
}

struct RelationsOptions {
  std::string log, out;
  RelationRule rule;
  LogReadFlags read;
  bool force = false;
};

void run_relations(const RelationsOptions& o, Context& ctx) {
  check_output_path(o.out, o.force, "--out");
  check_distinct_files({{o.log, "LOG", false}, {o.out, "--out"}});
  const BenchmarkRelations r = log_benchmark_relations(o.log, log_read_options(o.read), o.rule);
  if (r.relations.empty()) throw Error("the truth is too short for a relation (" + std::to_string(r.key_poses) + " key poses)", o.log, 0, "LOG");
  write_text_file(o.out, relations_text(r.relations), "--out");
  std::cout << "wrote " << o.out << ": " << r.relations.size() << " relations (" << r.local << " between neighbouring key poses, " << r.loops
            << " across loops) from " << r.key_poses << " key poses\n";
  ctx.exit_code = 0;
}

}  // namespace

void register_slam_benchmark_commands(CLI::App* slam, Context& ctx) {
  auto m = std::make_shared<MakeBenchmarkOptions>();
  auto* make = slam->add_subcommand(
      "make-benchmark",
      "a large building floor (map_server map: corridors, identical rooms, several large loops) and a scenario driving a route\n"
      "of kilometres through it; `starnav sim` runs it into log.clf, `slam relations` makes its relation file (docs/slam.md)");
  make->add_option("--kind", m->kind, "the generator: grid (4 x 3 corridors), ladder (2 long corridors, 7 rungs), courtyard (3 x 3, an atrium)")
      ->default_str("grid");
  make->add_option("--seed", m->seed, "the layout's and the simulation's seed")->default_str("0");
  make->add_option("--length-km", m->length_km, "the route's length: whole laps (rounded up) or, below one lap, its start")->default_str("3");
  make->add_option("--speed", m->speed_mps, "driving speed, m/s")->default_str("0.6");
  make->add_option("--scan-rate", m->scan_rate_hz, "the laser's logged rate, Hz")->default_str("5");
  make->add_option("--wheel-scale-error", m->wheel_scale_error_pct,
                   "each wheel's systematic count error, drawn from the seed within +- this, %")->default_str("0.5");
  make->add_option("--shut-doors", m->shut_doors, "each room's chance that its door is wall (1: corridors without openings, featureless along their length)")->default_str("0.2");
  make->add_option("--out", m->out, "folder for NAME.yaml (the scenario) and NAME_map.yaml + .pgm")->required();
  make->add_flag("--force", m->force, "overwrite");
  make->add_flag("--json", m->json, "print the summary as one JSON object");
  make->callback([m, &ctx] { run_make_benchmark(*m, ctx); });

  auto r = std::make_shared<RelationsOptions>();
  auto* rel = slam->add_subcommand(
      "relations",
      "a benchmark relation file from a simulated log's truth by the Freiburg rule: relations between neighbouring key poses\n"
      "and across loops (poses far apart along the route, close in space); the laser's poses (docs/slam.md)");
  rel->add_option("LOG", r->log, "a log with ground truth (TRUEPOS: starnav sim's log.clf)")->required();
  rel->add_option("--out", r->out, "the relation file")->required();
  rel->add_option("--key-distance", r->rule.key_distance_m, "travel between key poses, m")->default_str("0.5")->check(sign_rule(false));
  rel->add_option("--key-angle", r->rule.key_angle_deg, "... or turning, deg")->default_str("20")->check(sign_rule(false));
  rel->add_option("--loop-distance", r->rule.loop_max_distance_m, "a loop relation's poses at most this far apart, m")->default_str("2")
      ->check(sign_rule(false));
  rel->add_option("--loop-travel", r->rule.loop_min_travel_m, "... and at least this much travel between them, m")->default_str("50")
      ->check(sign_rule(true));
  rel->add_option("--loop-every", r->rule.loop_every, "loop relations from every N-th key pose")->default_str("4")->check(CLI::Range(1, 1000000));
  add_log_read_flags(rel, r->read);
  rel->add_flag("--force", r->force, "overwrite --out");
  rel->callback([r, &ctx] { run_relations(*r, ctx); });
}

}  // namespace starnav::cli
