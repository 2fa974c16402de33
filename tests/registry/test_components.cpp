// The component registry: one spelling per name, deprecated aliases with a warning, capabilities
// that agree with the components, declared defaults every factory accepts, and docs/parameters.md
// generated from the declarations (this test fails when the file is stale).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/parameter_docs.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

std::vector<ParamSetting> defaults_of(const ComponentInfo& c) {
  std::vector<ParamSetting> out;
  for (const ParamSpec& p : c.params)
    if (p.default_value.find(' ') == std::string::npos)  // rules ("the body's ...") are not values
      out.push_back({p.key, p.default_value, "", 0, p.key});
  return out;
}

TEST(Components, NamesAreUniqueLowerSnakeCaseAndFoundAgain) {
  std::set<std::string> seen;
  for (const ComponentInfo& c : all_components()) {
    EXPECT_TRUE(seen.insert(c.name).second) << c.name;
    EXPECT_EQ(c.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_"), std::string::npos) << c.name;
    EXPECT_FALSE(c.summary.empty()) << c.name;
    EXPECT_FALSE(c.section.empty()) << c.name;
    for (const auto& a : c.deprecated_aliases) EXPECT_TRUE(seen.insert(a).second) << a;
  }
  for (const auto& n : component_names(Role::GlobalPlanner)) EXPECT_EQ(find_global_planner(n).info.name, n);
  for (const auto& n : component_names(Role::LocalController)) EXPECT_EQ(find_local_controller(n).info.name, n);
  for (const auto& n : component_names(Role::Localizer)) EXPECT_EQ(find_localizer(n).info.name, n);
}

TEST(Components, TheOldDStarLiteSpellingIsADeprecatedAlias) {
  std::string warning;
  EXPECT_EQ(find_global_planner("dstarlite", "planner", &warning).info.name, "dstar_lite");
  EXPECT_EQ(warning, "'dstarlite' is deprecated; use 'dstar_lite'");
  find_global_planner("astar", "planner", &warning);
  EXPECT_EQ(warning, "");
  const std::string what = test::error_of([] { find_local_controller("dwa_someday", "navigation.controller"); });
  EXPECT_NE(what.find("path_follower, straight_to_goal"), std::string::npos) << what;
}

TEST(Components, CapabilitiesAgreeWithThePlanners) {
  const auto rough = rough_terrain_planner_names();
  for (const GlobalPlannerDef& d : global_planners()) {
    const bool elevation = std::find(rough.begin(), rough.end(), d.info.name) != rough.end();
    EXPECT_EQ(d.info.has(Capability::NeedsElevation), elevation) << d.info.name;
    EXPECT_EQ(d.info.has(Capability::Incremental), d.info.name == "dstar_lite") << d.info.name;
    if (elevation || d.info.has(Capability::NeedsHeadings)) continue;  // not grid planners
    // Against the planners themselves on a real query: an admissible planner's cost is optimal.
    const auto grid = make_grid_planner(d.info.name, OccupancyGrid(GridGeometry{3, 3, 1.0, {}}, 0));
    EXPECT_EQ(d.info.has(Capability::Admissible), grid->admissible()) << d.info.name;
  }
  EXPECT_TRUE(find_global_planner("oa").info.has(Capability::Admissible));
  EXPECT_FALSE(find_global_planner("ia").info.has(Capability::Admissible));
}

TEST(Components, EveryFactoryAcceptsItsDeclaredDefaultsAndRefusesUnknownKeys) {
  for (const GlobalPlannerDef& d : global_planners()) {
    EXPECT_NO_THROW(d.make({}, defaults_of(d.info))) << d.info.name;
    const std::vector<ParamSetting> bad = {{"no_such_key", "1", "x.yaml", 3, "navigation." + d.info.section + ".no_such_key"}};
    const std::string what = test::error_of([&] { d.make({}, bad); });
    EXPECT_NE(what.find("no_such_key"), std::string::npos) << what;
  }
  for (const LocalControllerDef& d : local_controllers()) {
    EXPECT_NO_THROW(d.make({}, defaults_of(d.info))) << d.info.name;
    const std::vector<ParamSetting> bad = {{"no_such_key", "1", "x.yaml", 3, "k"}};
    EXPECT_THROW(d.make({}, bad), Error) << d.info.name;
  }
  for (const LocalizerDef& d : localizers()) {
    EXPECT_NO_THROW(d.make({}, defaults_of(d.info))) << d.info.name;
    const std::vector<ParamSetting> bad = {{"no_such_key", "1", "x.yaml", 3, "k"}};
    EXPECT_THROW(d.make({}, bad), Error) << d.info.name;
  }
}

TEST(Components, ParametersMarkdownIsCurrent) {
  const std::string path = (std::filesystem::path(STARNAV_SOURCE_DIR) / "docs" / "parameters.md").string();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  EXPECT_TRUE(test::read_text(path) == parameters_markdown())
      << "docs/parameters.md is stale: run `build/bin/starnav params --markdown > docs/parameters.md`";
  // Every component and every navigation parameter is on the page.
  const std::string md = parameters_markdown();
  for (const ComponentInfo& c : all_components()) {
    EXPECT_NE(md.find("### `" + c.name + "`"), std::string::npos) << c.name;
    for (const ParamSpec& p : c.params) {
      // Elevation planners are not navigation components, and SLAM methods and scan matchers are
      // set by their commands' --set: their keys stand alone.
      const bool bare = c.has(Capability::NeedsElevation) || c.role == Role::Slam || c.role == Role::ScanMatcher ||
                        c.role == Role::ScanMatcher3d;
      const std::string key = bare ? "`" + p.key + "`" : "." + c.section + "." + p.key + "`";
      EXPECT_NE(md.find(key), std::string::npos) << p.key;
    }
  }
  for (const ParamSpec& p : navigation_params().specs()) EXPECT_NE(md.find("`navigation." + p.key + "`"), std::string::npos);
}

// `starnav params --role ROLE`: every component of the role and no other, each with every one of
// its parameters; every role has a name that reads back.
TEST(Components, EachRoleListsItsComponentsAndTheirParameters) {
  for (Role role : kAllRoles) {
    ASSERT_EQ(role_from_name(role_name(role)), role);
    const std::string text = role_components_text(role);
    for (const ComponentInfo& c : all_components()) {
      const bool listed = text.find(c.name + ": " + c.summary + "\n") != std::string::npos;
      EXPECT_EQ(listed, c.role == role) << role_name(role) << " " << c.name;
      if (c.role != role) continue;
      for (const ParamSpec& p : c.params) EXPECT_NE(text.find(p.key + " (" + param_type_name(p.type)), std::string::npos) << p.key;
    }
  }
  EXPECT_FALSE(role_from_name("planner").has_value());
}

}  // namespace
}  // namespace starnav
