// starnav map info | convert | render
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/map_report.hpp"
#include "starnav/io/map_file.hpp"

namespace starnav::cli {

namespace {

struct MapInfoOptions {
  std::string file;
  bool json = false;
};

void run_map_info(const MapInfoOptions& o) {
  const LoadedMap m = load_map(o.file);
  const GridGeometry& g = m.geometry();
  const std::string info = map_info_json(m, o.file);
  if (o.json) {
    std::cout << info;
    return;
  }
  const nlohmann::ordered_json j = nlohmann::ordered_json::parse(info);
  std::cout << "file:        " << o.file << "\n";
  std::cout << "format:      " << map_format_name(m.format) << "\n";
  std::cout << "size:        " << g.width << " x " << g.height << " cells";
  if (!g.y_down) std::cout << " (" << g.width_m() << " m x " << g.height_m() << " m)";
  std::cout << "\n";
  std::cout << "resolution:  " << g.resolution << " m/cell\n";
  std::cout << "origin:      [" << g.origin.x << ", " << g.origin.y << ", " << g.origin.yaw << "]"
            << (g.y_down ? "  (index grid: x column, y row from the top)" : "") << "\n";
  if (m.is_elevation()) {
    std::cout << "observed:    " << j["observed"] << " cells, unobserved: " << j["unobserved"] << "\n";
    if (j["z_min_m"].is_null())
      std::cout << "heights:     none observed\n";
    else
      std::cout << "heights:     " << j["z_min_m"].get<double>() << " m .. " << j["z_max_m"].get<double>() << " m\n";
  } else {
    std::cout << "free:        " << j["free"] << "\noccupied:    " << j["occupied"] << "\nunknown:     " << j["unknown"]
              << "\n";
  }
}

struct MapConvertOptions {
  std::string in;
  std::string out;
  bool force = false;
};

void run_map_convert(const MapConvertOptions& o) {
  const LoadedMap m = load_map(o.in);
  const MapFormat target = output_map_format(o.out, m.is_elevation());
  check_map_writable(m, o.out, target);
  for (const std::string& f : map_output_files(o.out, target, m.ros)) check_output_path(f, o.force, "OUT");
  std::vector<CommandFile> files;
  add_map_files(files, m, "IN");
  add_map_files(files, o.out, target, m.ros, "OUT");
  check_distinct_files(files);
  for (const std::string& loss : map_conversion_losses(m, target)) print_warning(o.out + ": " + loss);
  save_map(m, o.out, target);
  std::cout << "wrote " << o.out << " (" << map_format_name(target) << ")\n";
}

}  // namespace

void register_map_commands(CLI::App& app, Context& ctx) {
  auto* map = app.add_subcommand("map", "inspect, convert and render map files");
  map->require_subcommand(1);

  auto info_opts = std::make_shared<MapInfoOptions>();
  auto* info = map->add_subcommand("info", "size, resolution, origin and cell counts (or height range) of a map file");
  info->add_option("FILE", info_opts->file, "map file (.map, .yaml, .asc, .csv, .raw, .tif)")->required();
  info->add_flag("--json", info_opts->json, "print one JSON object");
  info->callback([info_opts, &ctx] {
    run_map_info(*info_opts);
    ctx.exit_code = 0;
  });

  auto conv_opts = std::make_shared<MapConvertOptions>();
  auto* conv = map->add_subcommand("convert", "convert a map between formats (chosen by OUT's extension)");
  conv->add_option("IN", conv_opts->in, "input map file")->required();
  conv->add_option("OUT", conv_opts->out, "output map file")->required();
  conv->add_flag("--force", conv_opts->force, "overwrite OUT if it exists");
  conv->callback([conv_opts, &ctx] {
    run_map_convert(*conv_opts);
    ctx.exit_code = 0;
  });

  register_map_render(*map, ctx);
  register_map_build(*map, ctx);
}

}  // namespace starnav::cli
