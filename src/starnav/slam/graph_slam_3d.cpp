#include "starnav/slam/graph_slam_3d.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "starnav/cloud/local_shape.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

const ParamTable<GraphSlam3dConfig>& graph_slam_3d_params() {
  static const ParamTable<GraphSlam3dConfig> table = [] {
    using C = GraphSlam3dConfig;
    ParamTable<C> t;
    t.nest("", prefilter_params(), [](C& c) -> PrefilterConfig& { return c.prefilter; });
    t.real("keyframe_delta_trans_m", &C::keyframe_delta_trans_m, closed(0.01, 100.0), "m", "a new key frame after this much motion");
    t.real("keyframe_delta_angle_deg", &C::keyframe_delta_angle_rad, closed(0.1, 360.0), "deg",
           "a new key frame after this much turning", kPi / 180.0);
    t.real("odometry_sigma_m", &C::odometry_sigma_m, closed(1e-5, 10.0), "m", "1 sigma of a registration edge's translation");
    t.real("odometry_sigma_deg", &C::odometry_sigma_rad, closed(1e-4, 90.0), "deg", "1 sigma of a registration edge's rotation",
           kPi / 180.0);
    t.boolean("floor", &C::floor, "detect the floor in every key frame and add it as a plane edge");
    t.real("floor_height_band_m", &C::floor_height_band_m, closed(0.01, 10.0), "m",
           "floor points are looked for this far above and below its expected height");
    t.real("floor_normal_max_deg", &C::floor_normal_max_rad, closed(0.0, 90.0), "deg",
           "a floor's normal is at most this far from the sensor's up", kPi / 180.0);
    t.integer("floor_min_points", &C::floor_min_points, closed(3, 10000000), "", "inliers a floor needs");
    t.real("floor_ransac_threshold_m", &C::floor_ransac_threshold_m, closed(0.001, 1.0), "m", "RANSAC's inlier distance");
    t.real("floor_sigma", &C::floor_sigma, closed(1e-5, 10.0), "rad, m", "1 sigma of a floor edge's angles and distance");
    t.boolean("loops", &C::loops, "look for loop closures");
    t.real("loop_distance_m", &C::loop_distance_m, closed(0.0, 1000.0), "m", "candidates within this distance");
    t.real("loop_accum_distance_m", &C::loop_accum_distance_m, closed(0.0, 1e6), "m", "... travelled at least this far apart");
    t.real("loop_min_interval_m", &C::loop_min_interval_m, closed(0.0, 1e6), "m", "travel between two closures");
    t.real("loop_fitness_max_m2", &C::loop_fitness_max_m2, closed(1e-6, 100.0), "m^2", "a closure's registration fitness at most");
    t.integer("seed", &C::seed, closed(0, 1e15), "", "RANSAC's random draws");
    return t;
  }();
  return table;
}

void GraphSlam3dConfig::validate() const {
  prefilter.validate();
  require_positive(keyframe_delta_trans_m, "keyframe_delta_trans_m");
  require_positive(keyframe_delta_angle_rad, "keyframe_delta_angle_deg");
  require_positive(odometry_sigma_m, "odometry_sigma_m");
  require_positive(odometry_sigma_rad, "odometry_sigma_deg");
  require_positive(floor_height_band_m, "floor_height_band_m");
  require(floor_normal_max_rad >= 0 && floor_normal_max_rad <= kPi / 2, "floor_normal_max_deg", "must be in [0, 90]");
  require(floor_min_points >= 3, "floor_min_points", "must be >= 3");
  require_positive(floor_ransac_threshold_m, "floor_ransac_threshold_m");
  require_positive(floor_sigma, "floor_sigma");
  require_non_negative(loop_distance_m, "loop_distance_m");
  require_non_negative(loop_accum_distance_m, "loop_accum_distance_m");
  require_non_negative(loop_min_interval_m, "loop_min_interval_m");
  require_positive(loop_fitness_max_m2, "loop_fitness_max_m2");
}

namespace {

Rigid3 level_base(const Pose2& p) {
  Rigid3 t = Rigid3::Identity();
  t.linear() = Eigen::AngleAxisd(p.yaw, Vec3::UnitZ()).toRotationMatrix();
  t.translation() = Vec3(p.x, p.y, 0.0);
  return t;
}

double seconds_between(std::chrono::steady_clock::time_point a) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

}  // namespace

GraphSlam3d::GraphSlam3d(const GraphSlam3dConfig& config, const MatcherFactory& make_matcher) : c_(config), rng_(config.seed) {
  c_.validate();
  if (make_matcher) {
    matcher_ = make_matcher();
    loop_matcher_ = make_matcher();
  }
  if (!matcher_ || !loop_matcher_) throw Error("no 3D scan matcher", "", 0, "matcher");
}

GraphSlam3d::GraphSlam3d(const GraphSlam3dConfig& config, const Pose3& mount, const MatcherFactory& make_matcher)
    : GraphSlam3d(config, make_matcher) {
  mount_ = mount;
}

Eigen::Matrix<double, 6, 6> GraphSlam3d::registration_information() const {
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
  info.diagonal().head<3>().setConstant(1.0 / (c_.odometry_sigma_m * c_.odometry_sigma_m));
  info.diagonal().tail<3>().setConstant(1.0 / (c_.odometry_sigma_rad * c_.odometry_sigma_rad));
  return info;
}

std::optional<Plane3> GraphSlam3d::detect_floor(const PointCloud& cloud) {
  // The expected floor: z = 0 in the map frame, seen from the current estimate of the sensor's
  // height and tilt (the last key frame's, or the mount's before the first).
  const Rigid3 pose = keyframes_.empty() ? to_rigid(*mount_) : keyframes_.back().pose;
  const Eigen::Matrix3d r = pose.linear();
  const double height = pose.translation().z();
  PointCloud near_floor;
  for (const Vec3& p : cloud)
    if (std::abs((r * p).z() + height) <= c_.floor_height_band_m) near_floor.push_back(p);
  // hdl_graph_slam's normal filter: only points whose own surface is level enough, so that the
  // feet of walls and the sides of furniture in the band cannot tilt the plane.
  const Vec3 up = r.transpose() * Vec3::UnitZ();
  const double min_cos = std::cos(c_.floor_normal_max_rad);
  PointCloud band;
  if (near_floor.size() >= 3) {
    const KdTree3 tree(near_floor);
    const std::vector<LocalShape> shapes = local_shapes(tree, 10);
    for (std::size_t i = 0; i < near_floor.size(); ++i)
      if (shapes[i].valid && std::abs(shapes[i].normal.dot(up)) >= min_cos) band.push_back(near_floor[i]);
  }
  RansacPlaneConfig rc;
  rc.distance_threshold_m = c_.floor_ransac_threshold_m;
  rc.iterations = 200;
  rc.min_inliers = static_cast<std::size_t>(c_.floor_min_points);
  rc.axis = up;
  rc.max_axis_angle_rad = c_.floor_normal_max_rad;
  const RansacPlane found = ransac_plane(band, rc, rng_);
  if (!found.found) return std::nullopt;
  return found.plane;
}

void GraphSlam3d::add_keyframe(std::size_t frame, double t_s, PointCloud cloud, const Rigid3& relative, double moved_m) {
  Slam3dKeyframe kf;
  kf.frame = frame;
  kf.t_s = t_s;
  kf.accum_distance_m = moved_m;
  if (keyframes_.empty()) {
    // The map frame: the floor at z = 0 below the mount. The first key frame is tied to that pose
    // by the anchor (optimise()), firmly in x, y and yaw, loosely in height and tilt, so that
    // the floor seen from every key frame, not the first one alone, sets them.
    kf.pose = to_rigid(*mount_);
  } else {
    kf.pose = keyframes_.back().pose * relative;
    edges_.push_back({keyframes_.size() - 1, keyframes_.size(), relative, registration_information(), RobustLoss::None, 1.0});
  }
  kf.cloud = std::move(cloud);
  keyframes_.push_back(std::move(kf));
  Slam3dKeyframe& added = keyframes_.back();
  if (c_.floor) added.floor = detect_floor(added.cloud);
  if (added.floor) {
    PlaneEdge3 e;
    e.node = keyframes_.size() - 1;
    e.measured = *added.floor;
    e.information = Eigen::Matrix3d::Identity() / (c_.floor_sigma * c_.floor_sigma);
    plane_edges_.push_back(e);
  }
  matcher_->set_reference(added.cloud);
  detect_loops();
}

void GraphSlam3d::detect_loops() {
  if (!c_.loops || keyframes_.size() < 2) return;
  const std::size_t n = keyframes_.size() - 1;
  const Slam3dKeyframe& now = keyframes_[n];
  if (now.accum_distance_m - last_loop_accum_m_ < c_.loop_min_interval_m) return;
  std::vector<std::pair<double, std::size_t>> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = (keyframes_[i].pose.translation() - now.pose.translation()).norm();
    if (now.accum_distance_m - keyframes_[i].accum_distance_m >= c_.loop_accum_distance_m && d <= c_.loop_distance_m)
      candidates.emplace_back(d, i);
  }
  std::sort(candidates.begin(), candidates.end());
  if (candidates.size() > 3) candidates.resize(3);
  std::optional<Slam3dLoop> best;
  Rigid3 best_transform = Rigid3::Identity();
  for (const auto& [d, i] : candidates) {
    const Rigid3 guess = keyframes_[i].pose.inverse() * now.pose;
    loop_matcher_->set_reference(keyframes_[i].cloud);
    const CloudMatch m = loop_matcher_->match(now.cloud, guess);
    if (!m.converged || !(m.fitness <= c_.loop_fitness_max_m2)) continue;
    if (!best || m.fitness < best->fitness) {
      best = Slam3dLoop{i, n, m.fitness};
      best_transform = m.transform;
    }
  }
  if (!best) return;
  // Huber beyond 3 sigma: a wrong closure that slipped through bends the map less.
  edges_.push_back({best->from, best->to, best_transform, registration_information(), RobustLoss::Huber, 3.0});
  loops_.push_back(*best);
  last_loop_accum_m_ = now.accum_distance_m;
  optimise();
}

void GraphSlam3d::optimise() {
  if (keyframes_.size() < 2) return;
  const auto start = std::chrono::steady_clock::now();
  // Node 0 is the fixed anchor at the mount's pose; key frame k is node k + 1.
  std::vector<Rigid3> poses;
  poses.reserve(keyframes_.size() + 1);
  poses.push_back(to_rigid(*mount_));
  for (const Slam3dKeyframe& k : keyframes_) poses.push_back(k.pose);
  std::vector<PoseGraph3Edge> edges;
  edges.reserve(edges_.size() + 1);
  PoseGraph3Edge anchor;
  anchor.from = 0;
  anchor.to = 1;
  // (x, y, z, roll, pitch, yaw) sigmas of 1 mm, 1 mm, 1 m, 1 rad, 1 rad, 0.001 rad.
  anchor.information.diagonal() << 1e6, 1e6, (c_.floor ? 1.0 : 1e6), (c_.floor ? 1.0 : 1e6), (c_.floor ? 1.0 : 1e6), 1e6;
  edges.push_back(anchor);
  for (PoseGraph3Edge e : edges_) {
    ++e.from;
    ++e.to;
    edges.push_back(e);
  }
  std::vector<PlaneEdge3> planes = plane_edges_;
  for (PlaneEdge3& p : planes) ++p.node;
  optimise_pose_graph_3d(poses, edges, planes, PoseGraph3Options{});
  for (std::size_t i = 0; i < keyframes_.size(); ++i) keyframes_[i].pose = poses[i + 1];
  optimise_s_ += seconds_between(start);
  ++optimisations_;
}

bool GraphSlam3d::add(double t_s, std::span<const Vec3> points, const std::optional<Pose2>& odometry) {
  if (!mount_) throw Error("the sensor's mount is not known (give it, or the clouds' messages carry it)", "", 0, "mount");
  Slam3dFrameResult fr;
  fr.frame = frames_.size();
  fr.t_s = t_s;
  PrefilterCounts counts;
  PointCloud cloud = prefilter_cloud(points, c_.prefilter, &counts);
  fr.raw_points = counts.raw;
  fr.windowed = counts.windowed;
  fr.voxelised = counts.voxelised;
  fr.filtered_points = counts.kept;
  if (cloud.size() < 10) throw Error("frame " + std::to_string(fr.frame) + " keeps " + std::to_string(cloud.size()) +
                                         " points after the prefilter, too few to register", "", 0, "prefilter");
  if (keyframes_.empty()) {
    add_keyframe(fr.frame, t_s, std::move(cloud), Rigid3::Identity(), 0.0);
    fr.keyframe_created = true;
    fr.converged = true;
    keyframe_odometry_ = odometry;
    frames_.push_back(fr);
    count(fr);
    return true;
  }
  Rigid3 guess = last_relative_ * last_step_;
  if (odometry && keyframe_odometry_) {
    const Rigid3 mount = to_rigid(*mount_);
    guess = mount.inverse() * level_base(*keyframe_odometry_).inverse() * level_base(*odometry) * mount;
  }
  const CloudMatch m = matcher_->match(cloud, guess);
  fr.match_s = m.time_s;
  fr.fitness = m.fitness;
  fr.iterations = m.iterations;
  fr.converged = m.converged;
  // A registration that failed outright keeps the guess (hdl_graph_slam ignores such a frame).
  const Rigid3 relative = m.transform.matrix().allFinite() && m.fitness <= 1.0 ? m.transform : guess;
  const Rigid3 step = last_relative_.inverse() * relative;
  last_step_ = step;
  last_relative_ = relative;
  accum_distance_m_ += translation_norm(step);
  fr.keyframe = keyframes_.size() - 1;
  fr.relative = relative;
  if (translation_norm(relative) >= c_.keyframe_delta_trans_m || rotation_angle(relative) >= c_.keyframe_delta_angle_rad) {
    add_keyframe(fr.frame, t_s, std::move(cloud), relative, accum_distance_m_);
    keyframe_odometry_ = odometry;
    last_relative_ = Rigid3::Identity();
    fr.keyframe = keyframes_.size() - 1;
    fr.relative = Rigid3::Identity();
    fr.keyframe_created = true;
  }
  frames_.push_back(fr);
  count(fr);
  return fr.keyframe_created;
}

void GraphSlam3d::count(const Slam3dFrameResult& f) {
  totals_.raw += f.raw_points;
  totals_.windowed += f.windowed;
  totals_.voxelised += f.voxelised;
  totals_.kept += f.filtered_points;
  totals_.match_s += f.match_s;
}

void GraphSlam3d::finish() { optimise(); }

std::vector<Rigid3> GraphSlam3d::sensor_poses() const {
  std::vector<Rigid3> out;
  out.reserve(frames_.size());
  for (const Slam3dFrameResult& f : frames_) out.push_back(keyframes_[f.keyframe].pose * f.relative);
  return out;
}

bool GraphSlam3d::on_cloud(const CloudMessage& cloud) {
  if (!mount_) mount_ = cloud.mount;
  return add(cloud.header.t_s, cloud.points, odometry_);
}

namespace {

// The base's planar pose under a sensor pose: (sensor * mount^-1) projected onto the floor.
Pose2 base_of(const Rigid3& sensor, const Rigid3& mount_inverse) {
  const Rigid3 base = sensor * mount_inverse;
  return Pose2(base.translation().x(), base.translation().y(), std::atan2(base.linear()(1, 0), base.linear()(0, 0)));
}

}  // namespace

std::vector<SlamPose> GraphSlam3d::trajectory() const {
  std::vector<SlamPose> out;
  if (!mount_) return out;
  const Rigid3 mount_inverse = to_rigid(*mount_).inverse();
  out.reserve(frames_.size());
  for (const Slam3dFrameResult& f : frames_) {
    const Rigid3 sensor = keyframes_[f.keyframe].pose * f.relative;
    out.push_back({f.t_s, microseconds_of(f.t_s), base_of(sensor, mount_inverse), sensor});
  }
  return out;
}

OctreeMap GraphSlam3d::map_3d(const OctreeMapConfig& config) const { return keyframes_octree(keyframes_, config); }

OccupancyGrid GraphSlam3d::map(const OccupancyMappingParams& params) const {
  OctreeMapConfig c;
  c.resolution_m = params.resolution_m;
  return map_3d(c).project_to_grid(GridProjectionConfig{});
}

SlamGraph GraphSlam3d::graph() const {
  SlamGraph g;
  if (!mount_) return g;
  const Rigid3 mount_inverse = to_rigid(*mount_).inverse();
  for (const Slam3dKeyframe& k : keyframes_) g.nodes.push_back({microseconds_of(k.t_s), base_of(k.pose, mount_inverse)});
  const Rigid3 mount = to_rigid(*mount_);
  const auto planar = [&](const Rigid3& sensor_relative) { return base_of(mount * sensor_relative, mount_inverse); };
  // Closures are the robust edges, in the order of loops_.
  std::size_t loop = 0;
  for (const PoseGraph3Edge& e : edges_) {
    const bool closure = e.loss != RobustLoss::None;
    g.edges.push_back({e.from, e.to, closure ? SlamEdgeKind::Loop : SlamEdgeKind::Local, planar(e.measurement),
                       closure ? loops_[loop++].fitness : 0.0});
  }
  return g;
}

std::vector<std::pair<std::string, double>> GraphSlam3d::statistics() const {
  const Slam3dTotals& t = totals_;
  const double nf = static_cast<double>(std::max<std::size_t>(1, frames_.size()));
  const auto d = [](std::size_t v) { return static_cast<double>(v); };
  return {{"frames", d(frames_.size())},
          {"keyframes", d(keyframes_.size())},
          {"loop_closures", d(loops_.size())},
          {"floor_edges", d(plane_edges_.size())},
          {"optimisations", static_cast<double>(optimisations_)},
          {"optimise_s", optimise_s_},
          {"raw_points", d(t.raw)},
          {"windowed_points", d(t.windowed)},
          {"voxelised_points", d(t.voxelised)},
          {"filtered_points", d(t.kept)},
          {"match_s", t.match_s},
          {"mean_raw_points", d(t.raw) / nf},
          {"mean_filtered_points", d(t.kept) / nf},
          {"mean_match_s", t.match_s / nf}};
}

SlamDef graph_slam_3d() {
  SlamDef d;
  d.info.role = Role::Slam;
  d.info.name = "graph3d";
  d.info.section = "graph3d";
  d.info.summary = "3D graph SLAM as hdl_graph_slam does it: prefiltered clouds registered onto key frames by a 3D scan matcher "
                   "(ndt_mt unless chosen), floor plane edges, loop closures, SE(3) pose-graph optimisation";
  d.info.capabilities = {Capability::ThreeD};
  d.info.params = graph_slam_3d_params().specs();
  d.make = [](const SlamContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Slam> {
    const GraphSlam3dConfig config = configured(graph_slam_3d_params(), settings, ctx.file);
    try {
      config.validate();
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
    if (!ctx.make_scan_matcher_3d) throw Error("no 3D scan matcher factory to compose 3D graph SLAM with", ctx.file, 0, ctx.matcher.field);
    SlamMatcherChoice choice = ctx.matcher;
    if (choice.name.empty()) choice.name = "ndt_mt";
    // Built once here so that a bad name or setting is reported before the SLAM holds any.
    (void)ctx.make_scan_matcher_3d(choice);
    return std::make_unique<GraphSlam3d>(config, [make = ctx.make_scan_matcher_3d, choice] { return make(choice); });
  };
  return d;
}

}  // namespace starnav
