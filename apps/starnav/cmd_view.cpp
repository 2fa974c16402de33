// starnav view: the browser viewer of a run folder, served on loopback or exported to one page.
#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/view/run_folder.hpp"
#if STARNAV_HAVE_HTTP
#include "starnav/view/run_server.hpp"
#endif

namespace starnav::cli {

namespace {

struct ViewOptions {
  std::string run_dir;
  int port = 8765;
  std::string bind = "127.0.0.1";
  std::string export_path;
  bool force = false;
};

void run_view(const ViewOptions& o, Context& ctx) {
  const RunFolder run = read_run_folder(o.run_dir);
  const std::string viewer = find_viewer_dir(viewer_dir_candidates(executable_path()));
  if (!o.export_path.empty()) {
    check_output_path(o.export_path, o.force, "--export");
    write_text_file(o.export_path, export_run_html(run, viewer), "--export");
    std::printf("wrote %s (open it in a browser; it needs no server)\n", o.export_path.c_str());
    ctx.exit_code = 0;
    return;
  }
#if STARNAV_HAVE_HTTP
  // Ctrl-C and SIGTERM are taken by this thread (sigwait), not by the server's threads.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  RunServerOptions options;
  options.run_dir = o.run_dir;
  options.viewer_dir = viewer;
  options.host = o.bind;
  options.port = o.port;
  RunServer server(options);  // a --bind or --port it cannot listen on is the one error line
  if (!server.loopback_only()) warn_if_served_beyond_loopback(o.bind);
  server.start();
  std::printf("starnav: viewing %s at %s (Ctrl-C stops)\n", o.run_dir.c_str(), server.url().c_str());
  std::fflush(stdout);
  int received = 0;
  sigwait(&signals, &received);
  server.stop();
  ctx.exit_code = 0;
#else
  throw Error("this starnav was built without its HTTP server (STARNAV_WITH_HTTP=OFF): use --export", "", 0, "--port");
#endif
}

}  // namespace

void register_view_command(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ViewOptions>();
  auto* view = app.add_subcommand("view", "view a run folder (the --out of sim, slam run, localize or slam3d) in the browser: "
                                          "3D world, robot, LiDAR, paths and map over a timeline (docs/viewer.md)");
  view->add_option("run_dir", o->run_dir,
                   "RUN_DIR: a folder written by starnav sim, slam run, localize or slam3d (it holds run.json)")
      ->required();
  view->add_option("--port", o->port, "TCP port to serve on (0: any free port; default 8765)")->check(CLI::Range(0, 65535));
  view->add_option("--bind", o->bind, "address to listen on (default 127.0.0.1, this machine only; anything else is warned about)");
  view->add_option("--export", o->export_path, "FILE.html: write one self-contained page (viewer and run) instead of serving");
  view->add_flag("--force", o->force, "overwrite the --export file");
  view->callback([o, &ctx] { run_view(*o, ctx); });
}

}  // namespace starnav::cli
