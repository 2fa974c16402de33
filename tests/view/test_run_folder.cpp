// Reading a run folder for the viewer: the schema check and its one-line errors, the plain-name
// rule the server and the exporter share, finding the viewer's files, and the exported page
// (the run's files inside it read back byte for byte; nothing in them can close its script).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/view/run_folder.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

struct Folder {
  fs::path root = fs::temp_directory_path() / ("starnav_run_folder_" + std::to_string(::getpid()));
  Folder() {
    fs::remove_all(root);
    fs::create_directories(root / "run");
    fs::create_directories(root / "viewer");
    write("viewer/index.html", "<html><!--starnav-run-->\n<script src=\"viewer.js\"></script></html>");
    write("viewer/viewer.js", "var s = '</script><b>';");
    write("run/world.json", "{\"schema\":\"starnav-world\",\"version\":1,\"note\":\"</script>\"}");
    write("run/steps.jsonl", "{\"t_s\":0}\n{\"t_s\":0.1}\n");
    write("run/trajectory.csv", "t_s,x_m\n0,1\n");
    manifest(R"({"schema":"starnav-run","version":1,"kind":"navigation","files":["steps.jsonl","trajectory.csv","world.json"]})");
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  void write(const std::string& rel, const std::string& text) const { std::ofstream(root / rel, std::ios::binary) << text; }
  void manifest(const std::string& text) const { write("run/run.json", text); }
  std::string run() const { return (root / "run").string(); }
};

void expect_error(const std::string& dir, const std::string& field, const std::string& words) {
  try {
    read_run_folder(dir);
    FAIL() << "accepted; expected an error on " << field;
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(RunFolder, ReadsTheManifest) {
  Folder f;
  const RunFolder r = read_run_folder(f.run());
  EXPECT_EQ(r.kind, "navigation");
  EXPECT_EQ(r.files, (std::vector<std::string>{"steps.jsonl", "trajectory.csv", "world.json"}));
}

TEST(RunFolder, EachBadManifestIsOneErrorNamingTheField) {
  Folder f;
  expect_error((f.root / "missing").string(), "RUN_DIR", "not a folder");
  fs::remove(f.root / "run" / "run.json");
  expect_error(f.run(), "", "no run.json");
  struct Row {
    std::string text, field, words;
  };
  for (const Row& row : std::vector<Row>{
           {"{", "", "not JSON"},
           {"[]", "schema", "not a starnav run record"},
           {R"({"schema":"other","version":1})", "schema", "not a starnav run record"},
           {R"({"schema":"starnav-run"})", "version", "missing"},
           {R"({"schema":"starnav-run","version":"1"})", "version", "not an integer"},
           {R"({"schema":"starnav-run","version":2,"kind":"navigation","files":[]})", "version", "version 2"},
           {R"({"schema":"starnav-run","version":0,"kind":"navigation","files":[]})", "version", "version 0"},
           {R"({"schema":"starnav-run","version":1,"files":[]})", "kind", "missing"},
           {R"({"schema":"starnav-run","version":1,"kind":"navigation"})", "files", "missing"},
           {R"({"schema":"starnav-run","version":1,"kind":"navigation","files":["../secret"]})", "files", "plain file name"},
           {R"({"schema":"starnav-run","version":1,"kind":"navigation","files":[3]})", "files", "plain file name"},
           {R"({"schema":"starnav-run","version":1,"kind":"navigation","files":["gone.csv","world.json"]})", "files", "gone.csv"},
           {R"({"schema":"starnav-run","version":1,"kind":"navigation","files":["steps.jsonl"]})", "files", "world.json"},
       }) {
    f.manifest(row.text);
    expect_error(f.run(), row.field, row.words);
  }
}

TEST(RunFolder, PlainFileNames) {
  for (const char* ok : {"world.json", "steps.jsonl", "dwa_1.50s.svg", "a", "map-2.pgm"}) EXPECT_TRUE(is_plain_file_name(ok)) << ok;
  for (const char* bad : {"", ".", "..", ".hidden", "a/b", "../x", "a\\b", "a b", "x%2F", "a\nb", "\xc3\xa9.json"})
    EXPECT_FALSE(is_plain_file_name(bad)) << bad;
  EXPECT_FALSE(is_plain_file_name(std::string(256, 'a')));
  EXPECT_TRUE(is_plain_file_name(std::string(255, 'a')));
}

TEST(RunFolder, FindsTheViewerOrSaysWhereItLooked) {
  Folder f;
  const std::string viewer = (f.root / "viewer").string();
  EXPECT_EQ(find_viewer_dir({(f.root / "nowhere").string(), viewer}), viewer);
  try {
    find_viewer_dir({(f.root / "nowhere").string()});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "viewer");
    EXPECT_NE(std::string(e.what()).find("nowhere"), std::string::npos);
  }
  // Beside the executable: an install's share/ and a build tree's viewer/.
  const auto c = viewer_dir_candidates("/opt/x/bin/starnav");
  EXPECT_NE(std::find(c.begin(), c.end(), "/opt/x/share/starnav/viewer"), c.end());
  EXPECT_NE(std::find(c.begin(), c.end(), "/opt/x/viewer"), c.end());
}

TEST(RunFolder, TheExportedPageHoldsTheViewerAndTheRunsFilesByteForByte) {
  Folder f;
  const std::string page = export_run_html(read_run_folder(f.run()), (f.root / "viewer").string());
  EXPECT_EQ(page.find("src=\"viewer.js\""), std::string::npos);
  // Only the page's own two script elements close: nothing inside them does.
  std::size_t closes = 0;
  for (std::size_t at = page.find("</script"); at != std::string::npos; at = page.find("</script", at + 1)) ++closes;
  EXPECT_EQ(closes, 2u);
  EXPECT_NE(page.find("var s = '<\\/script><b>';"), std::string::npos);
  const std::string open = "<script type=\"application/json\" id=\"starnav-run\">";
  const std::size_t a = page.find(open) + open.size();
  const std::size_t b = page.find("</script>", a);
  std::string data = page.substr(a, b - a);
  const auto j = nlohmann::json::parse(data);
  EXPECT_EQ(j["world.json"].get<std::string>(), "{\"schema\":\"starnav-world\",\"version\":1,\"note\":\"</script>\"}");
  EXPECT_EQ(j["steps.jsonl"].get<std::string>(), "{\"t_s\":0}\n{\"t_s\":0.1}\n");
  EXPECT_EQ(j["trajectory.csv"].get<std::string>(), "t_s,x_m\n0,1\n");
  EXPECT_TRUE(j.contains("run.json"));
  EXPECT_FALSE(j.contains("metrics.json"));  // not in this run
}

// The text between the page's data script element's tags.
std::string embedded_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"starnav-run\">";
  const std::size_t a = page.find(open) + open.size();
  return page.substr(a, page.find("</script>", a) - a);
}

TEST(RunFolder, TheExportedPageEscapesEveryLessThanInTheRunsText) {
  Folder f;
  // "<!--<script>" would put the HTML parser in the double-escaped state, where the data
  // element's own end tag no longer ends it and the page stays blank.
  const std::string world = "{\"schema\":\"starnav-world\",\"version\":1,\"note\":\"<!--<script></script>-->< / <\\/script\"}";
  f.write("run/world.json", world);
  const std::string page = export_run_html(read_run_folder(f.run()), (f.root / "viewer").string());
  const std::string data = embedded_data(page);
  EXPECT_EQ(data.find('<'), std::string::npos) << data;
  EXPECT_EQ(nlohmann::json::parse(data)["world.json"].get<std::string>(), world);
  EXPECT_EQ(json_for_script("[\"<a>\",\"b\"]"), "[\"\\u003ca>\",\"b\"]");
}

TEST(RunFolder, ALinkIsNotARunFileForTheExporterOrTheReader) {
  Folder f;
  f.write("secret.txt", "outside the run folder");
  f.write("run/real.json", "{\"inside\":true}");
  fs::create_symlink(f.root / "secret.txt", f.root / "run" / "metrics.json");
  fs::create_symlink(f.root / "run" / "real.json", f.root / "run" / "inside_link.json");
  // Neither a link out of the folder nor one inside it is a run file.
  EXPECT_EQ(RunFile(f.run(), "metrics.json").refusal(), "a symbolic link");
  EXPECT_EQ(RunFile(f.run(), "inside_link.json").refusal(), "a symbolic link");
  EXPECT_EQ(RunFile(f.run(), "gone.json").refusal(), "missing");
  EXPECT_EQ(RunFile(f.run(), "../secret.txt").refusal(), "not a plain file name");
  EXPECT_TRUE(RunFile(f.run(), "real.json").is_open());
  EXPECT_EQ(RunFile(f.run(), "real.json").read_all(), "{\"inside\":true}");
  const auto listed = run_folder_files(f.run());
  EXPECT_EQ(std::find(listed.begin(), listed.end(), "metrics.json"), listed.end());
  EXPECT_NE(std::find(listed.begin(), listed.end(), "real.json"), listed.end());
  // A run.json listing the link is refused, naming it; an exporter handed it anyway reads nothing.
  f.manifest(R"({"schema":"starnav-run","version":1,"kind":"navigation","files":["metrics.json","world.json"]})");
  expect_error(f.run(), "files", "metrics.json is a symbolic link");
  RunFolder forged;
  forged.dir = f.run();
  forged.kind = "navigation";
  forged.files = {"metrics.json", "world.json"};
  try {
    const std::string page = export_run_html(forged, (f.root / "viewer").string());
    ADD_FAILURE() << "exported a link";
    EXPECT_EQ(page.find("outside the run folder"), std::string::npos);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("symbolic link"), std::string::npos) << e.what();
  }
  // A FIFO is refused at once, not waited on.
  ASSERT_EQ(::mkfifo((f.root / "run" / "fifo.json").c_str(), 0600), 0);
  EXPECT_EQ(RunFile(f.run(), "fifo.json").refusal(), "not a regular file");
}

TEST(RunFolder, ContentTypes) {
  EXPECT_EQ(content_type_of("world.json"), "application/json");
  EXPECT_EQ(content_type_of("steps.jsonl"), "application/x-ndjson");
  EXPECT_EQ(content_type_of("viewer.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(content_type_of("scene.svg"), "image/svg+xml");
  EXPECT_EQ(content_type_of("data.bin"), "application/octet-stream");
}

}  // namespace
}  // namespace starnav
