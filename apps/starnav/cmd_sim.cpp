// starnav sim: run a scenario (docs/scenarios.md) and write its records and pictures to a folder.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "nav2_flags.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_pictures.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/parameter_docs.hpp"
#include "starnav/harness/route_drive.hpp"
#include "starnav/harness/lidar_frame_recorder.hpp"
#include "starnav/harness/robot_log_recorder.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/harness/simulation_pictures.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "starnav/config.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/view/run_folder.hpp"
#if STARNAV_HAVE_HTTP
#include "starnav/view/run_server.hpp"
#endif

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct SimOptions {
  std::string scenario;
  std::string out;
  std::string seed;
  std::string duration;
  std::string point_clouds;
  std::string motion_mode;
  std::string planner;
  std::string controller;
  std::vector<std::string> sets;
  std::string nav2_params;
  bool compare_astar = false;
  bool step_all_hits = false;
  std::vector<double> controller_pictures;
  std::vector<double> dwa_pictures;  // the old name of --controller-pictures
  bool png = false;
  bool force = false;
  bool json = false;
  bool quiet = false;
  bool live = false;
  bool live_wait = false;
  int port = 8765;
  std::string bind = "127.0.0.1";
};

double parse_duration(const std::string& text) {
  double v = 0.0;
  if (!parse_double(text, v) || !(v > 0.0))
    throw Error("expected a positive number of seconds, got '" + text + "'", {}, 0, "--duration");
  return v;
}

void prepare_out_dir(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    fs::remove_all(fs::path(dir) / "clouds", ec);  // stale clouds of an earlier run
  } else {
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), dir, 0, "--out");
  }
}

// cli_util's ProgressBar in hundredths of the simulated time, with the time itself.
class SimProgress {
 public:
  SimProgress(bool quiet, double duration_s) : bar_("sim", 100, quiet), duration_s_(duration_s) {}
  void update(double fraction) {
    char what[64];
    std::snprintf(what, sizeof what, "(t = %.1f / %.1f s)", fraction * duration_s_, duration_s_);
    bar_.update(static_cast<std::size_t>(std::clamp(fraction, 0.0, 1.0) * 100.0 + 0.5), what);
  }
  // The bar ends at 100 with how the run ended ("arrived at t = 184.0 s of 500.0 s"): a run that
  // stops before sim.duration_s must not read as one cut short.
  void finish(const std::string& how, double t_s) {
    char what[96];
    std::snprintf(what, sizeof what, "(%s at t = %.1f s of %.1f s)", how.c_str(), t_s, duration_s_);
    bar_.update(100, what);
    bar_.finish();
  }

 private:
  ProgressBar bar_;
  double duration_s_;
};

#if STARNAV_HAVE_HTTP
// The viewer's server for a live run: the world and a live manifest from memory, steps as events.
std::unique_ptr<RunServer> start_live_server(const Simulation& sim, const NavigationRun* navigation, const SimOptions& o) {
  RunServerOptions options;
  options.viewer_dir = find_viewer_dir(viewer_dir_candidates(executable_path()));
  options.host = o.bind;
  options.port = o.port;
  options.live = true;
  auto server = std::make_unique<RunServer>(options);  // a --bind or --port it cannot listen on is the one error line
  if (!server->loopback_only()) warn_if_served_beyond_loopback(o.bind);
  server->set_memory_file("world.json", world_json(sim, navigation));
  server->set_memory_file("run.json", live_run_manifest_json(sim, navigation ? "navigation" : "simulation"));
  server->start();
  std::fprintf(stderr, "starnav: live viewer at %s\n", server->url().c_str());
  if (o.live_wait) {
    std::fprintf(stderr, "starnav: waiting for a viewer to connect before the run starts\n");
    server->wait_for_live_client(-1.0);
  }
  return server;
}

// After the run: the end to every viewer, a short wait for them to read it, and the server stops.
void finish_live(RunServer& live, const std::string& out) {
  live.end_live();
  // Open viewers get the last steps and the end; a stalled one is not waited for long.
  live.wait_drained(5.0);
  live.stop();
  std::fprintf(stderr, "starnav: live run ended; replay it with: starnav view %s\n", out.c_str());
}
#endif

// ---- the command -------------------------------------------------------------------------------

// A navigation scenario (a `navigation` section): the navigation stack drives.
void run_navigation_scenario(const ScenarioSpec& spec, const SimOptions& o, Context& ctx) {
  NavigationOptions options;
  if (!o.motion_mode.empty()) options.motion_mode = o.motion_mode;
  if (!o.planner.empty()) options.planner = o.planner;
  if (!o.controller.empty()) options.controller = o.controller;
  options.compare_astar = o.compare_astar;
  options.step_all_hits = o.step_all_hits;
  const char* pictures_flag = o.dwa_pictures.empty() ? "--controller-pictures" : "--dwa-pictures";
  const std::vector<double>& pictures = o.dwa_pictures.empty() ? o.controller_pictures : o.dwa_pictures;
  if (!o.dwa_pictures.empty() && !o.controller_pictures.empty())
    throw Error("give --controller-pictures only (--dwa-pictures is its old name)", "", 0, "--dwa-pictures");
  if (!o.dwa_pictures.empty())
    print_warning("--dwa-pictures is deprecated; use --controller-pictures");
  for (const double t : pictures)
    if (!std::isfinite(t) || t < 0.0 || t > spec.duration_s)
      throw Error("each time must be in [0, sim.duration_s]", "", 0, pictures_flag);
  options.controller_snapshot_times_s = pictures;
#if STARNAV_HAVE_HTTP
  // The server is made once the run exists (it serves the run's world); steps before that: none.
  std::unique_ptr<RunServer> live;
  if (o.live) options.on_step_line = [&live](const std::string& line) { live->publish("step", line); };
#endif
  NavigationRun run(spec, options);
#if STARNAV_HAVE_HTTP
  if (o.live) live = start_live_server(run.simulation(), &run, o);
#endif
  for (const std::string& w : run.navigator().warnings()) print_warning(w);
  const OutputListing listing(o.out);
  prepare_out_dir(o.out);
  add_cloud_writer(run.simulation(), spec, o.out);
  std::optional<RobotLogRecorder> recorder;
  if (RobotLogRecorder::can_record(spec)) recorder.emplace(run.simulation());
  std::optional<LidarFrameRecorder> lidar_frames;
  if (spec.outputs.lidar_frames_every_n_scans > 0)
    lidar_frames.emplace(run.simulation(), (fs::path(o.out) / "lidar").string(), spec.outputs.lidar_frames_every_n_scans);

  SimProgress bar(o.quiet, spec.duration_s);
  run.run([&bar](double f) { bar.update(f); });
  bar.finish(run.metrics().outcome, run.simulation().time());

  const fs::path dir(o.out);
  write_navigation_records(run, o.out);
  if (recorder) write_text_file((dir / "log.clf").string(), carmen_log_text(recorder->log()), "--out");
  if (lidar_frames) lidar_frames->finish();
  write_navigation_scene(run, (dir / "scene.svg").string());
  write_navigation_overlay(run, (dir / "overlay.svg").string());
  if (o.png) {
    write_navigation_scene(run, (dir / "scene.png").string());
    write_navigation_overlay(run, (dir / "overlay.png").string());
  }
  // A controller that commands velocities under acceleration limits: its speed profile.
  if (run.navigator().controller_capabilities().has(Capability::VelocitySpace))
    speed_profile_plot(run.simulation().trajectory(), spec.name + ": achieved velocities").write_svg((dir / "speed.svg").string());
  {
    const std::string controller(run.navigator().controller().name());
    for (const ControllerSnapshot& s : run.controller_snapshots()) {
      const std::string stem = "controller_" + format_fixed(s.step.t_s, 2) + "s";
      const viz::MapPicture pic =
          controller_step_picture(s, spec.name + ": " + controller + " at t = " + format_fixed(s.step.t_s, 2) + " s");
      pic.write_svg((dir / (stem + ".svg")).string());
      if (o.png) {
        pic.write_png((dir / (stem + ".png")).string());
      }
    }
  }
  write_run_record(run.simulation(), &run, o.out);
#if STARNAV_HAVE_HTTP
  if (live) finish_live(*live, o.out);
#endif
  const NavigationMetrics m = run.metrics();
  if (o.json) {
    std::cout << navigation_metrics_json(run);
  } else {
    const double sim_s = run.simulation().time();
    std::printf("%s (%s, %s): %s after %.2f s simulated in %.2f s (%.0fx real time); %.2f m driven, %d plan%s "
                "(%llu nodes expanded), %lld collision%s, deviation from the path mean %.3f m, max %.3f m\n",
                spec.name.c_str(), m.planner.c_str(), (m.motion_mode == "none" ? m.controller : m.motion_mode).c_str(),
                m.outcome.c_str(), sim_s, run.wall_s(),
                run.wall_s() > 0 ? sim_s / run.wall_s() : 0.0, m.distance_m, m.plans, m.plans == 1 ? "" : "s",
                static_cast<unsigned long long>(m.expanded_total), static_cast<long long>(m.collisions),
                m.collisions == 1 ? "" : "s", m.deviation_mean_m, m.deviation_max_m);
    if (m.goals_total > 1) std::printf("%d of %d goals reached\n", m.arrivals, m.goals_total);
  }
  listing.print(o.json, o.quiet);
  if (m.success) {
    ctx.exit_code = 0;
  } else {
    std::fprintf(stderr, "starnav: error: %s: navigation: %s%s%s\n", spec.file.c_str(),
                 m.outcome == "timeout" ? "the goal was not reached within sim.duration_s" : "no path",
                 m.reason.empty() ? "" : ": ", m.reason.c_str());
    ctx.exit_code = 1;
  }
}

void run_sim(const SimOptions& o, Context& ctx) {
  std::vector<ScenarioOverride> overrides;
  for (const std::string& text : o.sets) overrides.push_back(parse_scenario_override(text));
  std::vector<CommandOwnedKey> owned;
  if (!o.seed.empty()) owned.push_back({"sim.seed", "--seed gives it"});
  if (!o.duration.empty()) owned.push_back({"sim.duration_s", "--duration gives it"});
  if (!o.planner.empty()) owned.push_back({"navigation.planner", "--planner gives it"});
  if (!o.controller.empty()) owned.push_back({"navigation.controller", "--controller gives it"});
  if (!o.point_clouds.empty()) owned.push_back({"outputs.point_clouds", "--point-clouds gives it"});
  if (!o.motion_mode.empty()) {
    owned.push_back({"motion_mode", "--motion-mode gives it"});
    owned.push_back({"navigation.follower.motion_mode", "--motion-mode gives it"});
  }
  check_user_overrides(overrides, owned);
  if (!o.nav2_params.empty()) {
    // The Nav2 file's settings go first, so that --set overrides them; which sections they reach
    // depends on the scenario's components.
    const Nav2Params nav2 = read_nav2_params(o.nav2_params, scenario_nav2_target(load_scenario(o.scenario, overrides), o.controller));
    std::vector<ScenarioOverride> mapped;
    for (const ParamSetting& s : nav2.settings()) mapped.push_back({s.key, s.value});
    overrides.insert(overrides.begin(), mapped.begin(), mapped.end());
    print_nav2_summary(nav2);
  }
  ScenarioSpec spec = load_scenario(o.scenario, overrides);
  if (!o.seed.empty()) spec.seed = parse_unsigned(o.seed, "--seed", "a non-negative integer");
  if (!o.duration.empty()) {
    spec.duration_s = parse_duration(o.duration);
    check_simulation_steps(spec, "--duration");
  }
  if (!o.point_clouds.empty()) {
    spec.outputs.point_clouds = parse_cloud_format(o.point_clouds, "--point-clouds");
    if (spec.outputs.point_clouds != ScenarioOutputs::CloudFormat::None && !spec.lidar)
      throw Error("the scenario has no sensors.lidar", o.scenario, 0, "--point-clouds");
  }
  if (!spec.navigation) {
    for (const auto& [flag, given] : {std::pair{"--motion-mode", !o.motion_mode.empty()}, std::pair{"--planner", !o.planner.empty()},
                                      std::pair{"--controller", !o.controller.empty()},
                                      std::pair{"--compare-astar", o.compare_astar}, std::pair{"--all-hits", o.step_all_hits},
                                      std::pair{"--controller-pictures", !o.controller_pictures.empty()},
                                      std::pair{"--dwa-pictures", !o.dwa_pictures.empty()}})
      if (given) throw Error("only for navigation scenarios (the scenario has no navigation section)", o.scenario, 0, flag);
  }
#if !STARNAV_HAVE_HTTP
  if (o.live) throw Error("this starnav was built without its HTTP server (STARNAV_WITH_HTTP=OFF)", "", 0, "--live");
#endif
  const OutputFolder out_folder = check_out_dir(o.out, o.force);
  if (spec.navigation) return run_navigation_scenario(spec, o, ctx);

  const auto t_setup = Clock::now();
  Simulation sim(spec);
  const double setup_s = std::chrono::duration<double>(Clock::now() - t_setup).count();
  const OutputListing listing(o.out);
  prepare_out_dir(o.out);
  add_cloud_writer(sim, spec, o.out);
  std::optional<RobotLogRecorder> recorder;
  if (RobotLogRecorder::can_record(spec)) recorder.emplace(sim);
  std::optional<LidarFrameRecorder> lidar_frames;
  if (spec.outputs.lidar_frames_every_n_scans > 0)
    lidar_frames.emplace(sim, (fs::path(o.out) / "lidar").string(), spec.outputs.lidar_frames_every_n_scans);
  std::optional<LocalizationChain> chain;
  if (spec.localization) chain.emplace(sim, localization_config(spec));
  std::unique_ptr<RouteDrive> route;
  if (spec.route) route = make_route_drive(sim);

  // With a LiDAR: a step per scan (pose, returns, the localization chain's estimate and particles).
  std::optional<ScanStepRecorder> steps;
  if (spec.lidar) steps.emplace(sim, chain ? &*chain : nullptr);
#if STARNAV_HAVE_HTTP
  // Live: the steps as they are recorded, or without a LiDAR the true pose ten times a simulated second.
  std::unique_ptr<RunServer> live;
  if (o.live) {
    live = start_live_server(sim, nullptr, o);
    if (steps) {
      steps->on_line = [&live](const std::string& line) { live->publish("step", line); };
    } else {
      const std::int64_t every = std::max<std::int64_t>(1, std::llround(0.1 / spec.dt_s));
      sim.on_step = [&sim, &live, every] {
        if (sim.step_count() % every == 0) live->publish("step", pose_step_json_line(sim.time(), sim.vehicle().state().pose));
      };
    }
  }
#endif
  SimProgress bar(o.quiet, spec.duration_s);
  const auto t_run = Clock::now();
  sim.run([&bar](double f) { bar.update(f); });
  const double wall_s = std::chrono::duration<double>(Clock::now() - t_run).count();
  bar.finish("ended", sim.time());

  const fs::path dir(o.out);
  write_simulation_records(sim, o.out);
  if (recorder) write_text_file((dir / "log.clf").string(), carmen_log_text(recorder->log()), "--out");
  if (lidar_frames) lidar_frames->finish();
  if (chain) write_text_file((dir / "estimate.csv").string(), estimate_csv(chain->records()), "--out");
  if (steps) write_text_file((dir / "steps.jsonl").string(), steps->steps_jsonl(), "--out");
  const SimulationMetrics m = sim.metrics();
  SimulationTiming timing;
  timing.wall_s = wall_s;
  timing.setup_s = setup_s;
  timing.sim_s = sim.time();
  timing.steps = m.steps;
  timing.lidar_rays = m.lidar_rays;
  write_timing_json(timing, (dir / "timing.json").string());
  write_scene_svg(sim, (dir / "scene.svg").string());
  write_height_trace(sim, (dir / "height_trace.svg").string());
  write_track(sim, (dir / "track.svg").string());
  write_run_record(sim, nullptr, o.out);
#if STARNAV_HAVE_HTTP
  if (live) finish_live(*live, o.out);
#endif

  if (o.json) {
    std::cout << metrics_json(sim);
  } else {
    std::printf("%s: %.2f s simulated in %.2f s (%.0fx real time), %.2f m driven, %lld collision%s, z %.3f..%.3f m\n",
                spec.name.c_str(), sim.time(), wall_s, wall_s > 0 ? sim.time() / wall_s : 0.0, m.distance_m,
                static_cast<long long>(m.collisions), m.collisions == 1 ? "" : "s", m.z_min_m, m.z_max_m);
    if (m.has_reference)
      std::printf("deviation from the reference line: mean %.4f m, max %.4f m\n", m.deviation_mean_m, m.deviation_max_m);
  }
  listing.print(o.json, o.quiet);
  ctx.exit_code = 0;
}

}  // namespace

void register_sim_commands(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<SimOptions>();
  auto* sim = app.add_subcommand("sim", "run a scenario (docs/scenarios.md): the robot follows its scripted commands, or navigates to the goal of a navigation scenario (docs/navigation.md)");
  sim->add_option("scenario", o->scenario, "SCENARIO.yaml")->required();
  sim->add_option("--out", o->out, "output folder (trajectory.csv, events.csv, metrics.json, timing.json, scene.svg, ...)")
      ->required();
  sim->add_option("--seed", o->seed, "random seed (overrides sim.seed)");
  sim->add_option("--duration", o->duration, "simulated seconds (overrides sim.duration_s)");
  sim->add_option("--point-clouds", o->point_clouds, "ply | pcd | none: write LiDAR point clouds (world frame) to OUT/clouds/");
  sim->add_option("--motion-mode", o->motion_mode,
                  "navigation: auto | turn_then_drive | holonomic | pure_pursuit (overrides motion_mode)");
  sim->add_option("--planner", o->planner, "navigation: a global planner (overrides navigation.planner; list below)");
  sim->add_option("--params", o->nav2_params,
                  "a Nav2 parameter file (nav2_params.yaml): its amcl, controller and costmap keys mapped to the scenario's\n"
                  "parameters before --set (docs/ros2.md; starnav params --nav2 FILE lists the mapping)");
  sim->add_option("--controller", o->controller, "navigation: a local controller (overrides navigation.controller; list below)");
  sim->add_option("--set", o->sets,
                  "KEY=VALUE: set any scenario key before it is read, e.g. navigation.follower.look_ahead_m=0.4 "
                  "(repeatable; checked as if written in the file)");
  sim->add_flag("--compare-astar", o->compare_astar, "navigation with an incremental planner (dstar_lite): also run A* from scratch at every plan");
  sim->add_flag("--all-hits", o->step_all_hits, "navigation: steps.jsonl holds every LiDAR return, not only obstacle hits");
  sim->add_option("--controller-pictures", o->controller_pictures,
                  "navigation: T1,T2,... (s): draw the controller's step at each time (controller_T.svg: local map, every\n"
                  "candidate it scored, the chosen one, its own points such as a local goal)")
      ->delimiter(',');
  sim->add_option("--dwa-pictures", o->dwa_pictures, "the old name of --controller-pictures (deprecated)")->delimiter(',');
  sim->add_flag("--png", o->png, "navigation: also write scene.png and overlay.png");
  sim->add_flag("--force", o->force, "write into a non-empty output folder");
  sim->add_flag("--json", o->json, "print metrics.json to stdout");
  sim->add_flag("--quiet", o->quiet, "no progress bar");
  sim->add_flag("--live", o->live,
                "serve the browser viewer and stream the run to it while it goes (docs/viewer.md); "
                "the records written are the same bytes as without it");
  sim->add_flag("--live-wait", o->live_wait, "--live: start the run only once a viewer has connected");
  sim->add_option("--port", o->port, "--live: TCP port (0: any free port; default 8765)")->check(CLI::Range(0, 65535));
  sim->add_option("--bind", o->bind, "--live: address to listen on (default 127.0.0.1)");
  sim->footer(component_help());
  sim->callback([o, &ctx, sim] {
    for (const char* flag : {"--port", "--bind", "--live-wait"})
      if (sim->count(flag) > 0 && !o->live) throw Error("only with --live", "", 0, flag);
    run_sim(*o, ctx);
  });
}

}  // namespace starnav::cli
