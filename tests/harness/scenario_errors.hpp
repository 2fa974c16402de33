#pragma once
// Shared by the navigation tests: a scenario that must be refused, with the error naming the
// file, a line and `field` (when parsing, or with at_run when the run is set up).
#include <gtest/gtest.h>

#include <string>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::test {

inline void expect_scenario_error(const std::string& yaml, const std::string& field, bool at_run = false) {
  try {
    const ScenarioSpec spec = parse_scenario(yaml, "bad.yaml");
    if (!at_run) FAIL() << "parsed: " << field;
    NavigationRun run(spec);
    FAIL() << "accepted: " << field;
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "bad.yaml") << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_GT(e.line(), 0) << e.what();
  }
}

}  // namespace starnav::test
