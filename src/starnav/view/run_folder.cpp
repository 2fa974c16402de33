#include "starnav/view/run_folder.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/io/file_bytes.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

// The files of a run the viewer reads, in the order it reads them.
constexpr const char* kViewerRunFiles[] = {"run.json", "world.json", "metrics.json", "trajectory.csv", "steps.jsonl"};

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

RunFile::RunFile(const std::string& dir, const std::string& name, Links links) : path_((fs::path(dir) / name).string()) {
  if (!is_plain_file_name(name)) {
    refusal_ = "not a plain file name";
    return;
  }
  // O_NOFOLLOW: a symbolic link is refused, not followed (the name has no other component); O_NONBLOCK:
  // opening a FIFO must not wait for a writer (it is refused below as not a regular file).
  fd_ = ::open(path_.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | (links == Links::Refuse ? O_NOFOLLOW : 0));
  if (fd_ < 0) {
    refusal_ = errno == ELOOP ? "a symbolic link" : errno == ENOENT ? "missing" : "cannot be opened";
    return;
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    refusal_ = "not a regular file";
    return;
  }
  size_ = static_cast<std::uintmax_t>(st.st_size);
}

RunFile::~RunFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t RunFile::read_at(std::uintmax_t offset, char* out, std::size_t n) const {
  if (fd_ < 0) return 0;
  for (;;) {
    const ssize_t got = ::pread(fd_, out, n, static_cast<off_t>(offset));
    if (got >= 0) return static_cast<std::size_t>(got);
    if (errno != EINTR) return 0;
  }
}

std::string RunFile::read_all(std::uintmax_t max_bytes) const {
  if (fd_ < 0) throw Error("a run file must be a regular file of the folder, and this one is " + refusal_, path_, 0, "");
  if (size_ > max_bytes)
    throw Error("is " + std::to_string(size_) + " bytes, more than the " + std::to_string(max_bytes) + " this reader takes", path_, 0, "");
  std::string out(static_cast<std::size_t>(size_), '\0');
  std::size_t have = 0;
  while (have < out.size()) {
    const std::size_t got = read_at(have, out.data() + have, out.size() - have);
    if (got == 0) throw Error("cannot read the whole file (it changed or the read failed)", path_, 0, "");
    have += got;
  }
  return out;
}

std::string json_for_script(std::string json_text) {
  std::string out;
  out.reserve(json_text.size());
  for (const char c : json_text) {
    if (c == '<') out += "\\u003c";
    else out += c;
  }
  return out;
}

bool is_plain_file_name(const std::string& name) {
  if (name.empty() || name.size() > 255 || name.front() == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  });
}

std::vector<std::string> run_folder_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "run.json" && RunFile(dir, name).is_open()) files.push_back(name);
  }
  std::sort(files.begin(), files.end());
  return files;
}

void write_run_manifest(const std::string& dir, const std::string& kind, const std::string& about_json) {
  nlohmann::ordered_json j;
  j["schema"] = "starnav-run";
  j["version"] = kRunRecordVersion;
  j["kind"] = kind;
  const auto about = nlohmann::ordered_json::parse(about_json);
  for (const auto& [key, value] : about.items()) j[key] = value;
  j["files"] = run_folder_files(dir);
  write_file_bytes((fs::path(dir) / "run.json").string(), j.dump(2) + "\n");
}

RunFolder read_run_folder(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("not a folder (give the --out folder of starnav sim, slam run, localize or slam3d)", dir, 0, "RUN_DIR");
  const std::string manifest = (fs::path(dir) / "run.json").string();
  const RunFile manifest_file(dir, "run.json");
  if (manifest_file.refusal() == "missing")
    throw Error("no run.json: not a run record (the --out folder of starnav sim, slam run, localize or slam3d holds one)", manifest, 0,
                "");
  const std::string text = manifest_file.read_all(kMaxRunManifestBytes);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("not JSON: ") + e.what(), manifest, 0, "");
  }
  if (!j.is_object() || !j.contains("schema") || j["schema"] != "starnav-run")
    throw Error("not a starnav run record (schema should be \"starnav-run\")", manifest, 0, "schema");
  if (!j.contains("version") || !j["version"].is_number_integer())
    throw Error("missing or not an integer", manifest, 0, "version");
  const auto version = j["version"].get<long long>();
  if (version < 1 || version > kRunRecordVersion)
    throw Error("version " + std::to_string(version) + " is not one this starnav reads (1.." + std::to_string(kRunRecordVersion) +
                    ")",
                manifest, 0, "version");
  RunFolder run;
  run.dir = dir;
  if (!j.contains("kind") || !j["kind"].is_string()) throw Error("missing or not text", manifest, 0, "kind");
  run.kind = j["kind"].get<std::string>();
  if (!j.contains("files") || !j["files"].is_array()) throw Error("missing or not a list", manifest, 0, "files");
  for (const auto& f : j["files"]) {
    if (!f.is_string() || !is_plain_file_name(f.get<std::string>()))
      throw Error("each entry must be a plain file name", manifest, 0, "files");
    const std::string name = f.get<std::string>();
    const RunFile file(dir, name);
    if (file.refusal() == "missing") throw Error("listed but not in the folder: " + name, manifest, 0, "files");
    if (!file.is_open())
      throw Error(name + " is " + file.refusal() + ": a run file must be a regular file of the folder", manifest, 0, "files");
    run.files.push_back(name);
  }
  if (std::find(run.files.begin(), run.files.end(), "world.json") == run.files.end())
    throw Error("world.json is not listed (the viewer needs the world)", manifest, 0, "files");
  return run;
}

std::vector<std::string> viewer_dir_candidates(const std::string& executable_path) {
  std::vector<std::string> out;
  if (const char* env = std::getenv("STARNAV_VIEWER_DIR"); env && *env) out.emplace_back(env);
  if (!executable_path.empty()) {
    const fs::path bin = fs::path(executable_path).parent_path();
    out.push_back((bin.parent_path() / "share" / "starnav" / "viewer").string());
    out.push_back((bin.parent_path() / "viewer").string());
  }
  return out;
}

std::string find_viewer_dir(const std::vector<std::string>& candidates) {
  std::error_code ec;
  std::string searched;
  for (const std::string& c : candidates) {
    if (fs::is_regular_file(fs::path(c) / "index.html", ec) && fs::is_regular_file(fs::path(c) / "viewer.js", ec)) return c;
    searched += (searched.empty() ? "" : ", ") + c;
  }
  throw Error("the viewer's files (index.html, viewer.js) are not built: run `make build` (it bundles them with npm's "
              "esbuild) or set STARNAV_VIEWER_DIR; searched " +
                  (searched.empty() ? std::string("nothing") : searched),
              "", 0, "viewer");
}

std::string export_run_html(const RunFolder& run, const std::string& viewer_dir) {
  std::uintmax_t total = 0;
  std::error_code ec;
  std::vector<std::unique_ptr<RunFile>> files_read;
  std::vector<std::string> names;
  for (const char* name : kViewerRunFiles) {
    if (std::string(name) != "run.json" && std::find(run.files.begin(), run.files.end(), name) == run.files.end()) continue;
    names.emplace_back(name);
    files_read.push_back(std::make_unique<RunFile>(run.dir, name));
    total += files_read.back()->size();
  }
  total += fs::file_size(fs::path(viewer_dir) / "viewer.js", ec);
  if (total > kMaxExportBytes)
    throw Error("the run is " + std::to_string(total >> 20) + " MiB, above the " + std::to_string(kMaxExportBytes >> 20) +
                    " MiB a page can hold: view it served (starnav view RUN_DIR)",
                run.dir, 0, "--export");
  nlohmann::json files = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size(); ++i) files[names[i]] = files_read[i]->read_all();
  std::string page = read_input_file((fs::path(viewer_dir) / "index.html").string());
  const std::string script_tag = "<script src=\"viewer.js\"></script>";
  const std::string data_mark = "<!--starnav-run-->";
  const std::size_t script_at = page.find(script_tag), data_at = page.find(data_mark);
  if (script_at == std::string::npos || data_at == std::string::npos || data_at > script_at)
    throw Error("not the viewer's page (no run marker before the script tag)", (fs::path(viewer_dir) / "index.html").string(), 0,
                "viewer");
  std::string script = read_input_file((fs::path(viewer_dir) / "viewer.js").string());
  for (std::size_t at = script.find("</script"); at != std::string::npos; at = script.find("</script", at + 3))
    script.replace(at, 2, "<\\/");
  page.replace(script_at, script_tag.size(), "<script>" + script + "</script>");
  page.replace(data_at, data_mark.size(),
               "<script type=\"application/json\" id=\"starnav-run\">" +
                   json_for_script(files.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) + "</script>");
  return page;
}

std::string content_type_of(const std::string& name) {
  static const std::pair<const char*, const char*> kTypes[] = {
      {".html", "text/html; charset=utf-8"},     {".js", "text/javascript; charset=utf-8"},
      {".json", "application/json"},             {".jsonl", "application/x-ndjson"},
      {".csv", "text/csv; charset=utf-8"},       {".svg", "image/svg+xml"},
      {".png", "image/png"},                     {".yaml", "text/yaml; charset=utf-8"},
      {".pgm", "image/x-portable-graymap"},      {".clf", "text/plain; charset=utf-8"},
      {".ply", "application/octet-stream"},      {".pcd", "application/octet-stream"}};
  for (const auto& [ext, type] : kTypes)
    if (ends_with(name, ext)) return type;
  return "application/octet-stream";
}

}  // namespace starnav
