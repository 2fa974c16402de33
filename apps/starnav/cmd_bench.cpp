#include "commands.hpp"

namespace starnav::cli {
void register_bench_commands(CLI::App& app, Context& ctx) {
  (void)ctx;
  app.add_subcommand("bench", "benchmarks and reproductions");
}
}  // namespace starnav::cli
