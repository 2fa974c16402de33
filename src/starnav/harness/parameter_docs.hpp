#pragma once
// The reference of every component and parameter, generated from their declarations (the
// registry and the navigation section's table): docs/parameters.md is exactly
// parameters_markdown() (a test checks it), `starnav params` prints it, and `--help` texts list
// the components from component_help().
#include <string>

#include "starnav/core/component.hpp"

namespace starnav {

// docs/parameters.md.
std::string parameters_markdown();
// Every component with its parameters as JSON (role, name, aliases, section, capabilities,
// params: key, type, default, range, unit, doc).
std::string parameters_json();
// A few lines for --help: each role's component names and where their parameters go.
std::string component_help();
// `starnav params --role ROLE`: each component of the role, its summary, capabilities and
// parameters (key, type, default, range, unit, meaning), one per line.
std::string role_components_text(Role role);

}  // namespace starnav
