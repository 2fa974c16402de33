// Ray casting and LiDAR scans (docs/simulator.md, "Speed"): a 16-line LiDAR (VLP-16 preset) at 0.2 deg
// horizontal resolution, 28,800 rays per scan, over a 100 m x 100 m terrain at 0.1 m with 100
// obstacles. Target: >= 1 million rays per second on one core.
// The terrain is smooth and random (sum of plane waves and Gaussian bumps from starnav::Rng);
// the obstacles (boxes, cylinders, prisms, spheres, 0.2-2 m) stand on it at random places; the
// sensor sits 0.8 m above the ground at 8 poses spread over the map, one per iteration in turn.
// Counters: items_per_second = rays per second; Mrays_per_s the same in millions.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Raycast
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sim/world.hpp"

namespace bench_raycast {

using namespace starnav;

ElevationMap bench_terrain(double size_m, double resolution, std::uint64_t seed) {
  GridGeometry g;
  g.width = g.height = static_cast<int>(std::lround(size_m / resolution));
  g.resolution = resolution;
  g.origin = Pose2(-0.5 * size_m, -0.5 * size_m, 0.0);
  ElevationMap map(g);
  Rng rng(seed);
  struct Wave {
    double kx, ky, amp, phase;
  };
  std::vector<Wave> waves;
  for (int k = 0; k < 12; ++k) {
    const double lambda = rng.uniform(5.0, 50.0), psi = rng.uniform(0.0, kPi);
    waves.push_back({2 * kPi * std::cos(psi) / lambda, 2 * kPi * std::sin(psi) / lambda, rng.uniform(0.02, 0.12),
                     rng.uniform(0.0, 2 * kPi)});
  }
  struct Bump {
    double x, y, r, h;
  };
  std::vector<Bump> bumps;
  for (int k = 0; k < 30; ++k)
    bumps.push_back({rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0), rng.uniform(2.0, 8.0),
                     rng.uniform(-1.5, 2.0)});
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Vec2 c = g.cell_center(ix, iy);
      double h = 0.0;
      for (const Wave& w : waves) h += w.amp * std::sin(w.kx * c.x() + w.ky * c.y() + w.phase);
      for (const Bump& b : bumps) {
        const double d2 = (c.x() - b.x) * (c.x() - b.x) + (c.y() - b.y) * (c.y() - b.y);
        h += b.h * std::exp(-d2 / (2 * b.r * b.r));
      }
      map.set_height(ix, iy, h);
    }
  return map;
}

std::vector<Obstacle> bench_obstacles(const TerrainSurface& ground, int count, std::uint64_t seed, int moving) {
  Rng rng(seed);
  std::vector<Obstacle> out;
  for (int i = 0; i < count; ++i) {
    const double x = rng.uniform(-45.0, 45.0), y = rng.uniform(-45.0, 45.0);
    const double z = ground.height(x, y);
    const double s = rng.uniform(0.2, 2.0), yaw = rng.uniform(0.0, kPi);
    Obstacle o;
    o.anchor = Vec3(x, y, z);
    switch (i % 4) {
      case 0: o.parts.emplace_back(Box{Vec3(x, y, z + 0.4 * s), Vec3(s, 0.7 * s, s), 0.0, 0.0, yaw}); break;
      case 1: o.parts.emplace_back(Cylinder{Vec3(x, y, z - 0.1), 0.4 * s, s}); break;
      case 2: o.parts.emplace_back(Prism{Vec3(x, y, z - 0.05), yaw, s, 0.5 * s, 0.0, 1.5 * s}); break;
      default: o.parts.emplace_back(Sphere{Vec3(x, y, z + 0.3 * s), 0.5 * s}); break;
    }
    if (i < moving) o.velocity = Vec3(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.0);
    out.push_back(std::move(o));
  }
  return out;
}

struct BenchWorld {
  std::unique_ptr<World> world;
  std::vector<Pose3> poses;
};

const BenchWorld& bench_world(bool terrain, int obstacles, int moving) {
  static std::vector<std::pair<std::tuple<bool, int, int>, std::unique_ptr<BenchWorld>>> cache;
  const auto key = std::make_tuple(terrain, obstacles, moving);
  for (const auto& [k, w] : cache)
    if (k == key) return *w;
  const ElevationMap map = bench_terrain(100.0, 0.1, 7);
  const TerrainSurface ground(map);
  WorldDescription d;
  if (terrain) d.terrain = map;
  d.obstacles = bench_obstacles(ground, obstacles, 11, moving);
  auto bw = std::make_unique<BenchWorld>();
  bw->world = std::make_unique<World>(d);
  Rng rng(3);
  for (int k = 0; k < 8; ++k) {
    const double x = rng.uniform(-40.0, 40.0), y = rng.uniform(-40.0, 40.0);
    const double z = terrain ? ground.height(x, y) : 0.0;
    bw->poses.push_back(Pose3::from_rpy(Vec3(x, y, z + 0.8), 0.0, 0.0, rng.uniform(-kPi, kPi)));
  }
  cache.emplace_back(key, std::move(bw));
  return *cache.back().second;
}

void run_scan(benchmark::State& state, const char* model, bool terrain, int obstacles, int moving) {
  const BenchWorld& bw = bench_world(terrain, obstacles, moving);
  Lidar lidar(lidar_preset(model, deg_to_rad(0.2)));
  LidarScan scan;
  std::size_t k = 0, returns = 0;
  double t = 0.0;
  for (auto _ : state) {
    lidar.scan(*bw.world, bw.poses[k++ % bw.poses.size()], t, scan);
    if (moving > 0) t += 0.1;
    returns += scan.points_world.size();
    benchmark::DoNotOptimize(scan.ranges.data());
  }
  const double rays = static_cast<double>(state.iterations()) * static_cast<double>(lidar.config().ray_count());
  state.SetItemsProcessed(static_cast<std::int64_t>(rays));
  state.counters["Mrays_per_s"] = benchmark::Counter(rays * 1e-6, benchmark::Counter::kIsRate);
  state.counters["rays_per_scan"] = static_cast<double>(lidar.config().ray_count());
  state.counters["return_fraction"] = static_cast<double>(returns) / rays;
}

void BM_RaycastVlp16TerrainObstacles(benchmark::State& s) { run_scan(s, "vlp16", true, 100, 0); }
void BM_RaycastVlp16TerrainOnly(benchmark::State& s) { run_scan(s, "vlp16", true, 0, 0); }
void BM_RaycastVlp16ObstaclesOnly(benchmark::State& s) { run_scan(s, "vlp16", false, 100, 0); }
void BM_RaycastVlp16MovingObstacles(benchmark::State& s) { run_scan(s, "vlp16", true, 100, 20); }
void BM_RaycastHdl64TerrainObstacles(benchmark::State& s) { run_scan(s, "hdl64e", true, 100, 0); }
void BM_RaycastUtm30TerrainObstacles(benchmark::State& s) { run_scan(s, "hokuyo_utm30lx", true, 100, 0); }
BENCHMARK(BM_RaycastVlp16TerrainObstacles)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastVlp16TerrainOnly)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastVlp16ObstaclesOnly)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastVlp16MovingObstacles)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastHdl64TerrainObstacles)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastUtm30TerrainObstacles)->Unit(benchmark::kMillisecond);

}  // namespace bench_raycast
