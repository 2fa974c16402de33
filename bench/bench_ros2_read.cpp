// Reading speed of ROS 2 recordings against ROS 1 bags of the same log (scripts/bench-ros2.sh runs
// these with the converted files; without STARNAV_ROS2_BENCH_DIR they skip): the whole read into a
// RobotLog (decompression, CDR decoding, assembly), bytes per second counted as the messages'
// decompressed payload (every message of every topic, the CDR bytes), so that a faster codec is
// not credited with the container's overhead.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "starnav/core/input_file.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/logs/ros2_bag.hpp"
#include "starnav/logs/ros_bag.hpp"

namespace {

std::string bench_file(const std::string& name) {
  const char* dir = std::getenv("STARNAV_ROS2_BENCH_DIR");
  if (!dir) return {};
  const std::filesystem::path p = std::filesystem::path(dir) / name;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

std::size_t mcap_payload(const std::string& bytes) {
  starnav::McapReader r(bytes, "payload");
  std::size_t n = 0;
  r.for_each_message([](const starnav::McapChannel&) { return true; }, [&](const starnav::McapMessageView& m) { n += m.data.size(); });
  return n;
}

void BM_ReadRos2(benchmark::State& state, const std::string& name) {
  const std::string path = bench_file(name);
  if (path.empty()) {
    state.SkipWithError("STARNAV_ROS2_BENCH_DIR does not hold the converted file (scripts/bench-ros2.sh)");
    return;
  }
  const std::string bytes = starnav::read_input_file(path);
  // A SQLite3 file holds the same messages as the plain MCAP converted from the same bag: its
  // payload is counted there.
  const std::string plain = bench_file("intel-plain.mcap");
  const std::size_t payload =
      starnav::is_mcap(bytes) ? mcap_payload(bytes) : (plain.empty() ? 0 : mcap_payload(starnav::read_input_file(plain)));
  for (auto _ : state) benchmark::DoNotOptimize(starnav::read_ros2_bag_bytes(bytes, path));
  state.SetBytesProcessed(static_cast<std::int64_t>(payload * state.iterations()));
  state.counters["payload_MB"] = static_cast<double>(payload) / 1e6;
}

void BM_ReadRos1(benchmark::State& state, const std::string& name) {
  const std::string path = bench_file(name);
  if (path.empty()) {
    state.SkipWithError("STARNAV_ROS2_BENCH_DIR does not hold the ROS 1 bag (scripts/bench-ros2.sh)");
    return;
  }
  const std::string bytes = starnav::read_input_file(path);
  std::size_t payload = 0;
  starnav::for_each_bag_message(bytes, path, [&](const starnav::BagMessageView& m) { payload += m.data.size(); });
  for (auto _ : state) benchmark::DoNotOptimize(starnav::read_ros1_bag(bytes, path));
  state.SetBytesProcessed(static_cast<std::int64_t>(payload * state.iterations()));
  state.counters["payload_MB"] = static_cast<double>(payload) / 1e6;
}

BENCHMARK_CAPTURE(BM_ReadRos2, intel_mcap_zstd, std::string("intel-zstd.mcap"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadRos2, intel_mcap_lz4, std::string("intel-lz4.mcap"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadRos2, intel_mcap_plain, std::string("intel-plain.mcap"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadRos2, intel_sqlite3, std::string("intel.db3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadRos1, intel_bag_bz2, std::string("intel.orig.bag"))->Unit(benchmark::kMillisecond);

}  // namespace
