#pragma once
// The laser models of AMCL (Nav2 nav2_amcl, after Player's amcl): the likelihood field and the
// beam model (Probabilistic Robotics, Table 6.1 and section 6.4). Both weigh one particle as
// Nav2 does, p = 1 + sum over the used beams of pz^3 (an ad hoc combination that keeps one bad
// beam from zeroing a particle), with the beams subsampled by step (n - 1) / (max_beams - 1).
//
// World <-> grid follows GridGeometry: a particle's laser pose is moved into the grid frame once,
// so an origin yaw is honoured at no cost per beam.
#include <cstdint>
#include <span>
#include <optional>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// One planar scan in the laser frame. Angles are given per beam, so scans whose azimuths
// decrease with the index (the simulator's) and scans whose angles increase (robot logs) are the
// same to the models. A non-return is +inf, NaN, a range >= range_max or <= range_min.
struct PlanarScan {
  std::vector<double> ranges;      // m
  std::vector<double> angles_rad;  // bearing of each beam in the laser frame
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  // A robot with several scanners: which one this is (each updates the filter once per motion
  // step, as Nav2's lasers_update_) and its mount, when it is not the filter's own laser.
  std::size_t sensor = 0;
  std::optional<Pose2> laser_in_base;

  // Throws Error (field "scan") unless ranges and angles have the same size, the angles are
  // finite and 0 <= range_min < range_max < inf.
  void validate() const;
};

// One beam a model uses: its range (range_max exactly for a non-return) and bearing.
struct ModelBeam {
  double range_m = 0.0;
  double bearing_rad = 0.0;
};

// The beams of `scan` a model uses, as Nav2: every step-th beam from the first, step =
// max(1, (n - 1) / (max_beams - 1)) in integer arithmetic; readings that are not finite, >=
// range_max or <= range_min become range_max (Nav2 maps short readings to max range). The
// caller chooses the limits (the scan's, or tighter ones from the configuration).
std::vector<ModelBeam> model_beams(const PlanarScan& scan, int max_beams, double range_min_m, double range_max_m);

// Where the distance of a point to "the obstacle" is measured to.
enum class FieldReference : std::uint8_t {
  Centre,   // the nearest occupied cell's centre (Nav2)
  Surface,  // the nearest occupied cell's square: a LiDAR hits walls on their faces, not centres
};

struct LikelihoodFieldConfig {
  double max_dist_m = 2.0;   // laser_likelihood_max_dist: distances are clamped here
  double sigma_hit_m = 0.2;
  double z_hit = 0.5;
  double z_rand = 0.5;
  double range_max_m = 30.0;  // enters through z_rand / range_max
  FieldReference reference = FieldReference::Surface;
  // How the beams' pz combine into one weight. 0: Nav2's p = 1 + sum pz^3. k > 0: the tempered
  // product p = exp(k mean ln(pz / pz(0))), i.e. (prod pz / pz(0))^(k / n) over the n returning
  // beams: the scan counts as k independent beams, whatever the beam count.
  double independent_beams = 0.0;
};
// The largest independent_beams accepted (a scan counted as 100 independent beams is already
// sharper than any map is true).
inline constexpr double kMaxIndependentBeams = 100.0;

// The likelihood field: per cell the clamped distance d from its centre to the nearest occupied
// cell (per the thresholds; unknown cells are not obstacles, as in Nav2) and the final per-beam
// term: pz^3 (Nav2's sum) or ln(pz / pz(0)) (the tempered product), pz = z_hit exp(-d^2 /
// (2 sigma^2)) + z_rand / range_max. A beam end point takes the value of the cell that contains
// it (nearest-cell lookup, as Nav2); off the map d = max_dist.
//
// weight() and weigh() use a scratch buffer of the object: one field per thread.
//
// Distances are exact for cell centres with both references: Centre comes from the exact
// Euclidean distance transform; Surface from an exact separable transform of the distance to the
// union of occupied squares (not from the nearest centre's square, which can be up to 0.19 cell
// too far: the nearest square need not belong to the nearest centre).
class LikelihoodField {
 public:
  // Throws Error (field "amcl.<parameter>") for a non-positive max distance, sigma or range_max
  // or negative z weights.
  LikelihoodField(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, const LikelihoodFieldConfig& config);

  const LikelihoodFieldConfig& config() const { return config_; }
  // Recomputes the terms for another range_max (the distances stay).
  void set_range_max(double range_max_m);

  // The clamped distance and the term of the cell containing a world point (max_dist off the map).
  double distance_m(const Vec2& world) const;
  double term(const Vec2& world) const;
  // The term for a distance (d clamped to max_dist): pz^3, or ln(pz / pz(0)) for the tempered product.
  double term_at_distance(double d_m) const;

  // For a robot at `pose` with the laser at `laser_in_base`, over the beams with range <
  // range_max: p = 1 + sum of the terms at the beams' end points, or exp(k / n sum) for the
  // tempered product (1 when no beam returns).
  double weight(const Pose2& pose, const Pose2& laser_in_base, std::span<const ModelBeam> beams) const;
  // The same for every pose into `out` (same size as `poses`).
  void weigh(std::span<const Pose2> poses, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
             std::span<double> out) const;

 private:
  void fill_terms();

  LikelihoodFieldConfig config_;
  int width_ = 0;
  int height_ = 0;
  double inv_resolution_ = 1.0;
  Pose2 origin_;
  std::vector<float> distance_;  // clamped, m
  std::vector<float> term_;      // per cell: pz^3, or ln(pz / pz(0))
  double far_term_ = 0.0;        // the term at max_dist (off the map)
  mutable std::vector<double> beam_x_, beam_y_;  // scratch of weigh(): end points in the laser frame, in cells
};

struct BeamModelConfig {
  double z_hit = 0.5;
  double z_short = 0.05;
  double z_max = 0.05;
  double z_rand = 0.5;
  double sigma_hit_m = 0.2;
  double lambda_short = 0.1;  // 1/m
};

// The beam model: each beam's expected range is found by exact grid traversal (Amanatides & Woo)
// from the laser through the grid; as in Nav2 the ray stops in the first cell that is not free
// (occupied or unknown) and at the map's edge. Per beam, as Nav2's beam_model:
//   pz = z_hit exp(-(z - z*)^2 / (2 sigma^2)) + [z < z*] z_short lambda exp(-lambda z)
//        + [z = range_max] z_max + [z < range_max] z_rand / range_max
// (no normalisation of the Gaussian and the exponential, as Nav2) and p = 1 + sum pz^3.
class BeamModel {
 public:
  // Throws Error (field "amcl.<parameter>") for a non-positive sigma or lambda or negative weights.
  BeamModel(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, const BeamModelConfig& config);

  const BeamModelConfig& config() const { return config_; }
  // The range from `laser` (a world pose) along its heading to the first cell that is not free,
  // or to the map's edge, at most range_max; 0 when the laser itself is in such a cell or off the map.
  double expected_range(const Pose2& laser, double range_max_m) const;
  // pz of one beam with observed range `z` and expected range `z_expected`.
  double beam_probability(double z, double z_expected, double range_max_m) const;

  double weight(const Pose2& pose, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
                double range_max_m) const;
  void weigh(std::span<const Pose2> poses, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
             double range_max_m, std::span<double> out) const;

 private:
  BeamModelConfig config_;
  GridGeometry geometry_;
  std::vector<std::uint8_t> blocked_;  // 1: not free (occupied or unknown)
};

}  // namespace starnav
