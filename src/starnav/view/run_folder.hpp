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

struct RunFolder {
  std::string dir;
  std::string kind;                // simulation | navigation
  std::vector<std::string> files;  // as run.json lists them, each checked to be in the folder
};

// Reads DIR/run.json. Throws Error naming the file and field: no folder, no run.json, not JSON,
// another schema, a newer version, a listed file that is missing or not a plain name.
RunFolder read_run_folder(const std::string& dir);

// The files of a run folder as run.json lists them: every regular file with a plain name (the
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
// trajectory.csv, steps.jsonl, when the run has them): it opens from a file URL, offline.
// Throws Error (field "--export") above kMaxExportBytes.
std::string export_run_html(const RunFolder& run, const std::string& viewer_dir);

// The MIME type the server sends for a file name.
std::string content_type_of(const std::string& name);

}  // namespace starnav
