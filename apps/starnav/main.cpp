// starnav: the command-line front end. See `starnav --help`.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "commands.hpp"
#include "starnav/config.hpp"
#include "starnav/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"starnav: mobile-robot navigation toolkit and simulator (planners, terrain, LiDAR, robots)", "starnav"};
  app.set_version_flag("--version", std::string("starnav ") + STARNAV_VERSION);
  app.require_subcommand(1);
  starnav::cli::Context ctx;
  starnav::cli::register_map_commands(app, ctx);
  starnav::cli::register_plan_commands(app, ctx);
  starnav::cli::register_bench_commands(app, ctx);
  starnav::cli::register_bench_ablation(app, ctx);
  starnav::cli::register_terrain_commands(app, ctx);
  starnav::cli::register_sim_commands(app, ctx);
  starnav::cli::register_params_command(app, ctx);
  starnav::cli::register_log_commands(app, ctx);
  starnav::cli::register_slam_commands(app, ctx);
  starnav::cli::register_localize_command(app, ctx);
  starnav::cli::register_slam3d_command(app, ctx);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Usage errors: one line, exit 2 (CLI11's own codes are not the project's).
    std::cerr << "starnav: error: " << starnav::escape_control_characters(e.what()) << " (run with --help for usage)\n";
    return 2;
  } catch (const starnav::Error& e) {
    std::cerr << "starnav: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "starnav: error: out of memory\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "starnav: error: " << starnav::escape_control_characters(e.what()) << "\n";
    return 2;
  }
  // A report that did not reach standard output (a full disk, a closed pipe) is a failure.
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "starnav: error: standard output: write failed" << (errno ? std::string(": ") + std::strerror(errno) : "") << "\n";
    return 2;
  }
  return ctx.exit_code;
}
