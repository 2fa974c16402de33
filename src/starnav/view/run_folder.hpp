#pragma once
// A run folder as the viewer reads it (docs/run-records.md): the schema check, the viewer's own
// files, and the self-contained page that `starnav view RUN --export` writes.
#include <cstdint>
#include <string>
#include <vector>

namespace starnav {

// The run-record schema's version (run.json and world.json carry it): a reader refuses a newer one.
inline constexpr int kRunRecordVersion = 1;
// The largest page --export writes (the run's files are inlined; a longer run is viewed served).
inline constexpr std::uintmax_t kMaxExportBytes = 512ull << 20;
// The largest run.json read (it names the run and lists its files).
inline constexpr std::uintmax_t kMaxRunManifestBytes = 16ull << 20;

struct RunFolder {
  std::string dir;
  std::string kind;                // simulation | navigation | slam | localization | slam3d
  std::vector<std::string> files;  // as run.json lists them, each checked to be a file of the folder
};

// A file of a run folder opened for reading by the one rule the server and the exporter share: a
// plain file name (is_plain_file_name) of a regular file directly in the folder, not a symbolic
// link. It is opened without following a link, so nothing can swap one in between check and read.
class RunFile {
 public:
  // Follow: the same, except that a link to a regular file is followed (the viewer's own files).
  enum class Links { Refuse, Follow };
  RunFile(const std::string& dir, const std::string& name, Links links = Links::Refuse);
  ~RunFile();
  RunFile(const RunFile&) = delete;
  RunFile& operator=(const RunFile&) = delete;

  bool is_open() const { return fd_ >= 0; }
  // Why the rule refused the file (empty when open): "missing", "a symbolic link", ...
  const std::string& refusal() const { return refusal_; }
  std::uintmax_t size() const { return size_; }
  // Up to `n` bytes from `offset`; the count read (0 at the end or on a read error).
  std::size_t read_at(std::uintmax_t offset, char* out, std::size_t n) const;
  // The whole file; Error naming it when it cannot be read or is larger than `max_bytes`.
  std::string read_all(std::uintmax_t max_bytes = kMaxExportBytes) const;

 private:
  std::string path_;
  int fd_ = -1;
  std::uintmax_t size_ = 0;
  std::string refusal_;
};

// Reads DIR/run.json. Throws Error naming the file and field: no folder, no run.json, not JSON,
// another schema, a newer version, a listed file that the RunFile rule refuses (missing, a
// symbolic link, not a plain name).
RunFolder read_run_folder(const std::string& dir);

// The files of a run folder as run.json lists them: every file the RunFile rule accepts (the
// output folder's lock, a dot file, is not one), sorted, run.json itself excluded.
std::vector<std::string> run_folder_files(const std::string& dir);

// Writes DIR/run.json (call last, once every other file is written): schema, version, kind, the
// members of `about` (a JSON object's text: what the run was, e.g. its scenario or log), and
// run_folder_files(DIR). Throws Error naming the file when it cannot be written.
void write_run_manifest(const std::string& dir, const std::string& kind, const std::string& about_json);

// True for a name the server and the exporter accept: a plain file name of letters, digits, '_',
// '-' and '.', not starting with '.', at most 255 bytes.
bool is_plain_file_name(const std::string& name);

// The viewer's built files (index.html and viewer.js): the first of `candidates` holding both.
// Throws Error (field "viewer") naming what was searched otherwise.
std::string find_viewer_dir(const std::vector<std::string>& candidates);
// Where the viewer is looked for: $STARNAV_VIEWER_DIR, then beside the executable
// (<prefix>/share/starnav/viewer for an install, <build>/viewer in a build tree).
std::vector<std::string> viewer_dir_candidates(const std::string& executable_path);

// One HTML page holding the viewer and the run (run.json, world.json, metrics.json,
// trajectory.csv, steps.jsonl, when the run has them): it opens from a file URL, offline. The
// run's files are read by the RunFile rule and embedded as JSON with every '<' escaped, so no text
// in them can end or confuse the script element. Throws Error (field "--export") above
// kMaxExportBytes.
std::string export_run_html(const RunFolder& run, const std::string& viewer_dir);

// JSON text made safe to embed in an HTML script element: every '<' (it can stand only inside a
// JSON string) becomes \u003c, so neither "</script" nor "<!--" can appear.
std::string json_for_script(std::string json_text);

// The MIME type the server sends for a file name.
std::string content_type_of(const std::string& name);

}  // namespace starnav
