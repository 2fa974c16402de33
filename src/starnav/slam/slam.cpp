#include "starnav/slam/slam.hpp"

#include <cmath>

#include "starnav/core/error.hpp"

namespace starnav {

const char* slam_space_name(SlamSpace space) {
  switch (space) {
    case SlamSpace::Planar: return "planar";
    case SlamSpace::ThreeD: return "3d";
  }
  return "planar";
}

std::vector<TrajectoryPose> planar_trajectory(const std::vector<SlamPose>& poses) {
  std::vector<TrajectoryPose> out;
  out.reserve(poses.size());
  for (const SlamPose& p : poses) out.push_back({p.stamp_us, p.base});
  return out;
}

std::int64_t microseconds_of(double t_s) { return std::llround(t_s * 1e6); }

std::size_t SlamGraph::closures() const {
  std::size_t n = 0;
  for (const SlamGraphEdge& e : edges) n += e.kind != SlamEdgeKind::Local;
  return n;
}

std::string slam_edge_kind_name(SlamEdgeKind kind) {
  switch (kind) {
    case SlamEdgeKind::Local:
      return "local";
    case SlamEdgeKind::Loop:
      return "loop";
    case SlamEdgeKind::Global:
      return "global";
  }
  return "local";
}

OctreeMap keyframes_octree(const std::vector<Slam3dKeyframe>& keyframes, const OctreeMapConfig& config) {
  OctreeMap map(config);
  for (const Slam3dKeyframe& kf : keyframes) map.insert_scan(kf.pose, kf.cloud);
  return map;
}

bool Slam::on_scan(const ScanMessage& scan) {
  throw Error("SLAM method '" + std::string(name()) + "' maps 3D clouds, not planar scans", {}, 0, scan.header.stream);
}

bool Slam::on_cloud(const CloudMessage& cloud) {
  throw Error("SLAM method '" + std::string(name()) + "' maps planar scans, not 3D clouds", {}, 0, cloud.header.stream);
}

OctreeMap Slam::map_3d(const OctreeMapConfig& /*config*/) const {
  throw Error("SLAM method '" + std::string(name()) + "' maps planar scans: it has no 3D map", {}, 0, "method");
}

const std::vector<Slam3dKeyframe>& Slam::keyframes_3d() const {
  static const std::vector<Slam3dKeyframe> none;
  return none;
}

}  // namespace starnav
