#include "starnav/harness/simulation_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/harness/navigation_pictures.hpp"
#include "starnav/sim/outline.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

namespace fs = std::filesystem;

void write_scene_svg(const Simulation& sim, const std::string& path) {
  const World& world = sim.world();
  std::unique_ptr<viz::MapPicture> pic;
  viz::PictureOptions opts;
  opts.title = sim.spec().name + ": top view";
  if (sim.terrain_map()) {
    pic = std::make_unique<viz::MapPicture>(*sim.terrain_map(), opts);
  } else {
    Aabb b = world.bounds(0.0);
    for (const TrajectorySample& s : sim.trajectory()) b.extend(s.position);
    if (b.empty()) b.extend(Vec3::Zero());
    const double span = std::max({b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y(), 1.0});
    GridGeometry g;
    g.resolution = span / 400.0;
    g.origin = Pose2(b.lo.x() - 0.05 * span, b.lo.y() - 0.05 * span, 0.0);
    g.width = static_cast<int>(std::ceil((b.hi.x() - b.lo.x() + 0.1 * span) / g.resolution));
    g.height = static_cast<int>(std::ceil((b.hi.y() - b.lo.y() + 0.1 * span) / g.resolution));
    pic = std::make_unique<viz::MapPicture>(g, opts);
  }
  const viz::Rgba obstacle_colour{60, 60, 60, 255};
  const viz::Rgba dynamic_colour{204, 121, 167, 255};
  add_obstacle_outlines(*pic, world.obstacles(), sim.spec().duration_s,
                        {{obstacle_colour, 1.2, 1.0, false}, {dynamic_colour, 1.2, 1.0, false}, {dynamic_colour, 1.0, 1.0, true},
                         "obstacle", "dynamic obstacle (where it appears)"});
  if (sim.spec().reference_line.size() >= 2)
    pic->add_polyline(sim.spec().reference_line, {{0, 0, 0, 255}, 1.0, 0.8, true}, "reference line");
  std::vector<Vec2> track;
  for (const TrajectorySample& s : sim.trajectory()) track.push_back(s.position.head<2>());
  pic->add_polyline(track, {viz::categorical_colour(1), 2.0, 1.0, false}, "trajectory");
  pic->add_pose(sim.spec().start, 0.4, {viz::categorical_colour(2), 2.0, 1.0, false}, "start");
  std::vector<Vec2> hits;
  for (const SimEvent& e : sim.events())
    if (e.kind == "collision" || e.kind == "step") hits.push_back(e.where);
  if (!hits.empty()) pic->add_points(hits, {{213, 0, 0, 255}, 4.0, {255, 255, 255, 255}, 1.0, 1.0}, "collision / step");
  pic->write_svg(path);
}

void write_height_trace(const Simulation& sim, const std::string& path) {
  viz::LinePlot plot({.title = sim.spec().name + ": height of base_link over time", .x_label = "t [s]", .y_label = "z [m]"});
  std::vector<Vec2> z;
  for (const TrajectorySample& s : sim.trajectory()) z.emplace_back(s.t_s, s.position.z());
  plot.add_series(z, {viz::categorical_colour(1), 1.8, false, false}, "z(t)");
  plot.write_svg(path);
}

void write_track(const Simulation& sim, const std::string& path) {
  viz::LinePlot plot({.title = sim.spec().name + ": XY track", .x_label = "x [m]", .y_label = "y [m]"});
  // Static obstacles as shaded x bands, labelled, so the track's wobbles can be read against them.
  for (const Obstacle& o : sim.world().obstacles()) {
    if (o.moving() || o.appear > 0.0) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Primitive& part : o.parts) {
      const Aabb b = bounds(part);
      lo = std::min(lo, b.lo.x());
      hi = std::max(hi, b.hi.x());
    }
    if (std::isfinite(lo) && std::isfinite(hi)) plot.add_band(lo, hi, {200, 200, 200, 110}, o.name);
  }
  if (sim.spec().reference_line.size() >= 2)
    plot.add_series(sim.spec().reference_line, {{0, 0, 0, 255}, 1.2, true, false}, "reference line");
  std::vector<Vec2> track;
  for (const TrajectorySample& s : sim.trajectory()) track.push_back(s.position.head<2>());
  plot.add_series(track, {viz::categorical_colour(1), 1.8, false, false}, "track");
  plot.write_svg(path);
}

// Point clouds of every n-th scan into OUT/clouds/, after whatever the simulation's on_scan did.
void add_cloud_writer(Simulation& sim, const ScenarioSpec& spec, const std::string& out) {
  const auto cloud_format = spec.outputs.point_clouds;
  if (cloud_format == ScenarioOutputs::CloudFormat::None) return;
  const fs::path clouds = fs::path(out) / "clouds";
  std::error_code ec;
  fs::create_directories(clouds, ec);
  if (ec) throw Error("cannot create the folder: " + ec.message(), clouds.string(), 0, "--out");
  const int every = spec.outputs.clouds_every_n_scans;
  const bool ply = cloud_format == ScenarioOutputs::CloudFormat::Ply;
  auto scan_index = std::make_shared<std::int64_t>(0);
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [clouds, every, ply, scan_index](const LidarScan& scan) {
    if (*scan_index % every == 0) {
      char name[64];
      std::snprintf(name, sizeof name, "scan_%06lld.%s", static_cast<long long>(*scan_index), ply ? "ply" : "pcd");
      write_point_cloud((clouds / name).string(), scan.points_world, ply ? PointCloudFormat::Ply : PointCloudFormat::Pcd);
    }
    ++*scan_index;
  });
}

}  // namespace starnav
