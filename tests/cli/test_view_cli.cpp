// starnav view and sim --live from the command line: one error line for a folder that is not a
// run record, --export written and refused over an existing file, the live flags only with --live,
// and live scripted runs streamed to a client over a real socket: each scan's step, the lines of
// steps.jsonl, or without a LiDAR the pose ten times a second, equal to trajectory.csv's; the
// records the same bytes as without --live.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "starnav/config.hpp"
#include "support/raw_http.hpp"
#include "support/test_support.hpp"

extern char** environ;

namespace starnav {
namespace {

namespace fs = std::filesystem;

int lines_of(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(CliView, AFolderThatIsNotARunRecordIsOneErrorLine) {
  const test::ScratchDir dir;
  fs::create_directories(dir.file("empty"));
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"view", dir.file("missing")}, {"view", dir.file("empty")}, {"view", dir.file("empty"), "--port", "70000"}}) {
    const test::CliResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(lines_of(r.err), 1) << r.err;
  }
  test::write_text(dir.file("empty/run.json"), "{\"schema\":\"starnav-run\",\"version\":99}");
  const test::CliResult newer = test::run_cli({"view", dir.file("empty")});
  EXPECT_EQ(newer.exit_code, 2);
  EXPECT_NE(newer.err.find("version 99"), std::string::npos) << newer.err;
}

TEST(CliView, ExportsOnePageAndRefusesToOverwriteIt) {
  const test::ScratchDir dir;
  const test::CliResult sim = test::run_cli({"sim", test::scenario_path("e1_terrain_platform.yaml"), "--out", dir.file("e1"), "--quiet",
                                             "--duration", "2"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  if (!fs::exists(fs::path(STARNAV_CLI_PATH).parent_path().parent_path() / "viewer" / "viewer.js"))
    GTEST_SKIP() << "the viewer is not bundled in this build (no npm)";
  const test::CliResult r = test::run_cli({"view", dir.file("e1"), "--export", dir.file("e1.html")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = test::read_text(dir.file("e1.html"));
  EXPECT_NE(page.find("id=\"starnav-run\""), std::string::npos);
  EXPECT_NE(page.find("e1_terrain_platform"), std::string::npos);
  const test::CliResult again = test::run_cli({"view", dir.file("e1"), "--export", dir.file("e1.html")});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(lines_of(again.err), 1) << again.err;
}

TEST(CliSim, TheLiveFlagsNeedLive) {
  for (const char* flag : {"--port", "--bind", "--live-wait"}) {
    std::vector<std::string> args = {"sim", test::scenario_path("e1_terrain_platform.yaml"), "--out", "/tmp/starnav_never", flag};
    if (std::string(flag) == "--port") args.push_back("9000");
    if (std::string(flag) == "--bind") args.push_back("127.0.0.1");
    const test::CliResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << flag;
    EXPECT_NE(r.err.find(std::string(flag) + ": only with --live"), std::string::npos) << r.err;
  }
}

#if STARNAV_HAVE_HTTP
// Runs `starnav sim ... --live --live-wait --port 0` in the background, reads its event stream
// as a viewer would, and returns the data of its step events once the run has exited 0.
std::vector<std::string> live_step_events(const std::vector<std::string>& sim_args, const std::string& err_file) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  std::vector<std::string> args = {STARNAV_CLI_PATH, "sim"};
  args.insert(args.end(), sim_args.begin(), sim_args.end());
  for (const char* a : {"--quiet", "--live", "--live-wait", "--port", "0"}) args.emplace_back(a);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, STARNAV_CLI_PATH, &actions, nullptr, argv.data(), environ) != 0) return {};
  posix_spawn_file_actions_destroy(&actions);
  int port = 0;
  const std::regex url(R"(http://127\.0\.0\.1:(\d+)/)");
  for (int i = 0; i < 600 && port == 0; ++i) {
    std::smatch m;
    const std::string err = test::read_text(err_file);
    if (std::regex_search(err, m, url)) port = std::stoi(m[1]);
    else std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_GT(port, 0) << test::read_text(err_file);
  if (port == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    return {};
  }
  const std::string manifest = test::http_get(port, "/run/run.json");
  EXPECT_NE(manifest.find("\"live\": true"), std::string::npos) << manifest;
  const std::string events = test::http_get(port, "/events", 60000);
  int status = 0;
  EXPECT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::read_text(err_file);
  EXPECT_NE(events.find("event: end"), std::string::npos);
  std::vector<std::string> steps;
  std::istringstream in(events);
  for (std::string line, event; std::getline(in, line);) {
    if (line.rfind("event: ", 0) == 0) event = line.substr(7);
    if (event == "step" && line.rfind("data: ", 0) == 0) steps.push_back(line.substr(6));
  }
  return steps;
}

// A scripted run with a LiDAR streams each scan's step, the very lines of its steps.jsonl, and
// writes the same records as without --live.
TEST(CliSim, ALiveScriptedRunStreamsItsStepsAndWritesTheSameBytes) {
  if (!fs::exists(fs::path(STARNAV_CLI_PATH).parent_path().parent_path() / "viewer" / "viewer.js"))
    GTEST_SKIP() << "the viewer is not bundled in this build (no npm)";
  const test::ScratchDir dir;
  const std::string scenario = test::scenario_path("e1_terrain_platform.yaml");
  ASSERT_EQ(test::run_cli({"sim", scenario, "--out", dir.file("plain"), "--quiet", "--duration", "3"}).exit_code, 0);
  const std::vector<std::string> steps =
      live_step_events({scenario, "--out", dir.file("live"), "--duration", "3"}, dir.file("live.err"));
  std::vector<std::string> written;
  std::istringstream in(test::read_text(dir.file("live/steps.jsonl")));
  for (std::string line; std::getline(in, line);) written.push_back(line);
  EXPECT_GE(written.size(), 30u);  // 10 Hz for 3 s
  EXPECT_EQ(steps, written);
  for (const auto& e : fs::directory_iterator(dir.file("plain"))) {
    const std::string name = e.path().filename().string();
    if (name == "timing.json" || name[0] == '.') continue;
    EXPECT_EQ(test::read_text(e.path().string()), test::read_text(dir.file("live/" + name))) << name;
  }
}

// Without a LiDAR: the true pose ten times a simulated second, equal to trajectory.csv's rows.
TEST(CliSim, ALiveRunWithoutALidarStreamsItsPose) {
  if (!fs::exists(fs::path(STARNAV_CLI_PATH).parent_path().parent_path() / "viewer" / "viewer.js"))
    GTEST_SKIP() << "the viewer is not bundled in this build (no npm)";
  const test::ScratchDir dir;
  test::write_text(dir.file("drive.yaml"), R"(name: drive
world: {obstacles: [{name: box, kind: box, position_m: [3.0, 0.0], size_m: [0.5, 0.5, 0.5]}]}
robot: {start: {x_m: 0.0, y_m: 0.0, yaw_deg: 0.0}}
sim: {dt_s: 0.01, duration_s: 2.0}
commands: [{duration_s: 2.0, vx_mps: 0.3, wz_radps: 0.2}]
)");
  const std::vector<std::string> steps = live_step_events({dir.file("drive.yaml"), "--out", dir.file("live")}, dir.file("live.err"));
  ASSERT_EQ(steps.size(), 20u);
  std::map<long, std::pair<double, double>> rows;  // by t in ms
  std::istringstream trajectory(test::read_text(dir.file("live/trajectory.csv")));
  std::string row;
  std::getline(trajectory, row);
  while (std::getline(trajectory, row)) {
    double t = 0, x = 0, y = 0;
    char c = 0;
    std::istringstream(row) >> t >> c >> x >> c >> y;
    rows[std::lround(t * 1000)] = {x, y};
  }
  for (const std::string& s : steps) {
    const auto j = nlohmann::json::parse(s);
    const auto it = rows.find(std::lround(j["t_s"].get<double>() * 1000));
    ASSERT_NE(it, rows.end()) << s;
    EXPECT_NEAR(j["pose"][0].get<double>(), it->second.first, 5e-4) << s;
    EXPECT_NEAR(j["pose"][1].get<double>(), it->second.second, 5e-4) << s;
  }
}
#endif

}  // namespace
}  // namespace starnav
