// starnav export mcap: a run record as an MCAP file that Foxglove opens (experiment/mcap_export.hpp,
// docs/ros2.md).
//
//   starnav export mcap RUN_FOLDER OUT.mcap [--ros2] [--json] [--force]
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/experiment/mcap_export.hpp"

namespace starnav::cli {

void register_export_commands(CLI::App& app, Context& ctx) {
  auto* exp = app.add_subcommand("export", "a run folder in another format");
  exp->require_subcommand(1);
  struct Options {
    std::string run, out;
    bool ros2 = false, json = false, force = false;
  };
  auto o = std::make_shared<Options>();
  auto* mcap = exp->add_subcommand(
      "mcap",
      "a run record (sim, slam run, localize) as MCAP for Foxglove: the world, maps, the robot's transform, trajectory,\n"
      "LiDAR hits and scans, plans and particles over the run's clock (Foxglove's schemas; --ros2: ROS 2 messages)");
  mcap->add_option("RUN_FOLDER", o->run, "a run folder (with run.json)")->required();
  mcap->add_option("OUT", o->out, "the MCAP file to write")->required();
  mcap->add_flag("--ros2", o->ros2, "ROS 2 messages (OccupancyGrid, LaserScan, Path, tf) in CDR, to replay into a ROS 2 stack");
  mcap->add_flag("--json", o->json, "print the summary as one JSON object");
  mcap->add_flag("--force", o->force, "overwrite OUT");
  mcap->callback([o, &ctx] {
    check_output_path(o->out, o->force, "OUT");
    McapExportOptions options;
    options.ros2 = o->ros2;
    const McapExportSummary s = export_run_mcap(o->run, o->out, options);
    if (o->json) {
      nlohmann::ordered_json j;
      j["file"] = o->out;
      j["messages"] = s.messages;
      j["topics"] = s.per_topic;
      j["first_s"] = s.first_s;
      j["last_s"] = s.last_s;
      std::cout << j.dump() << "\n";
    } else {
      std::cout << "wrote " << o->out << ": " << s.messages << " messages on " << s.per_topic.size() << " topics ("
                << format_fixed(s.last_s - s.first_s, 1) << " s)\n";
    }
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
