// starnav params and starnav metrics: the reference pages generated from the declarations
// (docs/parameters.md is `starnav params --markdown`, docs/metrics.md `starnav metrics --markdown`).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "nav2_flags.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/limits_docs.hpp"
#include "starnav/experiment/metrics.hpp"
#include "starnav/harness/parameter_docs.hpp"
#include "starnav/sim/scenario_keys.hpp"
#include "starnav/core/input_file.hpp"

namespace starnav::cli {

namespace {

// A command that prints one generated reference page; --markdown is accepted (the page is the
// default output too), so the docs' regeneration commands read the same for every page.
void add_page_command(CLI::App& app, Context& ctx, const char* name, const char* help, const std::string& page,
                      std::string (*generate)()) {
  auto markdown = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand(name, help);
  cmd->add_flag("--markdown", *markdown, "print " + page + " (the default output too)");
  cmd->callback([&ctx, markdown, generate] {
    std::cout << generate();
    ctx.exit_code = 0;
  });
}

// starnav scenario-keys: every mapping of a scenario and its declared keys; --fill regenerates
// the marked tables of a page (docs/scenarios.md).
void register_scenario_keys_command(CLI::App& app, Context& ctx) {
  struct Options {
    bool markdown = false;
    std::string section, fill;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("scenario-keys", "list every key of a scenario file with its type, default, range and unit");
  cmd->add_flag("--markdown", o->markdown, "print every section's table as Markdown (the default output too)");
  cmd->add_option("--section", o->section, "only this section's table (an id: robot, sensors.lidar, world.obstacles.box, ...)");
  cmd->add_option("--fill", o->fill,
                  "print this page with its generated blocks (<!-- BEGIN scenario-keys ID ... --> ... <!-- END scenario-keys ID -->)\n"
                  "regenerated: `starnav scenario-keys --fill docs/scenarios.md`");
  cmd->callback([o, &ctx] {
    if (!o->fill.empty()) {
      if (!o->section.empty()) throw Error("--fill regenerates every block of the page; --section prints one table", {}, 0, "--section");
      std::string page;
      try {
        page = read_input_file(o->fill);
      } catch (const Error& e) {
        throw Error(e.message(), o->fill, e.line(), e.field());
      }
      try {
        std::cout << scenario_page_with_keys(page);
      } catch (const Error& e) {
        throw Error(e.message(), o->fill, e.line(), e.field());
      }
    } else if (!o->section.empty()) {
      std::string ids;
      for (const ScenarioKeySection& s : scenario_key_sections()) {
        if (s.id == o->section) {
          std::cout << scenario_keys_table(s);
          ctx.exit_code = 0;
          return;
        }
        ids += (ids.empty() ? "" : ", ") + s.id;
      }
      throw Error("unknown section '" + o->section + "' (" + ids + ")", {}, 0, "--section");
    } else {
      std::cout << scenario_keys_markdown();
    }
    ctx.exit_code = 0;
  });
}

}  // namespace

void register_params_command(CLI::App& app, Context& ctx) {
  struct Options {
    bool markdown = false;
    bool json = false;
    std::string role;
    std::string nav2, scenario;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("params", "list every component (planners, controllers, localizers) and its declared parameters");
  cmd->add_flag("--markdown", o->markdown, "print docs/parameters.md");
  cmd->add_flag("--json", o->json, "print JSON: one object per component with its parameters");
  std::string roles;
  for (Role r : kAllRoles) roles += std::string(roles.empty() ? "" : ", ") + role_name(r);
  cmd->add_option("--role", o->role, "only the components of this role (" + roles + "): summary, capabilities, parameters");
  cmd->add_option("--nav2", o->nav2,
                  "a Nav2 parameter file: print which keys map to which starnav parameters (converted) and which are ignored\n"
                  "and why, as localize reads it, or as sim reads it for --scenario (docs/ros2.md)");
  cmd->add_option("--scenario", o->scenario, "with --nav2: the scenario whose components decide the mapping");
  cmd->callback([o, &ctx, roles] {
    if (!o->scenario.empty() && o->nav2.empty()) throw Error("only with --nav2", o->scenario, 0, "--scenario");
    if (!o->nav2.empty()) {
      if (!o->role.empty()) throw Error("--nav2 lists a Nav2 file's mapping; --role a role's components", {}, 0, "--role");
      Nav2Target target;
      target.kind = Nav2Target::Kind::Localize;
      if (!o->scenario.empty()) target = scenario_nav2_target(load_scenario(o->scenario), "");
      const Nav2Params p = read_nav2_params(o->nav2, target);
      std::cout << (o->json ? nav2_params_json(p) : nav2_params_text(p));
      ctx.exit_code = 0;
      return;
    }
    if (!o->role.empty()) {
      const std::optional<Role> role = role_from_name(o->role);
      if (!role) throw Error("unknown role '" + o->role + "' (roles: " + roles + ")", {}, 0, "--role");
      if (o->json || o->markdown) throw Error("--role prints text; --json and --markdown print every component", {}, 0, "--role");
      std::cout << role_components_text(*role);
      ctx.exit_code = 0;
      return;
    }
    if (o->json) std::cout << parameters_json();
    else if (o->markdown) std::cout << parameters_markdown();
    else std::cout << component_help();
    ctx.exit_code = 0;
  });

  add_page_command(app, ctx, "limits", "list every bound on an input or on the work a command plans (docs/limits.md)",
                   "docs/limits.md", limits_markdown);
  register_scenario_keys_command(app, ctx);
  add_page_command(app, ctx, "metrics", "list every metric the bench commands report, with its unit and meaning",
                   "docs/metrics.md", metrics_markdown);
}

}  // namespace starnav::cli
