#pragma once
// The scan-matcher role: the rigid transform that best lays one 2D scan onto another scan (or
// onto a map), with a score; the 3D registrations (ICP, GICP, NDT) have their own 3D twin
// (cloud/scan_matcher_3d.hpp). Points are in each scan's sensor frame; the transform maps `scan`
// into `reference`'s frame: reference_point ~= transform * scan_point.
//
// A SLAM front end matches many scans against one local map, and its back end many nodes against
// one submap, each time in a search window of its own: a matcher that supports it prepares a
// reference once (prepare: the correlative matcher's likelihood field with its branch-and-bound
// levels) and matches against it as often as asked (ScanReference::match, in the matcher's
// configured window or in one the caller gives). supports_reference() says whether a matcher can;
// graph SLAM needs one that can.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "starnav/core/angle.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

struct ScanMatch {
  bool converged = false;
  Pose2 transform;                                        // scan frame -> reference frame
  double score = 0.0;                                     // matcher-defined; documented by each matcher
  double rms_m = 0.0;                                     // RMS distance of matched points (m)
  int iterations = 0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of (x, y, yaw), when the matcher gives one
  // When the window asks for it (rival_exclusion_m > 0) and the matcher can: the best score of a
  // pose at least rival_exclusion_m from this match, over this match's, both on the search's own
  // lattice (0..1, 1 also when a rival outside the window searched scores higher; 0 when no other
  // pose reaches min_score or the window's rival_min_share of this match's score). Near 1: another
  // place fits as well
  // (a repeated room along a corridor), so the match says little about where the scan is.
  double ambiguity = 0.0;
};

// A search window around a guess: +- linear_m in x and y, +- angular_rad in yaw; poses scoring
// below min_score are not searched for (they prune the search from the start) and a match below it
// has not converged; an optional prior pulls toward the guess (the correlative matcher's weights).
struct MatchWindow {
  double linear_m = 0.3;
  double angular_rad = 0.349;
  double min_score = 0.0;
  double prior_linear_weight = 0.0, prior_angular_weight = 0.0;  // 1/m^2, 1/rad^2
  // The rival search behind ScanMatch::ambiguity (0: none): poses farther than rival_exclusion_m
  // from the match, within +- rival_linear_m of the guess (inside or beyond linear_m), their yaw
  // within +- rival_angular_rad of the match's and within the window's; rivals scoring below
  // rival_min_share of the match are not looked for (they prune the search).
  double rival_exclusion_m = 0.0, rival_linear_m = 0.0, rival_angular_rad = kPi, rival_min_share = 0.0;
};

// How the parameters of one search are named where they are set, for its errors (graph SLAM's
// local window: local.matcher.window_linear_m; a closure's: loop_window_linear_m).
struct SearchNames {
  std::string linear;   // the window's +- x, y
  std::string angular;  // its +- yaw ("": the whole circle)
  std::string reach;    // what bounds the points' range from the sensor
  std::string matcher;  // the prefix of the matcher's own keys ("local.matcher.")
};

// A reference prepared once for many matches (a local map, a submap), in the matcher's own form.
class ScanReference {
 public:
  virtual ~ScanReference() = default;
  // `scan` (sensor frame) onto the reference from `guess`, in the matcher's configured window.
  virtual ScanMatch match(std::span<const Vec2> scan, const Pose2& guess) const = 0;
  // ... in `window` instead.
  virtual ScanMatch match(std::span<const Vec2> scan, const Pose2& guess, const MatchWindow& window) const = 0;
  // Memory held (bytes).
  virtual std::size_t bytes() const = 0;
};

class ScanMatcher {
 public:
  virtual ~ScanMatcher() = default;
  virtual std::string_view name() const = 0;
  // `scan` onto `reference`, starting from `guess`.
  virtual ScanMatch match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) = 0;
  // `scan` (sensor frame) onto an occupancy map, starting from `guess` (the sensor's pose in the
  // map frame); the result's transform is the sensor's pose in the map frame. Matchers that
  // cannot match against a map say so: supports_map() false, and match_to_map throws Error.
  virtual bool supports_map() const { return false; }
  virtual ScanMatch match_to_map(const OccupancyGrid& map, std::span<const Vec2> scan, const Pose2& guess);

  // Prepared references (above). `points` (one frame) are prepared for scans laid up to
  // `search_margin_m` beyond them (the widest window the caller will search, besides the
  // matcher's own reach); `search_depth` the levels of precomputed bounds for wide searches
  // (matchers without levels ignore it). Matchers without prepared references: supports_reference()
  // false, and prepare throws Error.
  virtual bool supports_reference() const { return false; }
  virtual std::unique_ptr<ScanReference> prepare(std::span<const Vec2> points, double search_margin_m, int search_depth) const;
  // The configured search window (a matcher without one: all zero, it refines from the guess).
  virtual MatchWindow window() const { return {0.0, 0.0, 0.0, 0.0, 0.0}; }
  // Before any reference is prepared: throws Error (field `names.linear` or `names.reach`, the
  // message naming every parameter of the product) when searches of `window` over points out to
  // `reach_m` from the sensor, on references prepared with `search_margin_m` and `search_depth`,
  // would take more memory than the matcher's limits; a matcher without such costs accepts any.
  virtual void check_search(const MatchWindow& /*window*/, double /*reach_m*/, double /*search_margin_m*/, int /*search_depth*/,
                            const SearchNames& /*names*/) const {}
};

struct ScanMatcherContext {
  std::string file;
};
using ScanMatcherDef = ComponentDef<ScanMatcher, ScanMatcherContext>;

}  // namespace starnav
