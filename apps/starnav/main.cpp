// starnav: the command-line front end. See `starnav --help`.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"

namespace {

// The unknown option on the command line of the subcommand that was parsed, if any. CLI11 checks
// required options before unknown ones, so `plan --bogus` would otherwise be told that --map is
// required: the misspelt option is the real mistake.
std::string first_unknown_option(const CLI::App& app) {
  for (const CLI::App* sub = &app; sub != nullptr;) {
    for (const std::string& arg : sub->remaining(false))
      if (arg.size() > 1 && arg[0] == '-') return arg;
    const auto parsed = sub->get_subcommands();
    sub = parsed.empty() ? nullptr : parsed.front();
  }
  return {};
}

// CLI11's wording for an option given too often ("At Most 1 required but received 2") in plain words.
std::string usage_error_message(const CLI::App& app, const CLI::ParseError& e) {
  std::string msg = e.what();
  if (const std::string unknown = first_unknown_option(app); !unknown.empty()) return "unknown option " + unknown;
  const std::string at_most = "At Most 1 required but received ";
  if (const auto pos = msg.find(at_most); pos != std::string::npos)
    msg = msg.substr(0, pos) + "given " + msg.substr(pos + at_most.size()) + " times; give it once";
  return msg;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// A word where a command (or a subcommand) must come that names none: "unknown command 'simulate'
// (did you mean 'sim'?)". CLI11 would only say that a subcommand is required. Empty when the
// command line names its commands correctly.
std::string unknown_command_message(const CLI::App& app, int argc, char** argv) {
  const CLI::App* current = &app;
  std::string path = "starnav";
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') return {};
    const auto subs = current->get_subcommands([](const CLI::App*) { return true; });
    if (subs.empty() || current->get_require_subcommand_min() == 0) return {};
    const CLI::App* next = nullptr;
    std::vector<std::string> names;
    for (const CLI::App* s : subs) {
      if (s->check_name(word)) next = s;
      names.push_back(s->get_name());
    }
    if (next) {
      current = next;
      path += " " + word;
      continue;
    }
    // The closest names: one is a prefix of the other, or a few letters apart.
    std::vector<std::string> close;
    for (const std::string& n : names)
      if (word.rfind(n, 0) == 0 || n.rfind(word, 0) == 0 || edit_distance(word, n) <= std::max<std::size_t>(1, n.size() / 3))
        close.push_back("'" + n + "'");
    std::string msg = "unknown command '" + word + "' for " + path;
    if (!close.empty()) {
      msg += " (did you mean ";
      for (std::size_t k = 0; k < close.size(); ++k) msg += (k == 0 ? "" : k + 1 == close.size() ? " or " : ", ") + close[k];
      msg += "?)";
    } else {
      msg += " (commands:";
      for (const std::string& n : names) msg += " " + n;
      msg += ")";
    }
    return msg;
  }
  return {};
}

// Names the file whose reading ran out of memory, when a reader was at work.
std::string out_of_memory_message() {
  const std::string file = starnav::input_file_left_by_exception();
  if (file.empty()) return "out of memory";
  return starnav::escape_control_characters(file) + ": out of memory while reading it";
}

// An exception that is not a starnav::Error escaped the checks meant to turn every fault into
// one. Its what() is the implementation's wording ("std::get: wrong index for variant"), which
// never reaches the user as it is: main says what kind of failure it was instead.
std::string internal_error_message() {
  const std::string file = starnav::input_file_left_by_exception();
  return "internal error" + (file.empty() ? std::string() : " while reading " + starnav::escape_control_characters(file)) +
         " (a fault of starnav, not of the input: please report the command line)";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"starnav: mobile-robot navigation toolkit and simulator (planners, terrain, LiDAR, robots)", "starnav"};
  app.set_version_flag("--version", std::string("starnav ") + STARNAV_VERSION);
  app.require_subcommand(1);
  starnav::cli::Context ctx;
  starnav::cli::register_map_commands(app, ctx);
  starnav::cli::register_plan_commands(app, ctx);
  starnav::cli::register_bench_commands(app, ctx);
  starnav::cli::register_bench_ablation(app, ctx);
  starnav::cli::register_terrain_commands(app, ctx);
  starnav::cli::register_sim_commands(app, ctx);
  starnav::cli::register_params_command(app, ctx);
  starnav::cli::register_log_commands(app, ctx);
  starnav::cli::register_slam_commands(app, ctx);
  starnav::cli::register_localize_command(app, ctx);
  starnav::cli::register_slam3d_command(app, ctx);
  starnav::cli::register_view_command(app, ctx);
  starnav::cli::register_sweep_commands(app, ctx);
  starnav::cli::register_export_commands(app, ctx);
  starnav::cli::register_cloud_commands(app, ctx);
  starnav::cli::apply_number_rules(app);

  if (const std::string unknown = unknown_command_message(app, argc, argv); !unknown.empty()) {
    std::cerr << "starnav: error: " << starnav::escape_control_characters(unknown) << " (run with --help for usage)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Usage errors: one line, exit 2 (CLI11's own codes are not the project's).
    std::cerr << "starnav: error: " << starnav::escape_control_characters(usage_error_message(app, e))
              << " (run with --help for usage)\n";
    return 2;
  } catch (const starnav::Error& e) {
    std::cerr << "starnav: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "starnav: error: " << out_of_memory_message() << "\n";
    return 2;
  } catch (const std::length_error&) {
    // A size beyond what can be allocated ("cannot create std::vector larger than max_size()").
    std::cerr << "starnav: error: " << out_of_memory_message() << "\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    const std::string what = e.path1().empty() ? e.code().message() : e.path1().string() + ": " + e.code().message();
    std::cerr << "starnav: error: " << starnav::escape_control_characters(what) << "\n";
    return 2;
  } catch (const std::system_error& e) {
    std::cerr << "starnav: error: " << starnav::escape_control_characters(e.code().message()) << "\n";
    return 2;
  } catch (...) {
    std::cerr << "starnav: error: " << internal_error_message() << "\n";
    return 2;
  }
  starnav::cli::release_warnings();
  // A report that did not reach standard output (a full disk, a closed pipe) is a failure.
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "starnav: error: standard output: write failed" << (errno ? std::string(": ") + std::strerror(errno) : "") << "\n";
    return 2;
  }
  return ctx.exit_code;
}
