#include "commands.hpp"

namespace starnav::cli {
void register_map_commands(CLI::App& app, Context& ctx) {
  (void)ctx;
  auto* map = app.add_subcommand("map", "inspect, convert and render map files");
  map->require_subcommand(1);
}
}  // namespace starnav::cli
