#include "commands.hpp"

namespace starnav::cli {
void register_plan_commands(CLI::App& app, Context& ctx) {
  (void)ctx;
  app.add_subcommand("plan", "plan a path on a map");
}
}  // namespace starnav::cli
