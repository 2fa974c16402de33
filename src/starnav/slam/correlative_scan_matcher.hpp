#pragma once
// Correlative scan matching (Olson 2009, "Real-time correlative scan matching"): the scan is
// scored against a likelihood field of the reference (each cell exp(-d^2 / 2 sigma^2), d the
// distance to the nearest reference point or occupied cell), at every pose of a search window
// around the guess (translations on the field's cells, rotations in steps that move the farthest
// point by at most one cell), exhaustively and in two resolutions: a coarse field of cells 4x
// larger whose values bound the fine ones from above (max over the cells they cover) prunes the
// window as Cartographer's branch and bound does, without changing the answer. The best pose is
// then refined off the lattice by Gauss-Newton on the bilinearly interpolated field.
//
// Score: the mean field value over the scan's points, 0..1 (1: every point on the reference).
// Converged when the best score reaches min_score. The covariance (with refinement) is the
// Gauss-Newton estimate: the inverse of J'J times the residuals' variance. rms_m is the RMS
// distance of the points the field sees (value above 1e-3), read back from the field, so it
// measures to reference cell centres: below one cell for a perfect match.
#include <memory>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/params.hpp"
#include "starnav/slam/scan_matcher.hpp"

namespace starnav {

struct CorrelativeMatcherConfig {
  double resolution_m = 0.05;         // cell of the likelihood field and translation step
  double sigma_m = 0.05;              // spread of the likelihood around each reference point
  double window_linear_m = 0.3;       // search +- this in x and in y around the guess
  double window_angular_rad = deg_to_rad(20.0);  // +- this in yaw
  double min_score = 0.3;             // below: not converged
  bool refine = true;                 // Gauss-Newton after the lattice search
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

  // The likelihood field of occupied cells (or points), for reuse across matches against one map.
  struct Field {
    double resolution = 0.0;
    Vec2 origin{0, 0};  // world position of cell (0, 0)'s corner
    int width = 0, height = 0;
    std::vector<float> fine;    // width x height
    std::vector<float> coarse;  // ceil(width/4) x ceil(height/4): max of the fine cells covered
    double value(const Vec2& world) const;  // bilinear, 0 outside
  };
  Field field_of_points(std::span<const Vec2> points, const Vec2& lo, const Vec2& hi) const;
  Field field_of_map(const OccupancyGrid& map) const;
  ScanMatch match_to_field(const Field& field, std::span<const Vec2> scan, const Pose2& guess) const;

 private:
  CorrelativeMatcherConfig c_;
};

ScanMatcherDef correlative_scan_matcher();

}  // namespace starnav
