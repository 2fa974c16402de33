#pragma once
// The independent ROS 1 -> ROS 2 converter (tools/ros2-convert, JavaScript on npm's @mcap/core,
// @foxglove/rosmsg2-serialization and better-sqlite3) and the exported-MCAP checker, run with the
// machine's Node.js. Tests using them skip when Node or the npm packages are absent.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav::test {

inline std::string ros2_tools_dir() { return (fs::path(STARNAV_SOURCE_DIR) / "tools" / "ros2-convert").string(); }

inline bool have_ros2_tools() {
  return std::system("command -v node >/dev/null 2>&1") == 0 &&
         fs::exists(fs::path(ros2_tools_dir()) / "node_modules" / "@mcap" / "core" / "package.json");
}

// node tools/ros2-convert/SCRIPT ARGS...: exit code, stdout and stderr.
inline CliResult run_ros2_tool(const std::string& script, const std::vector<std::string>& args) {
  static int counter = 0;
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string out_path = (fs::temp_directory_path() / ("starnav_node_out_" + tag)).string();
  const std::string err_path = (fs::temp_directory_path() / ("starnav_node_err_" + tag)).string();
  std::string cmd = "node " + shell_quote((fs::path(ros2_tools_dir()) / script).string());
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  cmd.append(" >").append(shell_quote(out_path)).append(" 2>").append(shell_quote(err_path)).append(" </dev/null");
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  r.out = read_text(out_path);
  r.err = read_text(err_path);
  fs::remove(out_path);
  fs::remove(err_path);
  return r;
}

}  // namespace starnav::test
