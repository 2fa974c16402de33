#include "starnav/experiment/amcl_cost_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

namespace {

using json = nlohmann::ordered_json;

constexpr double kAmclCostRangeMaxM = 30.0;
// Nav2's subsampling, step (360 - 1) / (b - 1), gives exactly b beams for 30, 60, 120, 180 and 360.
constexpr int kAmclCostScanBeams = 360;

double amcl_cost_median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

void AmclCostConfig::validate() const {
  require(!particles.empty(), "--particles", "needs at least one count");
  for (const int p : particles) require(p >= 1 && p <= 1'000'000, "--particles", "each count must be in [1, 1000000]");
  require(!beams.empty(), "--beams", "needs at least one count");
  for (const int b : beams) require(b >= 2 && b <= kAmclCostScanBeams, "--beams", "each count must be in [2, 360]");
  require(updates >= 1 && updates <= 10'000, "--updates", "must be in [1, 10000]");
  require(repeats >= 1 && repeats <= 1'000, "--repeats", "must be in [1, 1000]");
}

AmclCostResult run_amcl_cost(const AmclCostConfig& config, const std::function<void(std::size_t, std::size_t)>& progress) {
  config.validate();
  AmclCostResult result;
  result.config = config;
  const OccupancyGrid map = read_ros_map(config.map_file);
  const GridGeometry& g = map.geometry();
  result.map_name = std::filesystem::path(config.map_file).stem().string();
  result.map_width_m = g.width * g.resolution;
  result.map_height_m = g.height * g.resolution;
  result.resolution_m = g.resolution;
  const OccupancyThresholds thresholds;

  // The robot at the free cell farthest from any obstacle: a pose every map has, found without a seed.
  const std::vector<double> distance = obstacle_distance_m(map, thresholds, /*unknown_is_obstacle=*/false);
  Vec2 robot(0.0, 0.0);
  double best = -1.0;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      if (thresholds.classify(map(ix, iy)) != CellState::Free) continue;
      const double d = distance[g.index(ix, iy)];
      if (d > best) {
        best = d;
        robot = g.cell_center(ix, iy);
      }
    }
  require(best >= 0.0, "map", "has no free cell");
  const Pose2 truth(robot.x(), robot.y(), 0.3);
  const BeamModel caster(map, thresholds, BeamModelConfig{});
  PlanarScan scan;
  scan.range_min_m = 0.05;
  scan.range_max_m = kAmclCostRangeMaxM;
  for (int i = 0; i < kAmclCostScanBeams; ++i) {
    const double a = kPi - i * (2.0 * kPi / kAmclCostScanBeams);
    scan.ranges.push_back(caster.expected_range(Pose2(truth.x, truth.y, truth.yaw + a), kAmclCostRangeMaxM));
    scan.angles_rad.push_back(a);
  }

  const std::size_t total = config.particles.size() * config.beams.size();
  for (const int particles : config.particles)
    for (const int beams : config.beams) {
      AmclConfig c;
      c.min_particles = c.max_particles = particles;
      c.max_beams = beams;
      c.laser_max_range_m = kAmclCostRangeMaxM;
      Amcl amcl(map, thresholds, c, Pose2(), config.seed);
      std::vector<double> per_update_ms;
      for (int r = 0; r < config.repeats; ++r) {
        amcl.initialize(truth);
        amcl.update(Pose2(), scan);  // the first scan: the odometry reference
        const double t0 = thread_cpu_s();
        for (int u = 0; u < config.updates; ++u) amcl.update(Pose2(u % 2 ? 0.0 : 0.3, 0.0, 0.0), scan);
        per_update_ms.push_back((thread_cpu_s() - t0) * 1e3 / config.updates);
      }
      AmclCostRow row;
      row.particles = particles;
      row.beams = static_cast<int>(model_beams(scan, beams, scan.range_min_m, scan.range_max_m).size());
      row.median_ms = amcl_cost_median(per_update_ms);
      row.min_ms = *std::min_element(per_update_ms.begin(), per_update_ms.end());
      row.max_ms = *std::max_element(per_update_ms.begin(), per_update_ms.end());
      row.ns_per_particle_beam = row.median_ms * 1e6 / (static_cast<double>(particles) * row.beams);
      result.rows.push_back(row);
      if (progress) progress(result.rows.size(), total);
    }
  return result;
}

std::string amcl_cost_markdown(const AmclCostResult& r) {
  std::ostringstream out;
  out << "# AMCL update time: " << r.map_name << " (" << format_fixed(r.map_width_m, 1) << " m x "
      << format_fixed(r.map_height_m, 1) << " m at " << format_fixed(r.resolution_m, 3) << " m)\n\n";
  out << "Per filter update (motion model, likelihood field, KLD resampling, clusters), median [min .. max] of "
      << r.config.repeats << " timings of " << r.config.updates << " updates; one core.\n\n";
  out << "| particles | beams | ms per update | ns per particle and beam |\n|---|---|---|---|\n";
  for (const AmclCostRow& row : r.rows)
    out << "| " << row.particles << " | " << row.beams << " | " << format_fixed(row.median_ms, 3) << " ["
        << format_fixed(row.min_ms, 3) << " .. " << format_fixed(row.max_ms, 3) << "] | "
        << format_fixed(row.ns_per_particle_beam, 2) << " |\n";
  return out.str();
}

std::string amcl_cost_json(const AmclCostResult& r) {
  json rows = json::array();
  for (const AmclCostRow& row : r.rows)
    rows.push_back({{"particles", row.particles},
                    {"beams", row.beams},
                    {"median_ms", row.median_ms},
                    {"min_ms", row.min_ms},
                    {"max_ms", row.max_ms},
                    {"ns_per_particle_beam", row.ns_per_particle_beam}});
  json j = {{"map", r.map_name},
            {"map_width_m", r.map_width_m},
            {"map_height_m", r.map_height_m},
            {"resolution_m", r.resolution_m},
            {"updates", r.config.updates},
            {"repeats", r.config.repeats},
            {"rows", rows}};
  return j.dump(2) + "\n";
}

std::string amcl_cost_csv(const AmclCostResult& r) {
  std::string out = "particles,beams,median_ms,min_ms,max_ms,ns_per_particle_beam\n";
  for (const AmclCostRow& row : r.rows)
    out += std::to_string(row.particles) + "," + std::to_string(row.beams) + "," + format_fixed(row.median_ms, 4) + "," +
           format_fixed(row.min_ms, 4) + "," + format_fixed(row.max_ms, 4) + "," +
           format_fixed(row.ns_per_particle_beam, 3) + "\n";
  return out;
}

void write_amcl_cost_pictures(const AmclCostResult& r, const std::string& dir) {
  const std::filesystem::path d(dir);
  viz::LinePlot by_particles({.title = "AMCL update time against particles (" + r.map_name + ")",
                              .x_label = "particles",
                              .y_label = "ms per update"});
  const std::size_t nb = r.config.beams.size();
  for (std::size_t b = 0; b < nb; ++b) {
    std::vector<Vec2> points;
    for (std::size_t p = 0; p < r.config.particles.size(); ++p) {
      const AmclCostRow& row = r.rows[p * nb + b];
      points.emplace_back(row.particles, row.median_ms);
    }
    by_particles.add_series(points, {.colour = viz::categorical_colour(b), .markers = true},
                            std::to_string(r.rows[b].beams) + " beams");
  }
  by_particles.write_svg((d / "cost_vs_particles.svg").string());
  viz::LinePlot by_beams({.title = "AMCL update time against beams (" + r.map_name + ")",
                          .x_label = "beams used",
                          .y_label = "ms per update"});
  for (std::size_t p = 0; p < r.config.particles.size(); ++p) {
    std::vector<Vec2> points;
    for (std::size_t b = 0; b < nb; ++b) {
      const AmclCostRow& row = r.rows[p * nb + b];
      points.emplace_back(row.beams, row.median_ms);
    }
    by_beams.add_series(points, {.colour = viz::categorical_colour(p), .markers = true},
                        std::to_string(r.config.particles[p]) + " particles");
  }
  by_beams.write_svg((d / "cost_vs_beams.svg").string());
}

}  // namespace starnav
