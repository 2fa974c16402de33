#include "cli_util.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav::cli {

bool parse_double(const std::string& s, double& out) {
  const std::optional<double> v = parse_real_text(s);
  if (v) out = *v;
  return v.has_value();
}

std::uint64_t parse_unsigned(const std::string& text, const std::string& flag, const std::string& what) {
  const std::optional<std::uint64_t> v = parse_unsigned_text(text);
  if (v) return *v;
  const std::string_view digits = text;
  if (!digits.empty() && digits.find_first_not_of("0123456789") == std::string_view::npos)
    throw Error("out of range (at most 2^64 - 1), got '" + printable(text, 40) + "'", {}, 0, flag);
  throw Error("expected " + what + ", got '" + printable(text, 40) + "'", {}, 0, flag);
}

void apply_number_rules(CLI::App& app) {
  // CLI11 reads integers with strtoull(base 0): "-1" wraps to 2^64 - 1, "010" is eight, "0x10"
  // sixteen. A check on the text, before CLI11 converts it, keeps every numeric flag to the one
  // decimal reading of core/number_text.hpp: each rule refuses the text unless `accepts` it.
  const auto rule = [](bool (*accepts)(const std::string&), const char* what, const char* name) {
    return CLI::Validator(
        [accepts, what](std::string& text) -> std::string {
          if (accepts(text)) return {};
          return text.empty() ? std::string("empty value") : std::string("expected ") + what + ", got '" + printable(text, 40) + "'";
        },
        "", name);
  };
  for (CLI::Option* opt : app.get_options()) {
    // A check already on the option (CLI::Range) extends the name: "INT:INT in [0 - 65535]".
    const std::string full_type = opt->get_type_name();
    const std::string type = full_type.substr(0, full_type.find(':'));
    // Every whole number a flag takes is a count, a size, a port or a seed (signed quantities are
    // reals): one rule for them, whatever C++ type holds the value, so that no flag reads "-1" as
    // "all" while another refuses it.
    if (type == "UINT" || type == "INT")
      opt->check(rule([](const std::string& t) { return parse_unsigned_text(t).has_value(); }, "a non-negative whole number",
                      "decimal count"));
    else if (type == "FLOAT")
      opt->check(rule([](const std::string& t) { return parse_real_text(t).has_value(); }, "a finite number", "decimal number"));
    else if (type == "TEXT")
      opt->check(rule([](const std::string& t) { return !t.empty(); }, "a value", "non-empty"));
  }
  for (CLI::App* sub : app.get_subcommands({})) apply_number_rules(*sub);
}

std::vector<double> parse_number_list(const std::string& text, const std::string& flag, std::size_t count,
                                      const std::string& what) {
  std::vector<double> values;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    double v = 0.0;
    if (!parse_double(text.substr(begin, comma - begin), v)) throw Error("expected " + what + ", got '" + text + "'", {}, 0, flag);
    values.push_back(v);
    begin = comma + 1;
  }
  if (values.size() != count) throw Error("expected " + what + ", got '" + text + "'", {}, 0, flag);
  return values;
}

Vec2 parse_xy(const std::string& text, const std::string& flag) {
  const auto comma = text.find(',');
  double x = 0, y = 0;
  if (comma == std::string::npos || !parse_double(text.substr(0, comma), x) ||
      !parse_double(text.substr(comma + 1), y))
    throw Error("expected X,Y (two numbers), got '" + text + "'", {}, 0, flag);
  return {x, y};
}

Cell parse_endpoint_cell(const std::string& text, const std::string& flag, bool in_cells, const GridGeometry& g) {
  return plan_endpoint_cell(parse_xy(text, flag), in_cells, g, flag, text);
}

void rethrow_with_flag(const Error& e, const std::vector<std::pair<std::string, std::string>>& renamed) {
  for (const auto& [field, flag] : renamed)
    if (e.field() == field) throw Error(e.message(), {}, 0, flag);
  std::string flag = "--" + e.field();
  std::replace(flag.begin(), flag.end(), '_', '-');
  throw Error(e.message(), {}, 0, flag);
}

std::vector<ParamSetting> parse_set_options(const std::vector<std::string>& sets) {
  std::vector<ParamSetting> out;
  for (const std::string& s : sets) {
    const std::size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("expected KEY=VALUE, got '" + printable(s, 60) + "'", {}, 0, "--set");
    const std::string key = s.substr(0, eq);
    for (const ParamSetting& earlier : out)
      if (earlier.key == key) throw Error("given twice; give each key once", {}, 0, "--set " + key);
    out.push_back({key, s.substr(eq + 1), {}, 0, "--set " + key});
  }
  return out;
}

void check_output_path(const std::string& path, bool force, const std::string& flag) {
  namespace fs = std::filesystem;
  if (path.empty()) throw Error("empty output path", {}, 0, flag);
  if (fs::exists(path) && !force) throw Error("exists already (use --force to overwrite)", path, 0, flag);
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent)) throw Error("folder does not exist", path, 0, flag);
}

void add_map_files(std::vector<CommandFile>& files, const std::string& path, MapFormat format,
                   const std::optional<RosMapMetadata>& ros, const std::string& flag) {
  const std::vector<std::string> written = map_output_files(path, format, ros);
  for (std::size_t i = 0; i < written.size(); ++i)
    files.push_back({written[i], i == 0 ? flag : flag + " (written beside " + path + ")", true});
}

void add_map_files(std::vector<CommandFile>& files, const LoadedMap& map, const std::string& flag) {
  for (std::size_t i = 0; i < map.files.size(); ++i)
    files.push_back({map.files[i], i == 0 ? flag : flag + " (read with " + map.files[0] + ")", false});
}

namespace {

// What makes two names one file: the device and inode of an existing file (after links), else
// the canonical path of a file still to be written.
struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  std::string path;
  bool operator==(const FileIdentity& o) const {
    return exists == o.exists && (exists ? device == o.device && inode == o.inode : path == o.path);
  }
};

FileIdentity identity_of(const std::string& path) {
  FileIdentity id;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    id.exists = true;
    id.device = st.st_dev;
    id.inode = st.st_ino;
    return id;
  }
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(absolute, ec);
  id.path = (ec ? absolute.lexically_normal() : canonical).string();
  return id;
}

}  // namespace

void check_distinct_files(const std::vector<CommandFile>& files) {
  std::vector<FileIdentity> ids;
  ids.reserve(files.size());
  for (const CommandFile& f : files) ids.push_back(identity_of(f.path));
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!files[i].output) continue;
    for (std::size_t j = 0; j < files.size(); ++j) {
      if (j == i || (files[j].output && j > i) || !(ids[i] == ids[j])) continue;
      // Named by the later output, against the earlier output or against the input it would replace.
      if (files[j].output)
        throw Error("the same file as " + files[j].what + ": each output needs a file of its own", files[i].path, 0, files[i].what);
      throw Error("the same file as the input " + files[j].what + ": an output never replaces an input", files[i].path, 0,
                  files[i].what);
    }
  }
}

void write_text_file(const std::string& path, const std::string& text, const std::string& flag) {
  try {
    write_file_atomically(path, text);
  } catch (const Error& e) {
    throw Error(e.message(), path, 0, flag);
  }
}

bool picture_is_png(const std::string& path, const std::string& flag) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return true;
  if (ext == ".svg") return false;
  throw Error("picture must end in .svg or .png", path, 0, flag);
}

ProgressBar::ProgressBar(std::string label, std::size_t total, bool quiet)
    : label_(std::move(label)), total_(total), enabled_(!quiet), tty_(!quiet && ::isatty(2) == 1) {}

void ProgressBar::update(std::size_t done, const std::string& what) {
  if (!enabled_ || total_ == 0) return;
  release_warnings();
  if (!tty_) {
    // One line per tenth of the work, and at the end.
    if (done < next_line_ && done != total_) return;
    next_line_ = done + std::max<std::size_t>(1, (total_ + 9) / 10);
    std::fprintf(stderr, "%s: %zu/%zu %s\n", label_.c_str(), done, total_, what.c_str());
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (done != 0 && done != total_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  constexpr int kWidth = 24;
  const int filled = std::clamp(static_cast<int>(static_cast<double>(done) / static_cast<double>(total_) * kWidth), 0, kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::string line = label_ + " [" + bar + "] " + std::to_string(done) + "/" + std::to_string(total_) + " " + what;
  if (line.size() > 79) line.resize(79);  // one line of an 80-column terminal
  std::fprintf(stderr, "\r%-79s", line.c_str());
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (tty_) std::fprintf(stderr, "\r%-79s\r", "");
}

namespace {

// Every regular file under `dir` (relative paths, sorted) with its last write time; nothing when
// the folder does not exist yet.
std::vector<std::pair<std::string, std::filesystem::file_time_type>> files_under(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, fs::file_time_type>> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (!it->is_regular_file(ec) || it->path().filename().string().front() == '.') continue;  // the folder's lock
    out.emplace_back(fs::relative(it->path(), dir, ec).generic_string(), it->last_write_time(ec));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

OutputListing::OutputListing(std::string dir) : dir_(std::move(dir)), before_(files_under(dir_)) {}

std::string OutputListing::wrote_line() const {
  std::vector<std::string> top;                            // files directly in the folder
  std::vector<std::pair<std::string, std::size_t>> subs;  // subfolder, files written in it
  for (const auto& [name, time] : files_under(dir_)) {
    const auto was = std::lower_bound(before_.begin(), before_.end(), std::make_pair(name, std::filesystem::file_time_type::min()));
    if (was != before_.end() && was->first == name && was->second == time) continue;  // untouched
    const std::size_t slash = name.find('/');
    if (slash == std::string::npos) {
      top.push_back(name);
      continue;
    }
    const std::string sub = name.substr(0, slash + 1);
    if (subs.empty() || subs.back().first != sub) subs.emplace_back(sub, 0);
    ++subs.back().second;
  }
  if (top.empty() && subs.empty()) return "wrote nothing in " + dir_;
  std::string s = "wrote " + dir_ + "/{";
  bool first = true;
  for (const std::string& f : top) {
    s += (first ? "" : ", ") + f;
    first = false;
  }
  for (const auto& [sub, n] : subs) {
    s += (first ? "" : ", ") + sub + " (" + std::to_string(n) + (n == 1 ? " file)" : " files)");
    first = false;
  }
  return s + "}";
}

void OutputListing::print(bool stdout_is_a_document, bool quiet) const {
  if (!stdout_is_a_document) {
    std::printf("%s\n", wrote_line().c_str());
  } else if (!quiet) {
    std::fflush(stdout);
    std::fprintf(stderr, "%s\n", wrote_line().c_str());
  }
}

OutputFolder check_out_dir(const std::string& dir, bool force) {
  namespace fs = std::filesystem;
  if (dir.empty()) throw Error("empty output folder", {}, 0, "--out");
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw Error("exists and is not a folder", dir, 0, "--out");
    // A lock file left by a run that was killed does not count.
    bool empty = true;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
      if (e.path().filename() != ".starnav-lock") empty = false;
    if (!empty && !force) throw Error("folder exists and is not empty (use --force to overwrite)", dir, 0, "--out");
  }
  return OutputFolder(dir, "--out");
}

namespace {
// Warnings wait until the command gets past its inputs (its long work starts, or it ends without an
// error): a command that refuses its input says one error line, not the warnings of the reading.
std::vector<std::string>& held_warnings() {
  static std::vector<std::string> held;
  return held;
}
bool& warnings_released() {
  static bool released = false;
  return released;
}
}  // namespace

void print_warning(const std::string& text) {
  const std::string line = "starnav: warning: " + escape_control_characters(text) + "\n";
  if (warnings_released()) std::fputs(line.c_str(), stderr);
  else held_warnings().push_back(line);
}

void release_warnings() {
  warnings_released() = true;
  for (const std::string& line : held_warnings()) std::fputs(line.c_str(), stderr);
  held_warnings().clear();
}

void warn_if_served_beyond_loopback(const std::string& bind) {
  if (bind != "127.0.0.1" && bind != "localhost" && bind != "::1")
    std::fprintf(stderr, "starnav: warning: --bind %s: the run is served to every machine that can reach this address\n", bind.c_str());
}

std::string executable_path() {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

}  // namespace starnav::cli
