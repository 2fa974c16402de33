#include "starnav/sweep/manifest.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

#include <nlohmann/json.hpp>

#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/sweep/streamed_file.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::uint64_t kIndexStride = 1024;
constexpr const char* kFormat = "starnav sweep 1";

// FNV-1a, 64 bits: a fixed function, so ids are the same on every machine and in every version.
std::uint64_t fnv1a(std::uint64_t h, std::string_view bytes) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::string hex16(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::uint64_t task_digest(const std::vector<std::string>& argv, const std::string& result) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::string& a : argv) {
    h = fnv1a(h, a);
    h = fnv1a(h, std::string_view("\0", 1));
  }
  h = fnv1a(h, std::string_view("\x01result\x01", 8));
  return fnv1a(h, result);
}

void escape_braces(std::string& out, std::string_view text) {
  for (const char c : text) {
    out += c;
    if (c == '{' || c == '}') out += c;
  }
}

bool valid_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return false;
    i += n;
  }
  return true;
}

void json_string(std::string& out, std::string_view s) {
  out += '"';
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  out += '"';
}

void append_line(std::string& out, const SweepTask& t, const std::vector<std::string>& columns) {
  out += "{\"id\":\"";
  out += t.id;
  out += "\",\"values\":{";
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';
    json_string(out, columns[i]);
    out += ':';
    json_string(out, t.values[i]);
  }
  out += "},\"argv\":[";
  for (std::size_t i = 0; i < t.argv.size(); ++i) {
    if (i) out += ',';
    json_string(out, t.argv[i]);
  }
  out += "]}\n";
}

json string_array(const std::vector<std::string>& v) {
  json a = json::array();
  for (const std::string& s : v) a.push_back(s);
  return a;
}

}  // namespace

SweepTask make_task(const SweepSpec& spec, std::uint64_t index, const std::vector<std::string>& extra_sets) {
  SweepTask t;
  t.index = index;
  // Mixed radix, the last axis fastest.
  std::vector<std::uint64_t> digit(spec.axes.size(), 0);
  std::uint64_t rest = index;
  for (std::size_t a = spec.axes.size(); a-- > 0;) {
    const std::uint64_t n = spec.axes[a].size();
    digit[a] = rest % n;
    rest /= n;
  }
  std::vector<std::vector<std::string>> values(spec.axes.size());
  for (std::size_t a = 0; a < spec.axes.size(); ++a)
    for (std::size_t f = 0; f < spec.axes[a].width(); ++f) {
      values[a].push_back(spec.axes[a].value(digit[a], f));
      t.values.push_back(values[a].back());
    }
  t.argv.reserve(spec.command.size() + 1 + 2 * extra_sets.size());
  t.argv.emplace_back("starnav");
  for (const TemplateArg& arg : spec.command) {
    std::string s;
    for (const TemplatePart& p : arg.parts) {
      switch (p.kind) {
        case TemplatePart::Kind::Text: escape_braces(s, p.text); break;
        case TemplatePart::Kind::Axis: escape_braces(s, values[p.axis][p.field]); break;
        case TemplatePart::Kind::Out: s += "{out}"; break;
      }
    }
    t.argv.push_back(std::move(s));
  }
  for (std::size_t a = 0; a < spec.axes.size(); ++a) {
    if (!spec.axes[a].as_set_option) continue;
    t.argv.emplace_back("--set");
    std::string s;
    escape_braces(s, spec.axes[a].name + "=" + values[a][0]);
    t.argv.push_back(std::move(s));
  }
  for (const std::string& set : extra_sets) {
    t.argv.emplace_back("--set");
    std::string s;
    escape_braces(s, set);
    t.argv.push_back(std::move(s));
  }
  t.id = hex16(task_digest(t.argv, spec.result));
  return t;
}

std::vector<std::string> command_for_run(const std::vector<std::string>& argv, const std::string& out_dir) {
  std::vector<std::string> out;
  out.reserve(argv.size());
  for (const std::string& a : argv) {
    std::string s;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if ((a[i] == '{' || a[i] == '}') && i + 1 < a.size() && a[i + 1] == a[i]) {
        s += a[i++];
      } else if (a.compare(i, 5, "{out}") == 0) {
        s += out_dir;
        i += 4;
      } else {
        s += a[i];
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::string shell_command(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) {
    if (!out.empty()) out += ' ';
    const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("-_./=,:+@%{}", c) != nullptr;
    });
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (const char c : a) {
      if (c == '\'') out += "'\\''";
      else out += c;
    }
    out += '\'';
  }
  return out;
}

std::string SweepDir::result_path(const std::string& id) const {
  return dir + "/results/" + id.substr(0, 2) + "/" + id + ".json";
}

ExpandReport expand_sweep(const std::string& sweep_file, const std::string& dir, const ExpandOptions& options) {
  SweepSpec spec = read_sweep_file(sweep_file);
  for (const auto& [name, count] : options.take) {
    const std::optional<std::size_t> a = spec.axis_index(name);
    if (!a) {
      std::string names;
      for (const SweepAxis& ax : spec.axes) names += (names.empty() ? "" : ", ") + ax.name;
      throw Error("'" + printable(name, 60) + "' is not an axis of " + sweep_file + " (axes: " + names + ")", {}, 0, "--take");
    }
    if (count == 0) throw Error("keep at least one value of " + name, {}, 0, "--take");
    spec.axes[*a].take(count);
  }
  for (const std::string& set : options.sets) {
    const std::size_t eq = set.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("expected KEY=VALUE, got '" + printable(set, 60) + "'", {}, 0, "--set");
    if (spec.axis_index(set.substr(0, eq)))
      throw Error(set.substr(0, eq) + " is an axis of the sweep (use --take to keep fewer of its values)", {}, 0, "--set");
  }
  check_axis_values(spec);
  const std::uint64_t n = spec.task_count();
  const std::vector<std::string> columns = spec.axis_columns();

  std::error_code ec;
  const fs::path out(dir);
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) throw Error("exists and is not a folder", dir, 0, "--out");
    bool empty = true, is_sweep = fs::exists(out / "sweep.json", ec);
    for (const fs::directory_entry& e : fs::directory_iterator(out, ec))
      if (e.path().filename() != ".starnav-lock") empty = false;
    if (!empty && !options.force)
      throw Error(std::string(is_sweep ? "holds an expanded sweep" : "folder exists and is not empty") +
                      " (use --force to expand again: finished tasks of the same id are kept)",
                  dir, 0, "--out");
    if (!empty && !is_sweep) throw Error("is not empty and holds no sweep: refusing to write into it", dir, 0, "--out");
  }
  OutputFolder claim(dir, "--out");

  // The manifest, streamed: a million tasks never sit in memory at once.
  std::vector<std::uint64_t> digests;
  digests.reserve(static_cast<std::size_t>(n));
  ExpandReport report;
  report.tasks = n;
  report.manifest = (out / "manifest.jsonl").string();
  {
    StreamedFile manifest(report.manifest);
    StreamedFile index((out / "manifest.index").string());
    index.write("starnav sweep manifest index: the byte offset of every 1024th line\n");
    std::string buffer;
    std::uint64_t offset = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
      const SweepTask t = make_task(spec, i, options.sets);
      for (const std::string& a : t.argv)
        if (!valid_utf8(a))
          throw Error("task " + std::to_string(i) + " has an argument that is not valid UTF-8: '" + printable(a, 60) + "'", sweep_file);
      if (i % kIndexStride == 0) index.write(std::to_string(offset + buffer.size()) + "\n");
      digests.push_back(std::stoull(t.id, nullptr, 16));
      append_line(buffer, t, columns);
      if (buffer.size() > (1u << 20)) {
        manifest.write(buffer);
        offset += buffer.size();
        buffer.clear();
      }
    }
    manifest.write(buffer);
    std::vector<std::uint64_t> sorted = digests;
    std::sort(sorted.begin(), sorted.end());
    if (const auto dup = std::adjacent_find(sorted.begin(), sorted.end()); dup != sorted.end()) {
      std::vector<std::uint64_t> same;
      for (std::uint64_t i = 0; i < n && same.size() < 2; ++i)
        if (digests[i] == *dup) same.push_back(i);
      const SweepTask a = make_task(spec, same.at(0), options.sets);
      throw Error("tasks " + std::to_string(same.at(0)) + " and " + std::to_string(same.at(1)) + " run the same command (" +
                      printable(shell_command(a.argv), 200) + "): an axis value the command does not use?",
                  sweep_file, spec.axes_line, "axes");
    }
    manifest.commit();
    index.commit();
  }
  // Results of an earlier expansion stay; count those whose task is still here.
  std::sort(digests.begin(), digests.end());
  for (const fs::directory_entry& shard : fs::directory_iterator(out / "results", ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(shard.path(), ec)) {
      const std::string stem = e.path().stem().string();
      if (e.path().extension() != ".json" || stem.size() != 16) continue;
      char* end = nullptr;
      const std::uint64_t d = std::strtoull(stem.c_str(), &end, 16);
      if (end == stem.c_str() + 16 && std::binary_search(digests.begin(), digests.end(), d)) ++report.results_kept;
    }
  }
  write_file_atomically((out / "sweep.yaml").string(), read_input_file(sweep_file, std::uint64_t{1} << 24));
  json header;
  header["format"] = kFormat;
  header["starnav"] = STARNAV_VERSION;
  header["name"] = spec.name;
  header["sweep_file"] = fs::absolute(sweep_file).lexically_normal().string();
  header["cwd"] = fs::absolute(sweep_file).lexically_normal().parent_path().string();
  header["tasks"] = n;
  header["columns"] = string_array(columns);
  json take = json::object();
  for (const auto& [name, count] : options.take) take[name] = count;
  header["take"] = take;
  header["set"] = string_array(options.sets);
  write_file_atomically((out / "sweep.json").string(), header.dump(2) + "\n");
  return report;
}

SweepDir open_sweep_dir(const std::string& dir) {
  SweepDir s;
  s.dir = dir;
  while (s.dir.size() > 1 && s.dir.back() == '/') s.dir.pop_back();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("no such folder (expand a sweep into it with starnav sweep expand)", dir);
  const std::string header_path = s.dir + "/sweep.json";
  if (!fs::exists(header_path, ec)) throw Error("not an expanded sweep (no sweep.json: run starnav sweep expand first)", dir);
  json header;
  try {
    header = json::parse(read_input_file(header_path, 1u << 20));
    if (header.at("format").get<std::string>() != kFormat)
      throw Error("written by another version of starnav sweep (format '" + printable(header.at("format").get<std::string>(), 40) + "')",
                  header_path, 0, "format");
    s.cwd = header.at("cwd").get<std::string>();
    s.tasks = header.at("tasks").get<std::uint64_t>();
    s.columns = header.at("columns").get<std::vector<std::string>>();
  } catch (const json::exception& e) {
    throw Error("not a sweep header (" + one_line(e.what(), 120) + ")", header_path);
  }
  const std::string yaml_path = s.dir + "/sweep.yaml";
  s.spec = parse_sweep_file(read_input_file(yaml_path, std::uint64_t{1} << 24), yaml_path, header.value("name", "sweep"));
  if (s.spec.axis_columns() != s.columns) throw Error("its columns differ from sweep.json's: expand the sweep again", yaml_path);
  return s;
}

namespace {

SweepTask parse_task_line(std::string_view line, const SweepDir& sweep, std::uint64_t index) {
  const std::string where = sweep.manifest_path() + ":" + std::to_string(index + 1);
  SweepTask t;
  t.index = index;
  try {
    const json j = json::parse(line);
    t.id = j.at("id").get<std::string>();
    if (t.id.size() != 16 || t.id.find_first_not_of("0123456789abcdef") != std::string::npos)
      throw Error("not a task id: '" + printable(t.id, 40) + "'", where, 0, "id");
    const json& values = j.at("values");
    for (const std::string& c : sweep.columns) t.values.push_back(values.at(c).get<std::string>());
    t.argv = j.at("argv").get<std::vector<std::string>>();
    if (t.argv.size() < 2 || t.argv[0] != "starnav") throw Error("expected a starnav command", where, 0, "argv");
  } catch (const json::exception& e) {
    throw Error("not a task line (" + one_line(e.what(), 120) + ")", where);
  }
  return t;
}

// Reads the manifest from byte `offset` (the start of line `line`), calling f(line, text) for
// each line until f returns false.
void scan_manifest(const SweepDir& sweep, std::uint64_t offset, std::uint64_t line,
                   const std::function<bool(std::uint64_t, std::string_view)>& f) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(sweep.manifest_path().c_str(), "rb"), &std::fclose);
  if (!file) throw Error(std::string("cannot open: ") + std::strerror(errno), sweep.manifest_path());
  if (std::fseek(file.get(), static_cast<long>(offset), SEEK_SET) != 0)
    throw Error("shorter than its index says: expand the sweep again", sweep.manifest_path());
  std::string pending;
  std::vector<char> buf(1 << 20);
  for (;;) {
    const std::size_t got = std::fread(buf.data(), 1, buf.size(), file.get());
    if (got == 0) break;
    pending.append(buf.data(), got);
    std::size_t start = 0;
    for (std::size_t nl; (nl = pending.find('\n', start)) != std::string::npos; start = nl + 1)
      if (!f(line++, std::string_view(pending).substr(start, nl - start))) return;
    pending.erase(0, start);
  }
  if (!pending.empty()) f(line, pending);
}

}  // namespace

std::vector<SweepTask> read_tasks(const SweepDir& sweep, std::uint64_t first, std::uint64_t count) {
  std::vector<SweepTask> out;
  if (first >= sweep.tasks || count == 0) return out;
  const std::uint64_t last = std::min(sweep.tasks, first + std::min(count, sweep.tasks - first));
  // The index: a header line, then one offset per kIndexStride lines.
  const std::string index_path = sweep.dir + "/manifest.index";
  const std::string index = read_input_file(index_path, std::uint64_t{1} << 30);
  const std::uint64_t block = first / kIndexStride;
  std::size_t pos = index.find('\n');
  for (std::uint64_t b = 0; b < block && pos != std::string::npos; ++b) pos = index.find('\n', pos + 1);
  if (pos == std::string::npos || pos + 1 >= index.size()) throw Error("shorter than the manifest: expand the sweep again", index_path);
  const std::uint64_t offset = std::strtoull(index.c_str() + pos + 1, nullptr, 10);
  out.reserve(static_cast<std::size_t>(last - first));
  scan_manifest(sweep, offset, block * kIndexStride, [&](std::uint64_t line, std::string_view text) {
    if (line >= last) return false;
    if (line >= first) out.push_back(parse_task_line(text, sweep, line));
    return true;
  });
  if (out.size() != last - first) throw Error("has fewer tasks than sweep.json says: expand the sweep again", sweep.manifest_path());
  return out;
}

void for_each_task(const SweepDir& sweep, const std::function<void(const SweepTask&)>& f) {
  std::uint64_t seen = 0;
  scan_manifest(sweep, 0, 0, [&](std::uint64_t line, std::string_view text) {
    f(parse_task_line(text, sweep, line));
    ++seen;
    return true;
  });
  if (seen != sweep.tasks)
    throw Error("has " + std::to_string(seen) + " tasks, sweep.json says " + std::to_string(sweep.tasks) + ": expand the sweep again",
                sweep.manifest_path());
}

}  // namespace starnav::sweep
