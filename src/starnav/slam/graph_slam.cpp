#include "starnav/slam/graph_slam.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/slam/occupancy_mapping.hpp"

namespace starnav {

namespace {

Eigen::Matrix3d information(double sigma_m, double sigma_rad) {
  return Eigen::Vector3d(1.0 / (sigma_m * sigma_m), 1.0 / (sigma_m * sigma_m), 1.0 / (sigma_rad * sigma_rad)).asDiagonal();
}

}  // namespace

double scan_constraint(std::span<const Vec2> points) {
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  std::size_t n = 0;
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    const Vec2 d = points[i + 1] - points[i - 1];
    // Neighbours on one surface only: near each other and near the point.
    if (d.norm() > 0.5 || d.norm() < 1e-6 || (points[i] - points[i - 1]).norm() > 0.3) continue;
    const Vec2 normal = Vec2(-d.y(), d.x()).normalized();
    scatter += normal * normal.transpose();
    ++n;
  }
  if (n < 10) return 0.0;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter / static_cast<double>(n)).eigenvalues()(0);
}

PointNeighbourhood::PointNeighbourhood(std::span<const Vec2> points, double radius_m) : radius_m_(radius_m) {
  std::vector<std::pair<std::uint64_t, Vec2>> binned;
  binned.reserve(points.size());
  for (const Vec2& p : points) binned.emplace_back(key(cell(p.x()), cell(p.y())), p);
  std::sort(binned.begin(), binned.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  keys_.reserve(binned.size());
  points_.reserve(binned.size());
  for (const auto& [k, p] : binned) keys_.push_back(k), points_.push_back(p);
}

std::int64_t SurfaceGrid::cell(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_m_)); }

std::int64_t PointNeighbourhood::cell(double v) const { return static_cast<std::int64_t>(std::floor(v / radius_m_)); }

std::uint64_t PointNeighbourhood::key(std::int64_t cell_x, std::int64_t cell_y) const {
  return (static_cast<std::uint64_t>(cell_x) << 32) ^ static_cast<std::uint32_t>(cell_y);
}

bool PointNeighbourhood::near(const Vec2& position) const {
  const std::int64_t cx = cell(position.x()), cy = cell(position.y());
  for (std::int64_t dx = -1; dx <= 1; ++dx)
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      const auto [first, last] = std::equal_range(keys_.begin(), keys_.end(), key(cx + dx, cy + dy));
      for (auto it = first; it != last; ++it)
        if ((points_[static_cast<std::size_t>(it - keys_.begin())] - position).norm() <= radius_m_) return true;
    }
  return false;
}

SurfaceGrid::SurfaceGrid(std::span<const Vec2> points, double cell_m, int min_hits) : cell_m_(cell_m), min_hits_(min_hits) {
  if (points.empty()) return;
  Vec2 low = points[0], high = points[0];
  for (const Vec2& p : points) low = low.cwiseMin(p), high = high.cwiseMax(p);
  // A long-range laser's submap spans kilometres: its cells grow until the grid fits the bound.
  const double area = (high.x() - low.x() + cell_m_) * (high.y() - low.y() + cell_m_);
  if (area / (cell_m_ * cell_m_) > static_cast<double>(kMaxSurfaceGridCells)) cell_m_ = std::sqrt(area / static_cast<double>(kMaxSurfaceGridCells));
  min_x_ = cell(low.x());
  min_y_ = cell(low.y());
  width_ = cell(high.x()) - min_x_ + 1;
  height_ = cell(high.y()) - min_y_ + 1;
  occupied_.assign(static_cast<std::size_t>(width_ * height_), 0);
  for (const Vec2& p : points) {
    std::uint8_t& hits = occupied_[static_cast<std::size_t>((cell(p.y()) - min_y_) * width_ + cell(p.x()) - min_x_)];
    if (hits < 255) ++hits;
  }
}

bool SurfaceGrid::occupied(std::int64_t cx, std::int64_t cy) const {
  cx -= min_x_;
  cy -= min_y_;
  return cx >= 0 && cy >= 0 && cx < width_ && cy < height_ && occupied_[static_cast<std::size_t>(cy * width_ + cx)] >= min_hits_;
}

bool SurfaceGrid::crosses_surface(const Vec2& from, const Vec2& to, double stop_m) const {
  const double length = (to - from).norm();
  if (!(stop_m > 0) || length <= 0) return false;
  const std::int64_t start_x = cell(from.x()), start_y = cell(from.y());
  // Every cell the segment passes through up to stop_m (an exact traversal on the grid's lattice).
  const Vec2 stop = stop_m < length ? Vec2(from + (to - from) * (stop_m / length)) : to;
  bool crosses = false;
  for_each_cell_on_segment(from, stop, cell_m_, [&](std::int64_t cx, std::int64_t cy, bool) {
    crosses = crosses || ((cx != start_x || cy != start_y) && occupied(cx, cy));
  });
  return crosses;
}

double see_through_share(std::span<const Vec2> scan, const Pose2& pose, const SurfaceGrid& surfaces, double margin_m) {
  if (scan.empty()) return 0.0;
  const Vec2 origin = pose.translation();
  std::size_t through = 0;
  for (const Vec2& p : scan) {
    const Vec2 end = pose.transform(p);
    if (surfaces.crosses_surface(origin, end, (end - origin).norm() - margin_m)) ++through;
  }
  return static_cast<double>(through) / static_cast<double>(scan.size());
}

std::vector<Vec2> overlapping_points(std::span<const Vec2> scan, const Pose2& pose, const PointNeighbourhood& reference) {
  std::vector<Vec2> out;
  for (const Vec2& p : scan)
    if (reference.near(pose.transform(p))) out.push_back(p);
  return out;
}

const ParamTable<GraphSlamConfig>& graph_slam_params() {
  static const ParamTable<GraphSlamConfig> table = [] {
    using C = GraphSlamConfig;
    ParamTable<C> t;
    t.nest("local", local_slam_params(), &C::local);
    t.integer("submap_nodes", &C::submap_nodes, closed(2, 10000), "", "nodes per submap (a new submap starts every half)");
    t.real("loop_max_distance_m", &C::loop_max_distance_m, closed(0.0, 1000.0), "m",
           "closures are searched in submaps whose middle node lies this near the node's estimate");
    t.real("loop_window_linear_m", &C::loop_window_linear_m, closed(0.0, 100.0), "m", "closure search window, +- in x and y");
    t.real("loop_window_angular_deg", &C::loop_window_angular_rad, closed(0.0, 180.0), "deg", "closure search window, +- in yaw",
           kPi / 180.0);
    t.real("loop_min_score", &C::loop_min_score, closed(0.0, 1.0), "", "least mean likelihood of a closure");
    t.real("loop_max_range_m", &C::loop_max_range_m, closed(0.1, 1000.0), "m", "scan points used for closures and submaps");
    t.real("loop_overlap_radius_m", &C::loop_overlap_radius_m, closed(1e-3, 10.0), "m",
           "a closure's scan point within this of its submap's points is confirmed; the confirmed points must reach loop_min_constraint");
    t.real("loop_max_ambiguity", &C::loop_max_ambiguity, closed(0.0, 1.0), "",
           "a closure is refused when a pose loop_rival_distance_m or more away, within the drift bound's reach, scores this share "
           "of its score (1: never refused)");
    t.real("loop_rival_distance_m", &C::loop_rival_distance_m, closed(1e-3, 100.0), "m", "how far from a closure its rivals lie");
    t.real("loop_rival_angular_deg", &C::loop_rival_angular_rad, closed(0.0, 180.0), "deg",
           "rivals' yaw within this of the closure's (the drift in yaw is small; a repeated room lies at the same yaw)", kPi / 180.0);
    t.real("loop_prior_drift_multiple", &C::loop_prior_drift_multiple, closed(0.0, 1000.0), "",
           "closures' lattice scores (local and wide) times a Gaussian prior around the estimate, sigma this x the drift bound "
           "since the submap (at least " + format_number(kMinClosurePriorSigmaM) + " m; 0: no prior)");
    t.real("loop_max_see_through", &C::loop_max_see_through, closed(0.0, 1.0), "",
           "a closure is refused when the share of its scan's rays that, placed by the match, cross a surface its submap measured "
           "(a cell a third of loop_overlap_radius_m wide holding " + std::to_string(kSurfaceMinHits) +
               " of its points) loop_see_through_margin_m or more before their end exceeds the share that cross its own submap's "
               "surfaces by this much (1: never refused)");
    t.real("loop_see_through_margin_m", &C::loop_see_through_margin_m, closed(0.0, 100.0), "m",
           "a ray sees through a surface it crosses this far or more before its end");
    t.integer("loop_every_nodes", &C::loop_every_nodes, closed(1, 100000), "", "closures are searched on every n-th node");
    t.integer("global_every_nodes", &C::global_every_nodes, closed(0, 100000), "",
              "a wide search (whole circle) on every n-th node that found no closure (0: never)");
    t.real("global_window_linear_m", &C::global_window_linear_m, closed(0.0, 100.0), "m", "the wide search's largest window, +- in x and y");
    t.real("global_drift_per_m", &C::global_drift_per_m, closed(0.0, 1.0), "",
           "bound on the local SLAM's drift per metre driven where the scans pin the position down: a submap is searched widely once "
           "the drift bound since it exceeds loop_window_linear_m, in a window of that bound (at most global_window_linear_m)");
    t.real("unconstrained_drift_per_m", &C::unconstrained_drift_per_m, closed(0.0, 1.0), "",
           "... where a node's scan does not pin its position down (scan constraint below loop_min_constraint): the odometry's drift");
    t.integer("global_max_submaps", &C::global_max_submaps, closed(1, 100000), "", "submaps a wide search visits, nearest first");
    t.real("global_min_score", &C::global_min_score, closed(0.0, 1.0), "", "least mean likelihood of a wide search's closure");
    t.real("global_agreement_m", &C::global_agreement_m, closed(0.0, 100.0), "m",
           "of a node's wide closures, those implying a pose of it this near the best one's enter the graph, and none when one implying "
           "another pose scores loop_max_ambiguity of the best");
    t.real("global_agreement_deg", &C::global_agreement_rad, closed(0.0, 180.0), "deg", "... and this near in yaw", kPi / 180.0);
    t.integer("appearance_candidates", &C::appearance_candidates, closed(0, 1000), "",
              "a wide search also tries this many submaps beyond the ones it visits, where the node's Scan Context (" +
                  std::to_string(kScanContextRings) + " rings to loop_max_range_m, " + std::to_string(kScanContextSectors) +
                  " sectors) finds the place, in the local window around that place (0: none)");
    t.real("appearance_max_distance", &C::appearance_max_distance, closed(0.0, 1.0), "",
           "... the places whose Scan Context distance (one minus the sectors' mean cosine similarity) is at most this");
    t.real("loop_min_constraint", &C::loop_min_constraint, closed(0.0, 0.5), "",
           "least scan constraint (smallest eigenvalue of the normals' mean scatter) of a node that searches for closures");
    t.integer("search_depth", &C::search_depth, closed(0, 10), "", "levels of the branch and bound (blocks up to 2^depth cells)");
    t.integer("optimise_every_nodes", &C::optimise_every_nodes, closed(1, 100000), "",
              "the pose graph is optimised after this many nodes that brought closures");
    t.real("local_sigma_m", &C::local_sigma_m, closed(1e-6, 100.0), "m", "standard deviation of consecutive nodes' relative position");
    t.real("local_sigma_deg", &C::local_sigma_rad, closed(1e-6, 180.0), "deg", "... and of their relative yaw", kPi / 180.0);
    t.real("loop_sigma_m", &C::loop_sigma_m, closed(1e-6, 100.0), "m", "standard deviation of a closure's position");
    t.real("loop_sigma_deg", &C::loop_sigma_rad, closed(1e-6, 180.0), "deg", "... and of its yaw", kPi / 180.0);
    t.choice(
        "loop_loss", {"none", "huber", "cauchy"}, [](C& c, const std::string& v) { c.loop_loss = parse_robust_loss(v); },
        [](const C& c) { return robust_loss_name(c.loop_loss); }, "robust loss of closures' edges");
    t.real("loop_loss_scale", &C::loop_loss_scale, closed(1e-3, 1e6), "", "chi (in standard deviations) where the loss bends");
    t.integer("field_cache", &C::field_cache, closed(1, 100000), "",
              "submap likelihood fields kept built (at most " + std::to_string(kMaxFieldCacheBytes >> 30) +
                  " GiB of them; others are built again when searched)");
    return t;
  }();
  return table;
}

void GraphSlamConfig::validate() const {
  local.validate();
  require(submap_nodes >= 2, "submap_nodes", "must be at least 2");
  require(std::isfinite(loop_max_distance_m) && loop_max_distance_m >= 0, "loop_max_distance_m", "must be >= 0");
  require(std::isfinite(loop_window_linear_m) && loop_window_linear_m >= 0 && loop_window_linear_m <= 100, "loop_window_linear_m",
          "must be in [0, 100] m");
  require(std::isfinite(loop_window_angular_rad) && loop_window_angular_rad >= 0 && loop_window_angular_rad <= kPi,
          "loop_window_angular_deg", "must be in [0, 180] deg");
  require(loop_min_score > 0 && loop_min_score <= 1, "loop_min_score", "must be in (0, 1]");
  require(global_min_score > 0 && global_min_score <= 1, "global_min_score", "must be in (0, 1]");
  require(std::isfinite(loop_max_range_m) && loop_max_range_m > 0, "loop_max_range_m", "must be > 0");
  require(loop_every_nodes >= 1, "loop_every_nodes", "must be >= 1");
  require(global_every_nodes >= 0, "global_every_nodes", "must be >= 0");
  require(std::isfinite(global_window_linear_m) && global_window_linear_m >= 0 && global_window_linear_m <= 100,
          "global_window_linear_m", "must be in [0, 100] m");
  require(loop_min_constraint >= 0 && loop_min_constraint <= 0.5, "loop_min_constraint", "must be in [0, 0.5]");
  require(std::isfinite(global_drift_per_m) && global_drift_per_m >= 0, "global_drift_per_m", "must be >= 0");
  require(std::isfinite(unconstrained_drift_per_m) && unconstrained_drift_per_m >= 0, "unconstrained_drift_per_m", "must be >= 0");
  require(std::isfinite(loop_overlap_radius_m) && loop_overlap_radius_m > 0, "loop_overlap_radius_m", "must be > 0");
  require(loop_max_ambiguity >= 0 && loop_max_ambiguity <= 1, "loop_max_ambiguity", "must be in [0, 1]");
  require(loop_max_see_through >= 0 && loop_max_see_through <= 1, "loop_max_see_through", "must be in [0, 1]");
  require(std::isfinite(loop_see_through_margin_m) && loop_see_through_margin_m >= 0, "loop_see_through_margin_m", "must be >= 0");
  require(std::isfinite(loop_rival_distance_m) && loop_rival_distance_m > 0, "loop_rival_distance_m", "must be > 0");
  require(std::isfinite(loop_rival_angular_rad) && loop_rival_angular_rad >= 0 && loop_rival_angular_rad <= kPi, "loop_rival_angular_deg",
          "must be in [0, 180] deg");
  require(std::isfinite(loop_prior_drift_multiple) && loop_prior_drift_multiple >= 0, "loop_prior_drift_multiple", "must be >= 0");
  require(global_max_submaps >= 1, "global_max_submaps", "must be >= 1");
  require(appearance_candidates >= 0, "appearance_candidates", "must be >= 0");
  require(appearance_max_distance >= 0 && appearance_max_distance <= 1, "appearance_max_distance", "must be in [0, 1]");
  require(std::isfinite(global_agreement_m) && global_agreement_m >= 0, "global_agreement_m", "must be >= 0");
  require(std::isfinite(global_agreement_rad) && global_agreement_rad >= 0, "global_agreement_deg", "must be >= 0");
  require(search_depth >= 0 && search_depth <= 10, "search_depth", "must be in [0, 10]");
  require(optimise_every_nodes >= 1, "optimise_every_nodes", "must be >= 1");
  for (const auto& [v, field] : {std::pair{local_sigma_m, "local_sigma_m"}, {local_sigma_rad, "local_sigma_deg"},
                                 {loop_sigma_m, "loop_sigma_m"}, {loop_sigma_rad, "loop_sigma_deg"}, {loop_loss_scale, "loop_loss_scale"}})
    require(std::isfinite(v) && v > 0, field, "must be > 0");
  require(field_cache >= 1, "field_cache", "must be >= 1");
}

namespace {

// The matcher, checked before the local SLAM holds on to it.
std::unique_ptr<ScanMatcher> checked(std::unique_ptr<ScanMatcher> matcher) {
  if (!matcher) throw Error("graph SLAM needs a scan matcher", {}, 0, "matcher");
  if (!matcher->supports_reference())
    throw Error("scan matcher '" + std::string(matcher->name()) + "' prepares no reference, which graph SLAM's local map and submaps are", {},
                0, "matcher");
  return matcher;
}

}  // namespace

double drift_per_m(const GraphSlamConfig& config, double constraint) {
  return constraint >= config.loop_min_constraint ? config.global_drift_per_m : config.unconstrained_drift_per_m;
}

double rival_search_window_m(const GraphSlamConfig& config, double drift_bound_m) {
  return std::min(drift_bound_m, config.global_window_linear_m);
}

double closure_prior_weight(const GraphSlamConfig& config, double drift_bound_m) {
  if (config.loop_prior_drift_multiple <= 0) return 0.0;
  const double sigma = config.loop_prior_drift_multiple * std::max(drift_bound_m, kMinClosurePriorSigmaM);
  return 1.0 / (2.0 * sigma * sigma);
}

double global_search_window_m(const GraphSlamConfig& config, double drift_bound_m) {
  return drift_bound_m <= config.loop_window_linear_m ? 0.0 : std::min(drift_bound_m, config.global_window_linear_m);
}

std::vector<std::size_t> wide_closures_kept(const GraphSlamConfig& config, std::span<const Pose2> implied, std::span<const double> scores) {
  std::vector<std::size_t> kept;
  if (implied.empty()) return kept;
  const std::size_t best = static_cast<std::size_t>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  for (std::size_t i = 0; i < implied.size(); ++i) {
    const bool agrees = (implied[i].translation() - implied[best].translation()).norm() <= config.global_agreement_m &&
                        std::abs(angle_diff(implied[i].yaw, implied[best].yaw)) <= config.global_agreement_rad;
    if (agrees)
      kept.push_back(i);
    else if (config.loop_max_ambiguity < 1.0 && scores[i] >= config.loop_max_ambiguity * scores[best])
      return {};
  }
  return kept;
}

GraphSlam::GraphSlam(const GraphSlamConfig& config, std::unique_ptr<ScanMatcher> matcher)
    : c_(config), matcher_(checked(std::move(matcher))), local_(config.local, *matcher_),
      loop_schedule_(config.loop_every_nodes), global_schedule_(config.global_every_nodes) {
  c_.validate();
  // Every search this SLAM will run, judged by the matcher before anything is built: the local
  // window on the local map (points out to local.max_range_m), the closures' and the wide search's
  // on submaps (points out to loop_max_range_m).
  const std::string m = "local.matcher.";
  matcher_->check_search(matcher_->window(), c_.local.max_range_m, matcher_->window().linear_m, 2,
                         {m + "window_linear_m", m + "window_angular_deg", "local.max_range_m", m});
  matcher_->check_search(MatchWindow{c_.loop_window_linear_m, c_.loop_window_angular_rad}, c_.loop_max_range_m, 0.0, c_.search_depth,
                         {"loop_window_linear_m", "loop_window_angular_deg", "loop_max_range_m", m});
  if (c_.loop_max_ambiguity < 1.0)
    matcher_->check_search(MatchWindow{std::max(c_.loop_window_linear_m, c_.global_window_linear_m), c_.loop_window_angular_rad},
                           c_.loop_max_range_m, 0.0, c_.search_depth,
                           {"global_window_linear_m", "loop_window_angular_deg", "loop_max_range_m", m});
  if (c_.global_every_nodes > 0)
    matcher_->check_search(MatchWindow{c_.global_window_linear_m, kPi}, c_.loop_max_range_m, 0.0, c_.search_depth,
                           {"global_window_linear_m", "", "loop_max_range_m", m});
}

bool GraphSlam::on_scan(const ScanMessage& scan) {
  if (!odometry_) return false;  // nowhere to start from
  const Pose2& odometry = *odometry_;
  Pose2 mount = scan.mount.to_pose2();
  mount.yaw += 0.0;  // a level mount's yaw reads back from the quaternion as -0
  const std::int64_t stamp_us = microseconds_of(scan.header.t_s);
  const LocalSlamConfig& lc = c_.local;
  std::vector<Vec2> points;
  LocalSlam::Step step;
  {
    ScopedCpuTimer timer(stats_.local_cpu_s);
    points = scan_points(scan, lc.min_range_m, lc.max_range_m, lc.voxel_m);
    step = local_.add(points, odometry, mount, stamp_us);
  }
  stats_.matched += step.matched;
  stats_.unmatched += step.attempted && !step.matched;
  ScanPose sp{scan.header.t_s, stamp_us, nodes_.empty() ? std::nullopt : std::optional<std::size_t>(nodes_.size() - 1), step.pose};
  if (!step.node) {
    scans_.push_back(sp);
    return false;
  }
  const std::size_t n = nodes_.size();
  Node node;
  node.stamp_us = stamp_us;
  node.local = step.pose;
  node.global = n == 0 ? step.pose : nodes_[n - 1].global.compose(nodes_[n - 1].local.inverse().compose(step.pose));
  node.mount = mount;
  for (const Vec2& p : points)
    if (p.norm() <= c_.loop_max_range_m) node.points.push_back(p);
  node.constraint = scan_constraint(node.points);
  if (n > 0)
    node.drift_bound_m = nodes_[n - 1].drift_bound_m +
                         drift_per_m(c_, node.constraint) * (step.pose.translation() - nodes_[n - 1].local.translation()).norm();
  node.scan = scan;
  nodes_.push_back(std::move(node));
  sp.node = n;
  scans_.push_back(sp);
  if (n > 0) {
    const Pose2 z = nodes_[n - 1].local.inverse().compose(nodes_[n].local);
    edges_.push_back({n - 1, n, z, information(c_.local_sigma_m, c_.local_sigma_rad), RobustLoss::None, 1.0});
    graph_edges_.push_back({n - 1, n, SlamEdgeKind::Local, z, 0.0});
  }
  add_to_submaps(n);
  {
    ScopedCpuTimer timer(stats_.loop_cpu_s);
    search_closures(n);
  }
  ++nodes_since_optimise_;
  if (closures_since_optimise_ > 0 && nodes_since_optimise_ >= static_cast<std::size_t>(c_.optimise_every_nodes)) optimise();
  return true;
}

void GraphSlam::add_to_submaps(std::size_t n) {
  const std::size_t half = static_cast<std::size_t>(std::max(1, c_.submap_nodes / 2));
  if (n % half == 0) {
    submaps_.push_back({n, 0, {}, false});
  }
  const Node& node = nodes_[n];
  for (Submap& s : submaps_) {
    if (s.finished || n < s.first) continue;
    const Pose2 sensor = nodes_[s.first].local.inverse().compose(node.local).compose(node.mount);
    for (const Vec2& p : node.points) s.points.push_back(sensor.transform(p));
    if (++s.count >= static_cast<std::size_t>(c_.submap_nodes)) {
      s.finished = true;
      if (c_.appearance_candidates > 0 && c_.global_every_nodes > 0)
        for (std::size_t i = s.first; i < s.first + s.count; i += kScanContextNodeStep) {
          places_.add(scan_context(i));
          place_of_.emplace_back(static_cast<std::size_t>(&s - submaps_.data()), i);
        }
    }
  }
}

ScanContext GraphSlam::scan_context(std::size_t n) const {
  return ScanContext(nodes_[n].points, kScanContextRings, kScanContextSectors, c_.loop_max_range_m);
}

const GraphSlam::Submap* GraphSlam::own_submap(std::size_t n) const {
  // The node's submap with the most nodes (each node lies in two; the older holds at least half
  // a submap's), in whose frame the node's pose is its local SLAM's.
  const Submap* own = nullptr;
  for (const Submap& s : submaps_)
    if (n >= s.first && n < s.first + s.count && (!own || s.count > own->count)) own = &s;
  return own;
}

void GraphSlam::search_closures(std::size_t n) {
  const bool searchable = nodes_[n].points.size() >= 10 && nodes_[n].constraint >= c_.loop_min_constraint;
  const bool loop_due = loop_schedule_.due(n, searchable), global_due = global_schedule_.due(n, searchable);
  if (!loop_due && !global_due) return;
  const Vec2 at = nodes_[n].global.translation();
  // Submaps that ended at least a submap's length of nodes ago: nearer ones are tied by the local SLAM.
  std::vector<std::pair<std::size_t, double>> eligible;
  std::vector<char> unsearched(submaps_.size(), 0);  // eligible and not searched: what appearance may propose
  for (std::size_t s = 0; s < submaps_.size(); ++s) {
    const Submap& m = submaps_[s];
    if (!m.finished || m.first + m.count + static_cast<std::size_t>(c_.submap_nodes) > n) continue;
    unsearched[s] = 1;
    eligible.push_back({s, (nodes_[m.first + m.count / 2].global.translation() - at).norm()});
  }
  // The wide search is for a node whose estimate has lost the map: not one whose local search
  // found places that fit but refused them as ambiguous (the wide window holds the same rivals).
  bool found = false;
  Closure closure;
  if (loop_due)
    for (const auto& [s, d] : eligible) {
      if (d > c_.loop_max_distance_m) continue;
      unsearched[s] = 0;
      const SubmapMatch match = search_submap(n, s, 0.0, closure);
      if (match == SubmapMatch::Found) add_closure(n, closure, false);
      found = found || match != SubmapMatch::None;
    }
  if (!found && global_due) {
    std::stable_sort(eligible.begin(), eligible.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    int searched = 0;
    std::vector<Closure> wide;
    for (const auto& [s, d] : eligible) {
      const double window = global_search_window_m(c_, drift_bound_since(n, s));
      if (window > 0 && d <= c_.loop_max_distance_m + window && searched++ < c_.global_max_submaps) {
        unsearched[s] = 0;
        if (search_submap(n, s, window, closure) == SubmapMatch::Found) wide.push_back(closure);
      }
    }
    std::vector<Pose2> implied;
    std::vector<double> scores;
    for (const Closure& w : wide) {
      implied.push_back(nodes_[w.anchor].global.compose(w.z));
      scores.push_back(w.score);
    }
    const std::vector<std::size_t> kept = wide_closures_kept(c_, implied, scores);
    stats_.disagreeing_matches += wide.size() - kept.size();
    for (const std::size_t i : kept) add_closure(n, wide[i], true);
  }
  // Where the pose estimate has lost the map, the node's appearance proposes places; one waiting
  // for confirmation is looked for again on every search until a later node confirms or it lapses.
  if (pending_appearance_ && n > pending_appearance_->expires) pending_appearance_.reset();
  if (c_.appearance_candidates > 0 && ((!found && global_due) || (pending_appearance_ && loop_due))) {
    std::vector<Closure> seen;
    search_by_appearance(n, std::move(unsearched), seen);
    confirm_appearance(n, seen);
  }
}

void GraphSlam::confirm_appearance(std::size_t n, std::vector<Closure>& seen) {
  if (seen.empty()) return;
  std::stable_sort(seen.begin(), seen.end(), [](const Closure& a, const Closure& b) { return a.score > b.score; });
  if (pending_appearance_ && n >= pending_appearance_->node + kScanContextNodeStep) {
    // Both implied poses from their submaps' estimates now (an optimisation may have moved them
    // since the first look), the motion between the two nodes the local SLAM's.
    const PendingAppearance& p = *pending_appearance_;
    const ClosureLook first{nodes_[p.node].local, nodes_[p.closure.anchor].global.compose(p.closure.z), nodes_[p.node].drift_bound_m};
    for (const Closure& c : seen) {
      if (appearance_closures_agree(c_, first, {nodes_[n].local, nodes_[c.anchor].global.compose(c.z), nodes_[n].drift_bound_m})) {
        add_closure(p.node, p.closure, true);
        add_closure(n, c, true);
        pending_appearance_.reset();
        return;
      }
    }
  }
  // Unconfirmed (a building repeats its places: one lookalike fits as well as the place): the
  // best waits for a later node's look, kScanContextNodeStep nodes or more on (the next place the
  // index would hold: another scan, not the same one again).
  if (pending_appearance_ && pending_appearance_->node + kScanContextNodeStep > n) return;
  const Closure& best = seen.front();
  pending_appearance_ = PendingAppearance{n, best, n + 2 * static_cast<std::size_t>(c_.submap_nodes)};
}

SurfaceGrid GraphSlam::surface_grid(std::span<const Vec2> points) const {
  return SurfaceGrid(points, c_.loop_overlap_radius_m / 3.0, kSurfaceMinHits);
}

void GraphSlam::search_by_appearance(std::size_t n, std::vector<char> wanted, std::vector<Closure>& wide) {
  if (places_.size() == 0) return;
  const ScanContext query = scan_context(n);
  // The ring key only narrows the field: several times the candidates wanted are compared in
  // full, as Scan Context does.
  struct Proposal {
    double distance;
    std::size_t place;
    double yaw_rad;
  };
  std::vector<Proposal> proposals;
  for (const std::size_t i : places_.nearest(query, kScanContextLookups * static_cast<std::size_t>(c_.appearance_candidates))) {
    if (!wanted[place_of_[i].first]) continue;
    const ScanContextMatch m = compare_scan_contexts(query, places_.at(i));
    if (m.distance <= c_.appearance_max_distance) proposals.push_back({m.distance, i, m.yaw_rad});
  }
  std::stable_sort(proposals.begin(), proposals.end(), [](const Proposal& a, const Proposal& b) { return a.distance < b.distance; });
  int tried = 0;
  Closure closure;
  for (const Proposal& p : proposals) {
    if (tried >= c_.appearance_candidates) break;
    const auto [s, at] = place_of_[p.place];
    if (!wanted[s]) continue;  // one try per submap: its best place
    wanted[s] = 0;
    const Submap& m = submaps_[s];
    Pose2 guess = nodes_[m.first].local.inverse().compose(nodes_[at].local).compose(nodes_[at].mount);
    guess.yaw = wrap_angle(guess.yaw + p.yaw_rad);
    // A place farther from the estimate than the node can have drifted since the submap is a
    // repeat of the building, not the node's place.
    const Pose2 implied = nodes_[m.first].global.compose(guess).compose(nodes_[n].mount.inverse());
    if ((implied.translation() - nodes_[n].global.translation()).norm() > drift_bound_since(n, s) + c_.loop_window_linear_m) continue;
    ++tried;
    if (search_submap_at(n, s, guess, closure) == SubmapMatch::Found) {
      ++stats_.appearance_matches;
      wide.push_back(closure);
    }
  }
}

double GraphSlam::own_see_through(std::size_t n) {
  if (own_see_through_ && own_see_through_->first == n) return own_see_through_->second;
  const Submap* own = own_submap(n);
  double share = 0.0;
  if (own) {
    const Node& node = nodes_[n];
    const Pose2 sensor = nodes_[own->first].local.inverse().compose(node.local).compose(node.mount);
    share = see_through_share(node.points, sensor, surface_grid(own->points), c_.loop_see_through_margin_m);
  }
  own_see_through_ = {n, share};
  return share;
}

double GraphSlam::drift_bound_since(std::size_t n, std::size_t s) const {
  const Submap& m = submaps_[s];
  return nodes_[n].drift_bound_m - nodes_[m.first + m.count - 1].drift_bound_m;
}

GraphSlam::SubmapMatch GraphSlam::search_submap(std::size_t n, std::size_t s, double global_window_m, Closure& closure) {
  const bool global = global_window_m > 0;
  const Node& node = nodes_[n];
  const std::size_t anchor = submaps_[s].first;
  const Pose2 guess = nodes_[anchor].global.inverse().compose(node.global).compose(node.mount);
  const double prior = closure_prior_weight(c_, drift_bound_since(n, s));
  const MatchWindow window = global ? MatchWindow{global_window_m, kPi, c_.global_min_score, prior}
                                    : MatchWindow{c_.loop_window_linear_m, c_.loop_window_angular_rad, c_.loop_min_score, prior};
  ++(global ? stats_.global_searches : stats_.loop_searches);
  return match_submap(n, s, guess, window, closure);
}

GraphSlam::SubmapMatch GraphSlam::search_submap_at(std::size_t n, std::size_t s, const Pose2& guess, Closure& closure) {
  ++stats_.appearance_searches;
  const SubmapMatch match =
      match_submap(n, s, guess, MatchWindow{c_.loop_window_linear_m, c_.loop_window_angular_rad, c_.global_min_score, 0.0}, closure);
  closure.appearance = true;
  if (match != SubmapMatch::Found) return match;
  // The wide search's prior around the estimate, applied to where the match puts the node: a
  // lookalike metres farther than the node is likely to have drifted must fit that much better.
  const double shift_m = (nodes_[submaps_[s].first].global.compose(closure.z).translation() - nodes_[n].global.translation()).norm();
  if (closure.score * std::exp(-closure_prior_weight(c_, drift_bound_since(n, s)) * shift_m * shift_m) < c_.global_min_score)
    return SubmapMatch::None;
  return match;
}

GraphSlam::SubmapMatch GraphSlam::match_submap(std::size_t n, std::size_t s, const Pose2& guess, const MatchWindow& searched,
                                               Closure& closure) {
  const Node& node = nodes_[n];
  const std::size_t anchor = submaps_[s].first;
  if (submaps_[s].points.empty()) return SubmapMatch::None;  // its nodes saw nothing within loop_max_range_m
  const CachedField& cached = submap_field(s);
  const ScanReference& field = *cached.field;
  MatchWindow window = searched;
  if (c_.loop_max_ambiguity < 1.0) {
    // Rivals are looked for as far as the node may have drifted since the submap, beyond the
    // window searched when the drift reaches farther (a repeated room one step along the corridor
    // may be the true place), and not where it cannot have gone.
    window.rival_exclusion_m = c_.loop_rival_distance_m;
    window.rival_min_share = c_.loop_max_ambiguity;
    window.rival_angular_rad = c_.loop_rival_angular_rad;
    window.rival_linear_m = rival_search_window_m(c_, drift_bound_since(n, s));
  }
  const ScanMatch m = field.match(node.points, guess, window);
  if (!m.converged) return SubmapMatch::None;
  // Another place within reach fits (nearly) as well: the building repeats itself (rooms along a
  // corridor, the crossings of a grid) and the match cannot tell which place the scan is at.
  if (m.ambiguity >= c_.loop_max_ambiguity && c_.loop_max_ambiguity < 1.0) {
    ++stats_.ambiguous_matches;
    return SubmapMatch::Ambiguous;
  }
  // A scan that sees a junction matched onto a submap of the corridor before it scores well
  // anywhere along the corridor: the part of the scan the submap confirms must itself pin the
  // position down in every direction.
  if (scan_constraint(overlapping_points(node.points, m.transform, cached.points)) < c_.loop_min_constraint) {
    ++stats_.unconstrained_matches;
    return SubmapMatch::None;
  }
  // A crossing seen from its other side, matched one corridor's width off, fits the submap's
  // walls with the scan's points but looks through them with its rays.
  // Clutter, glass and people let some rays through wherever the scan is placed: what counts is
  // how much more it sees through the submap's surfaces than through its own submap's.
  if (c_.loop_max_see_through < 1.0 &&
      see_through_share(node.points, m.transform, cached.surfaces, c_.loop_see_through_margin_m) - own_see_through(n) >=
          c_.loop_max_see_through) {
    ++stats_.see_through_matches;
    return SubmapMatch::None;
  }
  closure = {anchor, m.transform.compose(node.mount.inverse()), m.score, false};
  return SubmapMatch::Found;
}

void GraphSlam::add_closure(std::size_t n, const Closure& closure, bool global) {
  edges_.push_back({closure.anchor, n, closure.z, information(c_.loop_sigma_m, c_.loop_sigma_rad), c_.loop_loss, c_.loop_loss_scale});
  graph_edges_.push_back({closure.anchor, n, global ? SlamEdgeKind::Global : SlamEdgeKind::Loop, closure.z, closure.score});
  ++(global ? stats_.global_closures : stats_.loop_closures);
  stats_.appearance_closures += closure.appearance;
  ++closures_since_optimise_;
}

bool appearance_closures_agree(const GraphSlamConfig& config, const ClosureLook& first, const ClosureLook& second) {
  const Pose2 carried = first.implied.compose(first.motion.inverse().compose(second.motion));
  const double tolerance_m = config.global_agreement_m + std::abs(second.drift_bound_m - first.drift_bound_m);
  return (second.implied.translation() - carried.translation()).norm() <= tolerance_m &&
         std::abs(angle_diff(second.implied.yaw, carried.yaw)) <= config.global_agreement_rad;
}

std::size_t cached_fields_kept(std::span<const std::size_t> bytes_newest_first, std::size_t max_fields, std::size_t max_bytes) {
  std::size_t bytes = 0, kept = 0;
  for (; kept < bytes_newest_first.size() && kept < max_fields; ++kept) {
    if (kept > 0 && bytes + bytes_newest_first[kept] > max_bytes) break;
    bytes += bytes_newest_first[kept];
  }
  return kept;
}

const GraphSlam::CachedField& GraphSlam::submap_field(std::size_t s) {
  for (auto it = cache_.begin(); it != cache_.end(); ++it)
    if (it->submap == s) {
      cache_.splice(cache_.begin(), cache_, it);
      return cache_.front();
    }
  cache_.push_front({s, matcher_->prepare(submaps_[s].points, 0.0, c_.search_depth),
                     PointNeighbourhood(submaps_[s].points, c_.loop_overlap_radius_m),
                     surface_grid(submaps_[s].points)});
  // At most field_cache fields and kMaxFieldCacheBytes of them (the newest always): an evicted
  // field is built again when asked for, the same.
  std::vector<std::size_t> sizes;
  sizes.reserve(cache_.size());
  for (const CachedField& f : cache_) sizes.push_back(f.field->bytes() + f.points.bytes() + f.surfaces.bytes());
  const std::size_t kept = cached_fields_kept(sizes, static_cast<std::size_t>(c_.field_cache), kMaxFieldCacheBytes);
  cache_.erase(std::next(cache_.begin(), static_cast<std::ptrdiff_t>(kept)), cache_.end());
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < kept; ++i) bytes += sizes[i];
  stats_.peak_field_bytes = std::max(stats_.peak_field_bytes, bytes);
  return cache_.front();
}

void GraphSlam::optimise() {
  ScopedCpuTimer timer(stats_.optimise_cpu_s);
  std::vector<Pose2> poses(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) poses[i] = nodes_[i].global;
  optimise_pose_graph(poses, edges_);
  for (std::size_t i = 0; i < nodes_.size(); ++i) nodes_[i].global = poses[i];
  ++stats_.optimisations;
  closures_since_optimise_ = 0;
  nodes_since_optimise_ = 0;
}

void GraphSlam::finish() {
  if (closures_since_optimise_ > 0) optimise();
}

std::vector<SlamPose> GraphSlam::trajectory() const {
  std::vector<SlamPose> out;
  if (nodes_.empty()) return out;
  out.reserve(scans_.size());
  for (const ScanPose& s : scans_) {
    const Node& node = nodes_[s.node.value_or(0)];
    const Pose2 base = node.global.compose(node.local.inverse().compose(s.local));
    const Pose2 sensor = base.compose(node.mount);
    Rigid3 t = Rigid3::Identity();
    t.linear() = Eigen::AngleAxisd(sensor.yaw, Vec3::UnitZ()).toRotationMatrix();
    t.translation() = Vec3(sensor.x, sensor.y, 0.0);
    out.push_back({s.t_s, s.stamp_us, base, t});
  }
  return out;
}

OccupancyGrid GraphSlam::map(const OccupancyMappingParams& params) const {
  OccupancyMapper mapper(params);
  for (const Node& node : nodes_) mapper.add_scan(node.global.compose(node.mount), node.scan);
  return mapper.grid();
}

SlamGraph GraphSlam::graph() const {
  SlamGraph g;
  for (const Node& node : nodes_) g.nodes.push_back({node.stamp_us, node.global});
  g.edges = graph_edges_;
  for (const Submap& s : submaps_) g.submap_anchors.push_back(s.first);
  return g;
}

std::vector<std::pair<std::string, double>> GraphSlam::statistics() const {
  const auto d = [](std::size_t v) { return static_cast<double>(v); };
  const GraphSlamStats& s = stats_;
  return {{"scans", d(scans_.size())},
          {"nodes", d(nodes_.size())},
          {"submaps", d(submaps_.size())},
          {"matched", d(s.matched)},
          {"unmatched", d(s.unmatched)},
          {"loop_searches", d(s.loop_searches)},
          {"loop_closures", d(s.loop_closures)},
          {"global_searches", d(s.global_searches)},
          {"global_closures", d(s.global_closures)},
          {"unconstrained_matches", d(s.unconstrained_matches)},
          {"ambiguous_matches", d(s.ambiguous_matches)},
          {"see_through_matches", d(s.see_through_matches)},
          {"appearance_searches", d(s.appearance_searches)},
          {"appearance_matches", d(s.appearance_matches)},
          {"appearance_closures", d(s.appearance_closures)},
          {"disagreeing_matches", d(s.disagreeing_matches)},
          {"optimisations", d(s.optimisations)},
          {"local_cpu_s", s.local_cpu_s},
          {"loop_cpu_s", s.loop_cpu_s},
          {"optimise_cpu_s", s.optimise_cpu_s},
          {"peak_field_mb", d(s.peak_field_bytes) / 1e6}};
}

std::vector<ParamSpec> graph_slam_specs() {
  std::vector<ParamSpec> specs = graph_slam_params().specs();
  std::vector<ParamSpec> matcher = correlative_matcher_params().specs(local_slam_matcher_config());
  for (ParamSpec& p : matcher) p.key = "local.matcher." + p.key;
  // After the local SLAM's own keys, where the matcher's settings belong.
  auto at = specs.begin();
  while (at != specs.end() && at->key.rfind("local.", 0) == 0) ++at;
  specs.insert(at, matcher.begin(), matcher.end());
  return specs;
}

SlamDef graph_slam() {
  SlamDef d;
  d.info.role = Role::Slam;
  d.info.name = "graph";
  d.info.section = "slam";
  d.info.summary = "Graph SLAM of Cartographer's design: local scan-to-map matching, submaps, branch-and-bound loop closure, "
                   "sparse pose-graph optimisation with robust losses";
  d.info.capabilities = {Capability::Planar};
  d.info.params = graph_slam_specs();
  d.make = [](const SlamContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Slam> {
    // `local.matcher.*` are the scan matcher's settings, after the local SLAM's defaults for it.
    std::vector<ParamSetting> own, matcher = local_slam_matcher_settings();
    for (const ParamSetting& s : settings) {
      if (s.key.rfind("local.matcher.", 0) == 0) {
        ParamSetting m = s;
        m.key = s.key.substr(std::string("local.matcher.").size());
        matcher.push_back(std::move(m));
      } else {
        own.push_back(s);
      }
    }
    matcher.insert(matcher.end(), ctx.matcher.settings.begin(), ctx.matcher.settings.end());
    const GraphSlamConfig config = configured(graph_slam_params(), own, ctx.file);
    try {
      config.validate();
    } catch (const Error& e) {
      rethrow_at_setting(e, own, ctx.file);
    }
    if (!ctx.make_scan_matcher) throw Error("no scan matcher factory to compose graph SLAM with", ctx.file, 0, ctx.matcher.field);
    SlamMatcherChoice choice = ctx.matcher;
    if (choice.name.empty()) choice.name = "correlative";
    choice.settings = std::move(matcher);
    std::unique_ptr<ScanMatcher> made = ctx.make_scan_matcher(choice);
    try {
      return std::make_unique<GraphSlam>(config, std::move(made));
    } catch (const Error& e) {
      // A search's cost names every parameter of its product: the error goes to its own field's
      // setting, else to the last setting it names.
      const bool own_field_set = std::any_of(settings.begin(), settings.end(), [&](const ParamSetting& v) { return v.key == e.field(); });
      if (!own_field_set)
        for (auto it = settings.rbegin(); it != settings.rend(); ++it)
          if (e.message().find(it->key + " ") != std::string::npos)
            throw Error(e.message(), it->file, it->line, it->field.empty() ? it->key : it->field);
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
