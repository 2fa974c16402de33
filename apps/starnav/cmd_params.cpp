// starnav params: every component and parameter, generated from their declarations
// (docs/parameters.md is `starnav params --markdown`).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "starnav/harness/parameter_docs.hpp"

namespace starnav::cli {

void register_params_command(CLI::App& app, Context& ctx) {
  struct Options {
    bool markdown = false;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("params", "list every component (planners, controllers, localizers) and its declared parameters");
  cmd->add_flag("--markdown", o->markdown, "print docs/parameters.md");
  cmd->add_flag("--json", o->json, "print JSON: one object per component with its parameters");
  cmd->callback([o, &ctx] {
    if (o->json) std::cout << parameters_json();
    else if (o->markdown) std::cout << parameters_markdown();
    else std::cout << component_help();
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
