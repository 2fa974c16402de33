#pragma once
// Adaptive Monte Carlo localization on a known occupancy grid (docs/papers/ren2022.md), the
// filter of Nav2's nav2_amcl as plain library code: odometry motion model, likelihood-field or
// beam laser model, KLD-adaptive resampling, recovery by random injection. No time, no frames
// beyond the map and odom: the caller hands it odometry poses and scans; the Localizer wrapper
// (amcl_localizer.cpp) connects it to the navigation loop.
//
// Differences from Nav2, each for a reason given where it is implemented: the recovery average
// does not scale with the particle count; after an injection only the fast average is reset (to
// the slow one); random poses are injected (and the set resampled) whenever the injection
// probability is positive, even with selective resampling; yaw bins wrap at +-pi; the cluster yaw variance is divided by the cluster's weight; the reported covariance
// is the best cluster's (Nav2 reports the whole set's x-y covariance); non-returns (+inf) count
// as max-range readings in the beam model (Nav2 gives them pz = 0); the default field reference
// is the occupied cells' surface, not their centres.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl_motion_model.hpp"
#include "starnav/estimate/amcl_sensor_model.hpp"
#include "starnav/estimate/particle_filter.hpp"
#include "starnav/estimate/scan_proposal.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

enum class LaserModelType : std::uint8_t { LikelihoodField, Beam };

// Nav2's parameters and defaults (amcl_node.cpp), with units in the names; then starnav's.
struct AmclConfig {
  // motion
  MotionModelType robot_model = MotionModelType::Differential;
  double alpha1 = 0.2, alpha2 = 0.2, alpha3 = 0.2, alpha4 = 0.2, alpha5 = 0.2;
  // laser
  LaserModelType laser_model = LaserModelType::LikelihoodField;
  double z_hit = 0.5;
  double z_rand = 0.5;
  double z_short = 0.05;
  double z_max = 0.05;
  double sigma_hit_m = 0.2;
  double lambda_short = 0.1;                 // 1/m
  double laser_likelihood_max_dist_m = 2.0;
  double laser_max_range_m = -1.0;           // <= 0: the scan's range_max; else min(scan's, this)
  double laser_min_range_m = -1.0;           // <= 0: the scan's range_min; else max(scan's, this)
  int max_beams = 60;
  // Surface by default: a LiDAR hits a wall on its face, half a cell from the occupied cells'
  // centres Nav2 measures to; on a 0.1 m map that bias (0.05 m) is as large as the accuracy asked of AMCL.
  FieldReference field_reference = FieldReference::Surface;
  // particles
  int min_particles = 500;
  int max_particles = 2000;
  double pf_err = 0.05;
  double pf_z = 0.99;                        // used as the normal quantile z itself, as Nav2 (see kld_limit)
  double kld_bin_xy_m = 0.5;
  double kld_bin_yaw_rad = deg_to_rad(10.0);
  Resampler resampler = Resampler::LowVariance;
  bool selective_resampling = false;
  int resample_interval = 1;
  double recovery_alpha_slow = 0.0;
  double recovery_alpha_fast = 0.0;
  // FastToSlow rather than Nav2's Zero: with Zero a kidnapped filter relocalized in 2 of 12
  // seeded runs of the test room within 150 updates, with FastToSlow in all 12 (see RecoveryReset).
  RecoveryReset recovery_reset = RecoveryReset::FastToSlow;
  // updates: a filter update once the odometry moved more than this on x or y or turned more
  // than this since the last one (Nav2 compares |dx|, |dy| and |dyaw| separately)
  double update_min_d_m = 0.25;
  double update_min_a_rad = 0.2;
  // start (Nav2's initial covariance 0.5^2, 0.5^2, (pi/12)^2)
  double initial_sigma_xy_m = 0.5;
  double initial_sigma_yaw_rad = kPi / 12.0;
  // convergence: the best cluster holds this share of the weight and its position spread is small
  double converged_weight = 0.9;
  double converged_sigma_m = 0.15;
  // The search phase (starnav's): after a global start, and after random poses were injected,
  // until the filter converges, the motion noise is at least search_alpha and the likelihood field
  // uses the search_* laser terms (Nav2's defaults). Sharp tracking models collapse a cloud spread
  // over a whole map onto the first look-alike place; Nav2's broader ones keep the modes alive
  // until the scans tell them apart. With tracking settings equal to Nav2's it changes nothing.
  bool search_phase = true;
  double search_alpha = 0.2;
  double search_z_hit = 0.5;
  double search_z_rand = 0.5;
  double search_sigma_hit_m = 0.2;
  // How the search phase's likelihood field combines the beams: 0 is Nav2's 1 + sum pz^3; k > 0
  // the tempered product (prod pz / pz(0))^(k / n) over the n returning beams, the scan counted
  // as k independent beams (LikelihoodFieldConfig). Nav2's sum tells two places apart only by the
  // share of beams that fit each: look-alikes 10 % apart in it gain 1.1x a scan, and a cloud that
  // had found the robot took 10-25 more updates to leave its look-alikes (depot, warehouse).
  // The full product (k = n) is the opposite: a particle 0.2 m off loses to a look-alike with a
  // few wrong beams, and a two-mode cloud collapses on sampling noise (k = 6: false convergences
  // in 2 of 5 runs of the symmetric corridors). k = 3 found the robot in 3-15 updates and kept
  // the symmetric corridors' two modes until the scans differed (docs/localization.md).
  double search_independent_beams = 3.0;
  // The tempered product rises linearly to full strength over this many updates of a search (the
  // likelihoods raised to updates / this), and the search does not end before.
  int search_ramp_updates = 8;
  // The search ends once one cluster holds converged_weight of the weight within this spread (the
  // broad models keep a cloud wider than converged_sigma_m, so convergence itself would never come).
  double search_end_sigma_m = 0.5;
  // While searching the set keeps max_particles; KLD sizes it once the search has ended. KLD
  // counts occupied bins: two compact look-alike hypotheses occupy few, and the set shrank to
  // min_particles while both were alive, so chance decided between them within tens of updates
  // (the symmetric corridors: a wrong convergence in 4 of 20 runs, 1 of 20 holding the count).
  // Holding it until converged instead also gave 0 of 20 there, but under Nav2's flat likelihood
  // a larger set keeps a wider cloud (its tails stay represented), which then need not shrink to
  // converged_sigma_m at all: tracking from a 5 cm start stopped claiming convergence.
  bool search_holds_particles = true;
  // The scan proposal (starnav's; off is Nav2): a global start takes the max_particles candidate
  // poses that best explain its first scan, and the recovery draws its poses from the
  // max_particles best for the scan of that update, instead of uniformly over the free space
  // (scan_proposal.hpp). Needs the likelihood field.
  bool scan_proposal = false;
  ScanProposalConfig proposal;

  // Throws Error naming the field ("amcl.min_particles", ...) for an impossible value.
  void validate() const;
  MotionNoise motion_noise() const { return {alpha1, alpha2, alpha3, alpha4, alpha5}; }
  // The search phase's: every alpha at least search_alpha.
  MotionNoise search_motion_noise() const;
  ParticleFilterConfig filter_config() const;
  // The initial covariance diag(sigma_xy^2, sigma_xy^2, sigma_yaw^2).
  Eigen::Matrix3d initial_covariance() const;
};

// An AmclConfig from the amcl localizer's declared parameters (amcl_localizer.cpp; keys relative
// to the section, "alpha1", as `--set amcl.alpha1=...` gives them once the prefix is gone), for
// callers that drive Amcl themselves (`starnav localize` on a log). robot_model_type auto means
// differential here (no robot to ask); `initial` is read and checked but has no field here.
// Throws Error naming the setting (`file` when it came from one) for a bad key or value.
AmclConfig amcl_config_from_settings(std::span<const ParamSetting> settings, const std::string& file);

struct AmclEstimate {
  Pose2 pose;                                             // the best cluster's mean (map frame)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();   // the best cluster's covariance
  double cluster_weight = 0.0;                            // its share of the weight
  // cluster_weight >= converged_weight and the square root of the largest eigenvalue of the
  // x-y covariance <= converged_sigma_m (the largest eigenvalue, not the trace: the spread along
  // a corridor counts in full, whatever the spread across it).
  bool converged = false;
  int particles = 0;
  int clusters = 0;
  int updates = 0;                                        // filter updates so far
  bool searching = false;                                 // in the search phase (AmclConfig)
};

// Counters for reports and tests.
struct AmclCounters {
  int updates = 0;           // filter (sensor) updates
  int resamples = 0;
  long long injected = 0;    // random poses injected, in all
  int last_injected = 0;     // in the last resampling
  int proposals = 0;         // scan proposals drawn (global start, injections)
  long long proposal_candidates = 0;  // candidate poses they scored, in all
  int scan_injections = 0;   // injecting resamplings whose poses came from the scan (proposal.recovery)
  double last_w_diff = 0.0;  // injection probability of the last resampling
};

// Scanners one filter takes scans from (PlanarScan::sensor).
inline constexpr std::size_t kMaxAmclSensors = 16;

class Amcl {
 public:
  // `map` is copied where needed (free cells, the field); thresholds say which cells are free
  // (global start, injection) and occupied (the field). Throws Error for a bad configuration or map.
  Amcl(const OccupancyGrid& map, const OccupancyThresholds& thresholds, const AmclConfig& config,
       const Pose2& laser_in_base, std::uint64_t seed);

  const AmclConfig& config() const { return config_; }
  const Pose2& laser_in_base() const { return laser_in_base_; }

  // A Gaussian cloud of max_particles around `mean` (yaw wrapped). Throws Error (field
  // "amcl.initial_covariance") unless `cov` is finite, symmetric and positive semi-definite.
  void initialize(const Pose2& mean, const Eigen::Matrix3d& cov);
  // The same with the configured initial covariance.
  void initialize(const Pose2& mean) { initialize(mean, config_.initial_covariance()); }
  // max_particles poses uniform over the free cells (thresholded free, not unknown): a uniform
  // cell, a uniform offset inside it, a uniform yaw; with scan_proposal the first scan replaces
  // them by the best candidates for it (and the set is not weighed by that scan again). Throws
  // Error (field "map") without free cells.
  void initialize_global();
  bool initialized() const { return initialized_; }

  // One scan with the odometry pose (odom frame) at its time. The first call after an
  // initialisation only takes the odometry as reference and weighs the particles by the scan
  // (Nav2 updates on its first scan). Later calls update when the odometry moved beyond
  // update_min_d / update_min_a since the last update: the particles move by the odometry
  // increment, are weighed, and are resampled every resample_interval updates (see
  // ParticleFilter::wants_resample). Returns true when a filter update happened. Throws Error
  // before initialisation or for a malformed scan.
  bool update(const Pose2& odom_pose, const PlanarScan& scan);

  // The best (heaviest) cluster after the last update (or the initialisation).
  const AmclEstimate& estimate() const { return estimate_; }
  // map <- odom at the last update: estimate = map_to_odom() * odom between updates. Identity
  // before the first update.
  const Pose2& map_to_odom() const { return map_to_odom_; }
  // The map pose of the robot at odometry pose `odom`: map_to_odom() applied to it,
  // the best cluster's mean before the first update (no map <- odom is known yet).
  Pose2 pose_at(const Pose2& odom) const;
  const std::vector<ParticleCluster>& clusters() const { return clusters_; }

  std::span<const Pose2> particles() const { return filter_.poses(); }
  // At most `max` particles taken evenly over the set (a viewer's sample: after resampling the
  // set is in no particular order).
  std::vector<Pose2> particle_sample(std::size_t max) const;
  std::span<const double> weights() const { return filter_.weights(); }
  const ParticleFilter& filter() const { return filter_; }
  const AmclCounters& counters() const { return counters_; }
  // The likelihood field (null with the beam model).
  const LikelihoodField* likelihood_field() const { return field_ ? &*field_ : nullptr; }

  // A uniform random pose over the free cells (what injection draws).
  Pose2 random_free_pose(Rng& rng) const;

 private:
  void refresh_estimate();
  // Whether the search phase weighs with the tempered product (the ramp applies then).
  bool tempered_search() const;
  // Whether `candidate` explains the scan proposal.injection_margin times better than the set's best particle.
  bool scan_explained_better(const Pose2& candidate, std::span<const ModelBeam> beams, double range_max);
  // The `count` best of at most `limit` candidate poses for the scan's beams (scan_proposal); uniform free poses
  // for a scan without a return.
  std::vector<Pose2> proposed_poses(const LikelihoodField& field, std::span<const ModelBeam> beams, std::size_t count,
                                    std::size_t limit);

  AmclConfig config_;
  Pose2 laser_in_base_;
  Pose2 laser_;                              // the mount of the scan being weighed
  std::vector<std::uint8_t> sensor_pending_;  // per scanner: the motion since its last update is not weighed yet
  GridGeometry geometry_;
  std::vector<std::int32_t> free_cells_;
  std::optional<LikelihoodField> field_;
  std::optional<LikelihoodField> search_field_;  // the search phase's terms, when they differ
  std::optional<BeamModel> beam_model_;
  std::optional<ScanProposal> proposal_;
  bool global_proposal_pending_ = false;
  bool searching_ = false;
  int search_updates_ = 0;  // weighings since the search began
  ParticleFilter filter_;
  Rng rng_;
  bool initialized_ = false;
  bool have_odom_reference_ = false;
  Pose2 odom_reference_;
  int resample_count_ = 0;
  AmclEstimate estimate_;
  std::vector<ParticleCluster> clusters_;
  Pose2 map_to_odom_;
  AmclCounters counters_;
  std::vector<double> likelihoods_;
};

}  // namespace starnav
