#pragma once
// Correlative scan matching (Olson 2009, "Real-time correlative scan matching"): the scan is
// scored against a likelihood field of the reference (each cell exp(-d^2 / 2 sigma^2), d the
// distance to the nearest reference point or occupied cell), at every pose of a search window
// around the guess (translations on the field's cells, rotations in steps that move the farthest
// point by at most one cell), exhaustively by branch and bound (Hess et al. 2016): fields of
// blocks 2, 4, ... 2^depth cells wide hold the maximum of the fine cells a block of translations
// can reach, so whole blocks of the window are dropped when their bound falls below the best
// score found, without changing the answer. The best pose is then refined off the lattice by
// Gauss-Newton on the bicubically interpolated field. Local matching searches a small window
// (depth 2); loop closure searches metres and the whole circle (depth up to 7).
//
// Score: the mean field value over the scan's points, 0..1 (1: every point on the reference).
// Converged when the best score reaches min_score. The covariance (with refinement) is the
// Gauss-Newton estimate: the inverse of J'J times the residuals' variance. rms_m is the RMS
// distance of the points the field sees (value above 1e-3), read back from the field, so it
// measures to reference cell centres: below one cell for a perfect match.
#include <cstdint>
#include <memory>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/params.hpp"
#include "starnav/slam/scan_matcher.hpp"

namespace starnav {

// The most cells of one likelihood field (2^24): a cell takes about 50 bytes while the field is
// built (the distance transform, each cell's nearest point) and 4 + depth bytes kept.
inline constexpr std::int64_t kMaxCorrelativeFieldCells = std::int64_t{1} << 24;
// The most entries of one search's tables (2^24): the candidates at the top of its branch and
// bound (angles x translation blocks, 24 bytes each) and the scan's points turned to every angle
// (angles x points, 8 bytes each).
inline constexpr std::int64_t kMaxCorrelativeSearchEntries = std::int64_t{1} << 24;

struct CorrelativeMatcherConfig {
  double resolution_m = 0.05;         // cell of the likelihood field and translation step
  double sigma_m = 0.05;              // spread of the likelihood around each reference point
  double window_linear_m = 0.3;       // search +- this in x and in y around the guess
  double window_angular_rad = deg_to_rad(20.0);  // +- this in yaw
  double min_score = 0.3;             // below: not converged
  bool refine = true;                 // Gauss-Newton after the lattice search
  // A prior around the guess (0: none): lattice scores times exp(-(wl d^2 + wa dyaw^2)), and
  // n (wl d^2 + wa dyaw^2) added to the refinement's cost, so that a scan that fits equally well
  // anywhere along a corridor stays where the odometry put it.
  double prior_linear_weight = 0.0;   // 1/m^2 (local SLAM: 10)
  double prior_angular_weight = 0.0;  // 1/rad^2
  void validate() const;
};

const ParamTable<CorrelativeMatcherConfig>& correlative_matcher_params();

class CorrelativeScanMatcher final : public ScanMatcher {
 public:
  explicit CorrelativeScanMatcher(const CorrelativeMatcherConfig& config = {});
  std::string_view name() const override { return "correlative"; }
  ScanMatch match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) override;
  bool supports_map() const override { return true; }
  ScanMatch match_to_map(const OccupancyGrid& map, std::span<const Vec2> scan, const Pose2& guess) override;
  // A reference is the likelihood field of its points over their bounds widened by 3 sigma, a
  // cell and the search margin; match(scan, guess) on it is match_to_field in the configured window.
  bool supports_reference() const override { return true; }
  std::unique_ptr<ScanReference> prepare(std::span<const Vec2> points, double search_margin_m, int search_depth) const override;
  MatchWindow window() const override;
  // The field of one scan's points all round (reach plus the margins, over resolution_m, squared)
  // against kMaxCorrelativeFieldCells; the search's top candidates (its angles, in Olson's steps
  // for the farthest point, times the blocks of its translations) against
  // kMaxCorrelativeSearchEntries.
  void check_search(const MatchWindow& window, double reach_m, double search_margin_m, int search_depth,
                    const SearchNames& names) const override;

  // The likelihood field of occupied cells (or points), for reuse across matches against one map.
  struct Field {
    double resolution = 0.0;
    Vec2 origin{0, 0};  // world position of cell (0, 0)'s corner
    int width = 0, height = 0;
    std::vector<float> fine;  // width x height
    // bounds[k - 1]: for blocks 2^k cells wide, the maximum of the fine cells over
    // [x, x + 2^k) x [y, y + 2^k), x and y from -(2^k - 1) (padded), rounded up to 1/255.
    std::vector<std::vector<std::uint8_t>> bounds;
    double value(const Vec2& world) const;  // bicubic (Catmull-Rom), 0 outside
    int depth() const { return static_cast<int>(bounds.size()); }
    std::size_t bytes() const;
  };
  // `depth`: the levels of bounds (2: enough for the local window; more for wide searches).
  Field field_of_points(std::span<const Vec2> points, const Vec2& lo, const Vec2& hi, int depth = 2) const;
  Field field_of_map(const OccupancyGrid& map, int depth = 2) const;
  // The configured window and min_score.
  ScanMatch match_to_field(const Field& field, std::span<const Vec2> scan, const Pose2& guess) const;
  ScanMatch match_to_field(const Field& field, std::span<const Vec2> scan, const Pose2& guess, const MatchWindow& window) const;

 private:
  CorrelativeMatcherConfig c_;
};

ScanMatcherDef correlative_scan_matcher();

}  // namespace starnav
