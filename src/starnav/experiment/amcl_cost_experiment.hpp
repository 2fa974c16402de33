#pragma once
// The CPU time of one AMCL update against the particle count and the beams used (Ren et al.
// 2022's localization on a small robot's CPU; the plot): on a map_server map, a robot at
// the free pose farthest from any obstacle, a 360-beam scan cast there on the map, and for every
// pair (particles, beams) a filter with min = max particles updated `updates` times (the odometry
// alternating between two poses 0.3 m apart, so every call updates: motion model, likelihood
// field, KLD resampling, clusters), timed `repeats` times in the thread's CPU time (what it costs
// on one core, whatever else a shared machine runs); the median, the fastest and the slowest per
// update.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace starnav {

struct AmclCostConfig {
  std::string map_file;                                        // map_server YAML
  std::vector<int> particles = {500, 1000, 2000, 5000, 10000, 20000};
  std::vector<int> beams = {30, 60, 120, 180, 360};
  int updates = 10;    // per timing
  int repeats = 5;     // timings per pair (median, min, max)
  std::uint64_t seed = 0;
  // Throws Error naming the flag ("--particles", ...) for an impossible value.
  void validate() const;
};

struct AmclCostRow {
  int particles = 0;
  int beams = 0;        // used per update
  double median_ms = 0.0, min_ms = 0.0, max_ms = 0.0;  // per update
  double ns_per_particle_beam = 0.0;                     // median / (particles x beams)
};

struct AmclCostResult {
  AmclCostConfig config;
  std::string map_name;
  double map_width_m = 0.0, map_height_m = 0.0, resolution_m = 0.0;
  std::vector<AmclCostRow> rows;  // particles outer, beams inner, in the configured order
};

// progress(done, total) after each pair.
AmclCostResult run_amcl_cost(const AmclCostConfig& config,
                             const std::function<void(std::size_t, std::size_t)>& progress = {});
std::string amcl_cost_markdown(const AmclCostResult& result);
std::string amcl_cost_json(const AmclCostResult& result);
std::string amcl_cost_csv(const AmclCostResult& result);
// cost_vs_particles.svg (a line per beam count) and cost_vs_beams.svg (a line per particle count).
void write_amcl_cost_pictures(const AmclCostResult& result, const std::string& dir);

}  // namespace starnav
