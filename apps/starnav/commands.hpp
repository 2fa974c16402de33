#pragma once
// Each CLI command family registers its subcommands on the root app. A command's callback
// stores its exit code in `exit_code` (0 success, 1 no answer, 2 bad input) and throws
// starnav::Error for bad input; main() prints one `starnav: error: ...` line for it.
#include <CLI/CLI.hpp>

namespace starnav::cli {

struct Context {
  int exit_code = 0;
};

void register_map_commands(CLI::App& app, Context& ctx);    // cmd_map.cpp
void register_plan_commands(CLI::App& app, Context& ctx);   // cmd_plan.cpp
void register_bench_commands(CLI::App& app, Context& ctx);  // cmd_bench.cpp
void register_bench_ablation(CLI::App& app, Context& ctx);  // cmd_bench_ablation.cpp (after register_bench_commands)
void register_bench_terrain(CLI::App& app, Context& ctx);   // cmd_bench_terrain.cpp (called by register_bench_commands)
void register_bench_nav(CLI::App& app, Context& ctx);       // cmd_bench_nav.cpp (called by register_bench_commands)
void register_bench_slam(CLI::App& app, Context& ctx);      // cmd_bench_slam.cpp (called by register_bench_commands)
void register_bench_localization(CLI::App& app, Context& ctx);  // cmd_bench_localization.cpp (called by register_bench_commands)
void register_bench_ren(CLI::App& app, Context& ctx);           // cmd_bench_ren.cpp (called by register_bench_commands)
void register_bench_cloud(CLI::App& app, Context& ctx);         // cmd_bench_cloud.cpp (called by register_bench_commands)
void register_map_render(CLI::App& map, Context& ctx);       // cmd_map_render.cpp
void register_map_build(CLI::App& map, Context& ctx);        // cmd_map_build.cpp
void register_terrain_commands(CLI::App& app, Context& ctx);  // cmd_terrain.cpp
void register_sim_commands(CLI::App& app, Context& ctx);      // cmd_sim.cpp
void register_params_command(CLI::App& app, Context& ctx);    // cmd_params.cpp
void register_log_commands(CLI::App& app, Context& ctx);      // cmd_log.cpp
void register_slam_commands(CLI::App& app, Context& ctx);     // cmd_slam.cpp
void register_slam_benchmark_commands(CLI::App* slam, Context& ctx);  // cmd_slam_benchmark.cpp (called by register_slam_commands)
void register_localize_command(CLI::App& app, Context& ctx);  // cmd_localize.cpp
void register_slam3d_command(CLI::App& app, Context& ctx);    // cmd_slam3d.cpp
void register_view_command(CLI::App& app, Context& ctx);      // cmd_view.cpp
void register_sweep_commands(CLI::App& app, Context& ctx);    // cmd_sweep.cpp
void register_export_commands(CLI::App& app, Context& ctx);   // cmd_export.cpp
void register_cloud_commands(CLI::App& app, Context& ctx);    // cmd_cloud.cpp

}  // namespace starnav::cli
