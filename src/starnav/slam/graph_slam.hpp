#pragma once
// Graph SLAM of Cartographer's design (Hess et al. 2016): the local SLAM (scan-to-local-map
// matching from odometry) makes nodes; consecutive nodes are grouped into submaps (rigid point
// sets in their first node's frame; each node lies in two overlapping submaps); each node is
// matched by branch and bound against the finished submaps near its estimate (loop closure, on
// every `loop_every_nodes`-th node, or the next one whose scan is constrained enough) and, at a
// lower rate, against the submaps the drift since them puts beyond the local window, in a window
// of that drift over the whole circle (global closures), and where the node's Scan Context finds
// its place among the older submaps the wide search does not reach (within the drift bound, in
// the local window around that place); the drift bound grows faster where the
// scans do not pin the position down (the odometry's rate). A match is kept only when no other pose
// within the drift bound's reach fits nearly as well (the building's repeats), the part of the
// scan its submap confirms pins the pose down, and its rays, placed by the match, see through the
// submap's surfaces no more than through the node's own submap's (a place seen from another
// side, one corridor's width off, fits the points but not the rays); of a node's wide closures only those agreeing with
// the best one enter the graph (none when a place elsewhere rivals it). The pose graph
// (consecutive nodes joined by the local SLAM's relative poses, loop closures under a robust loss)
// is optimised every `optimise_every_nodes` nodes that brought closures, and at the end. Scans
// between nodes keep their pose relative to the node before them.
//
// The front end (LocalSlam) and the back end (submaps, closures, pose graph) share one scan
// matcher, the ScanMatcher role injected by whoever builds the SLAM (the registry's factory picks
// `correlative` with the `local.matcher.*` settings); it must prepare references (the local map
// and each submap are one, the closures search them in windows of their own). Input through the
// Slam role: scans (ScanMessage, any stream the caller routes here) placed from the latest
// odometry; scans before the first odometry are not placed.
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <optional>
#include <utility>
#include <span>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/slam/local_slam.hpp"
#include "starnav/slam/pose_graph.hpp"
#include "starnav/slam/scan_context.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav {

// The most bytes of submap likelihood fields kept built at once, whatever field_cache says (the
// newest field always is): a fine resolution's fields are built again when searched instead of
// filling the memory.
inline constexpr std::size_t kMaxFieldCacheBytes = std::size_t{1} << 30;

// How many of the cached fields, newest first with these sizes, stay built: at most `max_fields`,
// and no more bytes than `max_bytes` except that the newest always stays.
std::size_t cached_fields_kept(std::span<const std::size_t> bytes_newest_first, std::size_t max_fields, std::size_t max_bytes);

// A point set binned in square cells `radius_m` wide, to ask whether a position lies within
// radius_m of one of its points.
class PointNeighbourhood {
 public:
  PointNeighbourhood(std::span<const Vec2> points, double radius_m);
  bool near(const Vec2& position) const;
  std::size_t bytes() const { return keys_.capacity() * sizeof(std::uint64_t) + points_.capacity() * sizeof(Vec2); }

 private:
  std::uint64_t key(std::int64_t cell_x, std::int64_t cell_y) const;
  std::int64_t cell(double v) const;
  double radius_m_;
  std::vector<std::uint64_t> keys_;  // sorted; points_ in the same order
  std::vector<Vec2> points_;
};

// A point set rasterised in square cells `cell_m` wide (wider when the points' extent would need
// more than kMaxSurfaceGridCells): the cells holding at least `min_hits` of its points are the
// surfaces the points were measured on (a wall seen from a submap's nodes holds many; a stray
// return, one).
inline constexpr std::size_t kMaxSurfaceGridCells = std::size_t{1} << 24;
class SurfaceGrid {
 public:
  SurfaceGrid(std::span<const Vec2> points, double cell_m, int min_hits);
  // Whether the segment from `from` towards `to` passes through a surface cell within `stop_m`
  // along it (every cell it passes through, exactly; the cell holding `from` itself is not
  // counted: the sensor stands there).
  bool crosses_surface(const Vec2& from, const Vec2& to, double stop_m) const;
  std::size_t bytes() const { return occupied_.capacity(); }

 private:
  bool occupied(std::int64_t cx, std::int64_t cy) const;
  std::int64_t cell(double v) const;
  double cell_m_;
  int min_hits_;
  std::int64_t min_x_ = 0, min_y_ = 0, width_ = 0, height_ = 0;
  std::vector<std::uint8_t> occupied_;  // points per cell, at most 255
};

// The points a submap's cell must hold to be a surface of the see-through check.
inline constexpr int kSurfaceMinHits = 3;

// The share of a scan's rays that pass through a surface of `surfaces` more than `margin_m` before
// their end when the scan (points in the sensor frame) is placed at `pose` in the surfaces' frame:
// rays that see through a wall the reference measured. A scan placed where it was taken sees
// through little (what has moved: a door opened, a person gone; thin things the reference saw from
// elsewhere: chairs' legs); placed one corridor's width off, its rays cross the walls the
// reference saw from the other side.
double see_through_share(std::span<const Vec2> scan, const Pose2& pose, const SurfaceGrid& surfaces, double margin_m);

// The Scan Context the wide search's appearance proposer describes places with: rings of
// loop_max_range_m / kScanContextRings (0.75 m at 15 m: coarser than a metre of drift moves a
// wall, finer than a room), sectors of 6 degrees; a finished submap's every
// kScanContextNodeStep-th node is a place (a node a few nodes on sees nearly the same scene, and
// is the next look that may confirm a match); kScanContextLookups x the
// candidates wanted are taken from the ring keys' k-d tree and compared in full.
inline constexpr int kScanContextRings = 20;
inline constexpr int kScanContextSectors = 60;
inline constexpr std::size_t kScanContextNodeStep = 4;
inline constexpr std::size_t kScanContextLookups = 8;

// When closure searches run: one falls due on every `every`-th node (0: never) and, when that node
// is too poorly constrained to search from, is owed to the next node that is. In a featureless
// corridor the due node rarely is, and a search dropped there is a loop that never closes.
class ClosureSchedule {
 public:
  explicit ClosureSchedule(int every) : every_(every) {}
  // Whether node `n` (nodes come in order) searches; `searchable`: it is constrained enough.
  bool due(std::size_t n, bool searchable) {
    owed_ = owed_ || (every_ > 0 && n % static_cast<std::size_t>(every_) == 0);
    if (!owed_ || !searchable) return false;
    owed_ = false;
    return true;
  }

 private:
  int every_;
  bool owed_ = false;
};

struct GraphSlamConfig {
  LocalSlamConfig local;
  int submap_nodes = 40;                  // nodes per submap (a new one starts every half)
  double loop_max_distance_m = 8.0;       // submaps whose middle lies this near the node's estimate are searched
  double loop_window_linear_m = 2.0;      // +- x, y around the estimate
  double loop_window_angular_rad = 0.349; // +- yaw (20 deg)
  double loop_min_score = 0.55;           // least mean likelihood of a closure
  double loop_max_range_m = 15.0;         // scan points used for closures
  int loop_every_nodes = 2;               // search on every n-th node
  int global_every_nodes = 100;           // a wide search on every n-th node that found no closure
  double global_window_linear_m = 8.0;    // the most +- x, y of the wide search (yaw: the whole circle)
  double global_drift_per_m = 0.02;       // bound on the local SLAM's drift per metre driven
  double unconstrained_drift_per_m = 0.02; // ... where the scans do not pin the position down
  double global_min_score = 0.75;
  int global_max_submaps = 8;             // the wide search visits at most this many submaps, nearest first
  double global_agreement_m = 0.5;        // a node's wide closures that imply a pose of it this near the best one's agree
  double global_agreement_rad = 0.0523599;  // ... and this near in yaw (3 deg)
  int appearance_candidates = 3;          // submaps beyond the wide search a wide search also tries where Scan Context proposes (0: none)
  double appearance_max_distance = 0.5;   // ... those whose Scan Context distance to the node's is at most this
  double loop_min_constraint = 0.2;       // least scan_constraint of a node that searches for closures
                                          // and of the part of its scan a closure's submap confirms
  double loop_overlap_radius_m = 0.15;    // a scan point within this of a submap point is confirmed
  double loop_max_ambiguity = 1.0;        // a closure whose best rival (see below) scores this share of it is refused (1: never)
  double loop_rival_distance_m = 1.0;     // rivals: poses at least this far from the match
  double loop_rival_angular_rad = 0.0873; // ... and within this of its yaw (5 deg)
  double loop_prior_drift_multiple = 1.0; // closures' scores weighed by a prior around the estimate, sigma this x the drift bound (0: none)
  double loop_max_see_through = 0.08;     // a closure whose scan sees through this share more of its submap's surfaces
                                          // than of its own submap's is refused (1: never)
  double loop_see_through_margin_m = 1.0; // ... a ray sees through a surface it crosses this far before its end
  int search_depth = 7;                   // levels of the branch and bound (blocks up to 2^depth cells)
  int optimise_every_nodes = 40;
  double local_sigma_m = 0.02, local_sigma_rad = 0.0087;  // consecutive nodes' edges
  double loop_sigma_m = 0.05, loop_sigma_rad = 0.0175;    // closures' edges
  RobustLoss loop_loss = RobustLoss::Cauchy;
  double loop_loss_scale = 2.0;           // chi where the loss bends
  int field_cache = 48;                   // submap fields kept built (at most kMaxFieldCacheBytes of them)
  void validate() const;
};

// How fast the local SLAM's position may drift, per metre driven, where a node's scan has
// `constraint` (scan_constraint): global_drift_per_m where the scan pins the position down
// (loop_min_constraint or more), unconstrained_drift_per_m (the odometry's) where it does not (a
// featureless corridor, where matching keeps the odometry's slide along it).
double drift_per_m(const GraphSlamConfig& config, double constraint);
// The wide search's window (+- x, y) for a submap whose drift bound (the sum of drift_per_m x the
// distance driven, from the submap's last node to the node searching) is `drift_bound_m`: the
// bound, at most global_window_linear_m; 0 (no wide search) while the bound is within the local
// search's loop_window_linear_m, which already covers it (a wider window there only adds the
// corridor's repeats: a room's width along it, a junction's).
double global_search_window_m(const GraphSlamConfig& config, double drift_bound_m);
// How far from the guess a closure's rivals are looked for: the drift bound, at most
// global_window_linear_m.
double rival_search_window_m(const GraphSlamConfig& config, double drift_bound_m);
// The weight (1/m^2) of the prior a closure search's lattice scores (local and wide) are
// multiplied by, exp(-w d^2) for a shift d from the graph's estimate: a Gaussian of sigma
// loop_prior_drift_multiple x the drift bound since the submap (at least kMinClosurePriorSigmaM),
// 0 when the multiple is 0. The estimate is where the node most likely is: a pose metres from it
// (a crossing seen from its other side, one corridor's width on) must fit clearly better than the
// estimate's surroundings to win, the more so the less the node can have drifted.
inline constexpr double kMinClosurePriorSigmaM = 0.1;
double closure_prior_weight(const GraphSlamConfig& config, double drift_bound_m);
// Which of one node's wide closures enter the graph: `implied` holds the node's pose each implies
// (its submap's estimate composed with the match), `scores` their scores. Those implying the best
// one's pose (within global_agreement_m and global_agreement_rad; the first of equal scores), in
// order; none when a closure implying another pose scores loop_max_ambiguity of the best or more:
// the scan then fits two places of the building in different submaps (a repeat of its place in
// one, the place itself in another), which the rival search within one submap cannot see.
std::vector<std::size_t> wide_closures_kept(const GraphSlamConfig& config, std::span<const Pose2> implied, std::span<const double> scores);
const ParamTable<GraphSlamConfig>& graph_slam_params();

// Two nodes' appearance closures agree when the first's implied pose, carried to the second node
// by the motion between them, lies within global_agreement_m (plus the drift bound
// accumulated between the two) and global_agreement_rad of the second's implied pose: both
// correct the estimate the same way, as two looks at one place do and a lookalike seldom does.
struct ClosureLook {
  Pose2 motion;           // the node's pose in a frame both nodes' are known in (the local SLAM's): the motion between them counts
  Pose2 implied;          // the node's pose the closure implies
  double drift_bound_m;   // the node's drift bound (accumulated from the first node)
};
bool appearance_closures_agree(const GraphSlamConfig& config, const ClosureLook& first, const ClosureLook& second);

// Counters of a run (scans, nodes and submaps are the run's own sizes: statistics()).
struct GraphSlamStats {
  std::size_t matched = 0, unmatched = 0;  // the local matcher's scans
  std::size_t loop_searches = 0, loop_closures = 0, global_searches = 0, global_closures = 0;
  std::size_t unconstrained_matches = 0;  // matches refused: their overlap pins no position down
  std::size_t ambiguous_matches = 0;      // matches refused: another place in reach fits almost as well
  std::size_t see_through_matches = 0;    // matches refused: the scan sees through the submap's surfaces
  // Where Scan Context proposed: searches, matches found, and closures (confirmed matches) entered.
  std::size_t appearance_searches = 0, appearance_matches = 0, appearance_closures = 0;
  std::size_t disagreeing_matches = 0;    // wide matches refused: another pose than the best one's, or the best one's rivalled
  std::size_t optimisations = 0;
  double local_cpu_s = 0.0, loop_cpu_s = 0.0, optimise_cpu_s = 0.0;
  std::size_t peak_field_bytes = 0;  // the submap fields held at once
};

class GraphSlam final : public Slam {
 public:
  GraphSlam(const GraphSlamConfig& config, std::unique_ptr<ScanMatcher> matcher);
  std::string_view name() const override { return "graph"; }
  SlamSpace space() const override { return SlamSpace::Planar; }
  void on_odometry(const OdometryMessage& odometry) override { odometry_ = odometry.pose; }
  bool on_scan(const ScanMessage& scan) override;
  void finish() override;
  std::vector<SlamPose> trajectory() const override;
  OccupancyGrid map(const OccupancyMappingParams& params) const override;
  SlamGraph graph() const override;
  std::vector<std::pair<std::string, double>> statistics() const override;
  const GraphSlamStats& stats() const { return stats_; }

 private:
  struct Node {
    std::int64_t stamp_us = 0;
    Pose2 local, global;
    Pose2 mount;
    std::vector<Vec2> points;  // sensor frame, for closures (range-limited)
    double constraint = 0.0;   // scan_constraint(points)
    double drift_bound_m = 0.0;  // drift_per_m x distance, summed along the local SLAM's path from the first node
    ScanMessage scan;          // for the map
  };
  struct Submap {
    std::size_t first = 0, count = 0;  // node indices [first, first + count)
    std::vector<Vec2> points;          // in the first node's base frame
    bool finished = false;
  };
  struct ScanPose {
    double t_s = 0.0;
    std::int64_t stamp_us = 0;
    std::optional<std::size_t> node;  // the node before it (none: before the first node)
    Pose2 local;
  };
  struct CachedField {
    std::size_t submap = 0;
    std::unique_ptr<ScanReference> field;
    PointNeighbourhood points;  // the submap's, for the closure check
    SurfaceGrid surfaces;       // ... and for the see-through check
  };
  void add_to_submaps(std::size_t node);
  void search_closures(std::size_t node);
  enum class SubmapMatch { None, Found, Ambiguous };
  struct Closure {
    std::size_t anchor = 0;  // the submap's first node
    Pose2 z;                 // the node's base in the anchor's
    double score = 0.0;
    bool appearance = false;  // where Scan Context proposed
  };
  // `global_window_m` > 0: the wide search in that window (+- x, y; the whole circle). A match
  // found is left in `closure`.
  SubmapMatch search_submap(std::size_t node, std::size_t submap, double global_window_m, Closure& closure);
  // The search around `guess` (the node's sensor in the submap's frame, where Scan Context places
  // it) in the local window, with the wide search's least score and no prior around the estimate.
  SubmapMatch search_submap_at(std::size_t node, std::size_t submap, const Pose2& guess, Closure& closure);
  SubmapMatch match_submap(std::size_t node, std::size_t submap, const Pose2& guess, const MatchWindow& window, Closure& closure);
  // Closures proposed by Scan Context in the submaps `wanted` marks (eligible, not searched by
  // this node's other searches), verified by the matcher; appended to `wide`.
  void search_by_appearance(std::size_t node, std::vector<char> wanted, std::vector<Closure>& wide);
  // Appearance closures enter the graph in pairs: one node's best match waits (pending) until a
  // later node's match agrees with it (the same correction of the estimate), and both enter.
  void confirm_appearance(std::size_t node, std::vector<Closure>& seen);
  struct PendingAppearance {
    std::size_t node = 0;
    Closure closure;
    std::size_t expires = 0;   // the last node that may confirm it
  };
  std::optional<PendingAppearance> pending_appearance_;
  // The Scan Context of `node`'s scan (its points out to loop_max_range_m). Measured against the
  // whole submap around the node, which sees all around where the laser sees half: that found
  // the building's repeats and not the place (docs/slam.md).
  ScanContext scan_context(std::size_t node) const;
  const Submap* own_submap(std::size_t node) const;
  void add_closure(std::size_t node, const Closure& closure, bool global);
  // A submap's surfaces for the see-through check: cells a third of loop_overlap_radius_m,
  // kSurfaceMinHits points each (the same for the submap searched and the node's own).
  SurfaceGrid surface_grid(std::span<const Vec2> points) const;
  // The share of `node`'s rays that see through its own submap's surfaces where the local SLAM
  // placed it (see_through_share): the scan's own level of clutter, glass and moving people.
  double own_see_through(std::size_t node);
  // The drift bound accumulated from submap `submap`'s last node to `node`.
  double drift_bound_since(std::size_t node, std::size_t submap) const;
  const CachedField& submap_field(std::size_t submap);
  void optimise();

  GraphSlamConfig c_;
  std::unique_ptr<ScanMatcher> matcher_;
  LocalSlam local_;
  std::optional<Pose2> odometry_;  // the latest
  std::vector<Node> nodes_;
  std::vector<Submap> submaps_;
  std::vector<ScanPose> scans_;
  std::vector<PoseGraphEdge> edges_;
  std::vector<SlamGraphEdge> graph_edges_;
  std::list<CachedField> cache_;  // most recent first
  ScanContextIndex places_;                                // of finished submaps' nodes
  std::vector<std::pair<std::size_t, std::size_t>> place_of_;  // per description: (submap, node)
  std::optional<std::pair<std::size_t, double>> own_see_through_;  // the last node's
  std::size_t closures_since_optimise_ = 0, nodes_since_optimise_ = 0;
  ClosureSchedule loop_schedule_, global_schedule_;
  GraphSlamStats stats_;
};

// How well a scan pins a pose down in every direction: the smallest eigenvalue of the mean of
// n n^T over its points' normals (each from its neighbours in beam order), in [0, 0.5]: 0.5 for
// normals spread evenly, near 0 for a corridor's two parallel walls, which leave the position
// along the corridor free (the closures such scans would make slide along it).
double scan_constraint(std::span<const Vec2> points);

// The points of `scan` (its order kept) that land near a point of `reference` when the scan is
// placed at `pose` in the reference's frame: the part of a match the reference confirms.
std::vector<Vec2> overlapping_points(std::span<const Vec2> scan, const Pose2& pose, const PointNeighbourhood& reference);

// The declared parameters of the `graph` component: graph_slam_params() with the matcher's under
// `local.matcher.` (their defaults the local SLAM's: local_slam_matcher_settings()).
std::vector<ParamSpec> graph_slam_specs();

SlamDef graph_slam();

}  // namespace starnav
