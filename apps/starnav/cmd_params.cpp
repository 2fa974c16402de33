// starnav params and starnav metrics: the reference pages generated from the declarations
// (docs/parameters.md is `starnav params --markdown`, docs/metrics.md `starnav metrics --markdown`).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "starnav/experiment/limits_docs.hpp"
#include "starnav/experiment/metrics.hpp"
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

  auto limits_markdown_only = std::make_shared<bool>(false);
  auto* limits = app.add_subcommand("limits", "list every bound on an input or on the work a command plans (docs/limits.md)");
  limits->add_flag("--markdown", *limits_markdown_only, "print docs/limits.md (the default output too)");
  limits->callback([&ctx, limits_markdown_only] {
    std::cout << limits_markdown();
    ctx.exit_code = 0;
  });

  auto metrics_markdown_only = std::make_shared<bool>(false);
  auto* metrics = app.add_subcommand("metrics", "list every metric the bench commands report, with its unit and meaning");
  metrics->add_flag("--markdown", *metrics_markdown_only, "print docs/metrics.md (the default output too)");
  metrics->callback([&ctx, metrics_markdown_only] {
    std::cout << metrics_markdown();
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
