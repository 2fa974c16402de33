#pragma once
// docs/limits.md: every bound starnav puts on an input or on the work a command plans, generated
// from the constants the code checks (a test keeps the page current; `starnav limits` prints it).
#include <string>

namespace starnav {

std::string limits_markdown();

}  // namespace starnav
