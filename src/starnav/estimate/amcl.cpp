#include "starnav/estimate/amcl.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

namespace {

void amcl_require_unit(double v, const char* field) {
  require(std::isfinite(v) && v >= 0.0 && v <= 1.0, field, "must be in [0, 1]");
}

// The largest eigenvalue of the x-y block of a covariance.
double amcl_max_xy_eigenvalue(const Eigen::Matrix3d& c) {
  const double a = c(0, 0), b = c(0, 1), d = c(1, 1);
  return 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
}

// The heaviest cluster holds at least `weight` of the weight within a spread of `sigma_m`.
bool amcl_concentrated(const std::vector<ParticleCluster>& clusters, double weight, double sigma_m) {
  return !clusters.empty() && clusters.front().weight >= weight &&
         std::sqrt(std::max(0.0, amcl_max_xy_eigenvalue(clusters.front().covariance))) <= sigma_m;
}

}  // namespace

void AmclConfig::validate() const {
  motion_noise().validate();
  require_non_negative(z_hit, "amcl.z_hit");
  require_non_negative(z_rand, "amcl.z_rand");
  require_non_negative(z_short, "amcl.z_short");
  require_non_negative(z_max, "amcl.z_max");
  require(z_hit + z_rand + z_short + z_max > 0.0, "amcl.z_hit", "the laser model weights z_* are all 0");
  require_positive(sigma_hit_m, "amcl.sigma_hit_m");
  require_positive(lambda_short, "amcl.lambda_short");
  require_positive(laser_likelihood_max_dist_m, "amcl.laser_likelihood_max_dist_m");
  require(std::isfinite(laser_max_range_m), "amcl.laser_max_range_m", "must be finite (<= 0: the scan's)");
  require(std::isfinite(laser_min_range_m), "amcl.laser_min_range_m", "must be finite (<= 0: the scan's)");
  require(max_beams >= 2, "amcl.max_beams", "must be >= 2");
  filter_config().validate();
  require(resample_interval >= 1, "amcl.resample_interval", "must be >= 1");
  require_non_negative(update_min_d_m, "amcl.update_min_d_m");
  require_non_negative(update_min_a_rad, "amcl.update_min_a_rad");
  require_non_negative(initial_sigma_xy_m, "amcl.initial_sigma_xy_m");
  require_non_negative(initial_sigma_yaw_rad, "amcl.initial_sigma_yaw_rad");
  amcl_require_unit(converged_weight, "amcl.converged_weight");
  require_positive(converged_sigma_m, "amcl.converged_sigma_m");
  require_non_negative(search_alpha, "amcl.search_alpha");
  require_non_negative(search_z_hit, "amcl.search_z_hit");
  require_non_negative(search_z_rand, "amcl.search_z_rand");
  require(search_z_hit + search_z_rand > 0.0, "amcl.search_z_hit", "search_z_hit and search_z_rand are both 0");
  require_positive(search_sigma_hit_m, "amcl.search_sigma_hit_m");
  require_positive(search_end_sigma_m, "amcl.search_end_sigma_m");
  require(search_ramp_updates >= 0, "amcl.search_ramp_updates", "must be >= 0");
  require(std::isfinite(search_independent_beams) && search_independent_beams >= 0.0 &&
              search_independent_beams <= kMaxIndependentBeams,
          "amcl.search_independent_beams", "must lie in [0, 100]");
  if (scan_proposal) {
    proposal.validate();
    require(laser_model == LaserModelType::LikelihoodField, "amcl.scan_proposal",
            "needs laser_model_type likelihood_field");
  }
}

MotionNoise AmclConfig::search_motion_noise() const {
  return {std::max(alpha1, search_alpha), std::max(alpha2, search_alpha), std::max(alpha3, search_alpha),
          std::max(alpha4, search_alpha), std::max(alpha5, search_alpha)};
}

ParticleFilterConfig AmclConfig::filter_config() const {
  ParticleFilterConfig c;
  c.min_particles = min_particles;
  c.max_particles = max_particles;
  c.pf_err = pf_err;
  c.pf_z = pf_z;
  c.bins.xy_m = kld_bin_xy_m;
  c.bins.yaw_rad = kld_bin_yaw_rad;
  c.resampler = resampler;
  c.alpha_slow = recovery_alpha_slow;
  c.alpha_fast = recovery_alpha_fast;
  c.selective_resampling = selective_resampling;
  c.recovery_reset = recovery_reset;
  return c;
}

Eigen::Matrix3d AmclConfig::initial_covariance() const {
  return Eigen::Vector3d(initial_sigma_xy_m * initial_sigma_xy_m, initial_sigma_xy_m * initial_sigma_xy_m,
                         initial_sigma_yaw_rad * initial_sigma_yaw_rad)
      .asDiagonal();
}

Amcl::Amcl(const OccupancyGrid& map, const OccupancyThresholds& thresholds, const AmclConfig& config,
           const Pose2& laser_in_base, std::uint64_t seed)
    : config_((config.validate(), config)),
      laser_in_base_(laser_in_base),
      laser_(laser_in_base),
      geometry_(map.geometry()),
      filter_(config.filter_config()),
      rng_(seed) {
  validate_geometry(geometry_, "map");
  require(std::isfinite(laser_in_base.x) && std::isfinite(laser_in_base.y) && std::isfinite(laser_in_base.yaw),
          "amcl.laser_in_base", "must be finite");
  for (std::size_t i = 0; i < map.cell_count(); ++i)
    if (thresholds.classify(map[i]) == CellState::Free) free_cells_.push_back(static_cast<std::int32_t>(i));
  if (config_.laser_model == LaserModelType::LikelihoodField) {
    LikelihoodFieldConfig f;
    f.max_dist_m = config_.laser_likelihood_max_dist_m;
    f.sigma_hit_m = config_.sigma_hit_m;
    f.z_hit = config_.z_hit;
    f.z_rand = config_.z_rand;
    // The terms are refreshed for the scans' range_max on the first scan.
    f.range_max_m = config_.laser_max_range_m > 0.0 ? config_.laser_max_range_m : 30.0;
    f.reference = config_.field_reference;
    field_.emplace(map, thresholds, f);
    if (config_.search_phase && (config_.search_z_hit != f.z_hit || config_.search_z_rand != f.z_rand ||
                                 config_.search_sigma_hit_m != f.sigma_hit_m || config_.search_independent_beams > 0.0)) {
      f.z_hit = config_.search_z_hit;
      f.z_rand = config_.search_z_rand;
      f.sigma_hit_m = config_.search_sigma_hit_m;
      f.independent_beams = config_.search_independent_beams;
      search_field_.emplace(map, thresholds, f);
    }
  } else {
    BeamModelConfig b;
    b.z_hit = config_.z_hit;
    b.z_short = config_.z_short;
    b.z_max = config_.z_max;
    b.z_rand = config_.z_rand;
    b.sigma_hit_m = config_.sigma_hit_m;
    b.lambda_short = config_.lambda_short;
    beam_model_.emplace(map, thresholds, b);
  }
  if (config_.scan_proposal && !free_cells_.empty()) proposal_.emplace(geometry_, free_cells_, config_.proposal);
}

void Amcl::initialize(const Pose2& mean, const Eigen::Matrix3d& cov) {
  require(std::isfinite(mean.x) && std::isfinite(mean.y) && std::isfinite(mean.yaw), "amcl.initial_pose",
          "must be finite");
  require(cov.allFinite(), "amcl.initial_covariance", "must be finite");
  const double scale = std::max(1.0, cov.cwiseAbs().maxCoeff());
  require((cov - cov.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale, "amcl.initial_covariance",
          "must be symmetric");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  require(eig.eigenvalues().minCoeff() >= -1e-12 * scale, "amcl.initial_covariance", "must be positive semi-definite");
  // A square root that also serves a singular covariance (a known yaw, say).
  const Eigen::Matrix3d root = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  std::vector<Pose2> poses(static_cast<std::size_t>(config_.max_particles));
  for (Pose2& p : poses) {
    const Eigen::Vector3d n(rng_.normal(), rng_.normal(), rng_.normal());
    const Eigen::Vector3d d = root * n;
    p = Pose2(mean.x + d.x(), mean.y + d.y(), wrap_angle(mean.yaw + d.z()));
  }
  filter_.set_particles(std::move(poses));
  searching_ = false;  // tracking from a known pose
  global_proposal_pending_ = false;
  initialized_ = true;
  have_odom_reference_ = false;
  refresh_estimate();
}

void Amcl::initialize_global() {
  require(!free_cells_.empty(), "map", "has no free cell to spread particles over");
  std::vector<Pose2> poses(static_cast<std::size_t>(config_.max_particles));
  for (Pose2& p : poses) p = random_free_pose(rng_);
  filter_.set_particles(std::move(poses));
  initialized_ = true;
  have_odom_reference_ = false;
  searching_ = config_.search_phase;
  search_updates_ = 0;
  global_proposal_pending_ = proposal_.has_value();
  refresh_estimate();
}

Pose2 Amcl::random_free_pose(Rng& rng) const {
  const std::int64_t k = rng.uniform_int(0, static_cast<std::int64_t>(free_cells_.size()) - 1);
  const Cell c = geometry_.cell_of_index(static_cast<std::size_t>(free_cells_[static_cast<std::size_t>(k)]));
  const double gx = (c.x + rng.uniform()) * geometry_.resolution;
  const double gy = (c.y + rng.uniform()) * geometry_.resolution;
  const Vec2 w = geometry_.grid_to_world({gx, gy});
  return {w.x(), w.y(), rng.uniform(-kPi, kPi)};
}

bool Amcl::update(const Pose2& odom_pose, const PlanarScan& scan) {
  require(initialized_, "amcl", "update before initialize");
  scan.validate();
  require(std::isfinite(odom_pose.x) && std::isfinite(odom_pose.y) && std::isfinite(odom_pose.yaw), "odometry",
          "pose must be finite");
  const double range_max =
      config_.laser_max_range_m > 0.0 ? std::min(scan.range_max_m, config_.laser_max_range_m) : scan.range_max_m;
  const double range_min =
      config_.laser_min_range_m > 0.0 ? std::max(scan.range_min_m, config_.laser_min_range_m) : scan.range_min_m;

  require(scan.sensor < kMaxAmclSensors, "scan", "sensor index " + std::to_string(scan.sensor) + " is not below " +
                                                    std::to_string(kMaxAmclSensors));
  if (sensor_pending_.size() <= scan.sensor) sensor_pending_.resize(scan.sensor + 1, 1);
  bool motion = true;  // this update applies the motion since the reference (else a pending scanner's update at the same place)
  if (!have_odom_reference_) {
    odom_reference_ = odom_pose;
    have_odom_reference_ = true;
    resample_count_ = 0;
  } else {
    const double dx = odom_pose.x - odom_reference_.x, dy = odom_pose.y - odom_reference_.y;
    const double dyaw = angle_diff(odom_pose.yaw, odom_reference_.yaw);
    const bool moved = std::abs(dx) > config_.update_min_d_m || std::abs(dy) > config_.update_min_d_m ||
                       std::abs(dyaw) > config_.update_min_a_rad;
    if (moved) {
      apply_motion_model(config_.robot_model, searching_ ? config_.search_motion_noise() : config_.motion_noise(),
                         odom_reference_, odom_pose, filter_.poses(), rng_);
      std::fill(sensor_pending_.begin(), sensor_pending_.end(), 1);
    } else if (!sensor_pending_[scan.sensor]) {
      return false;
    } else {
      motion = false;
    }
  }
  sensor_pending_[scan.sensor] = 0;
  laser_ = scan.laser_in_base.value_or(laser_in_base_);

  const std::vector<ModelBeam> beams = model_beams(scan, config_.max_beams, range_min, range_max);
  LikelihoodField* field = nullptr;
  if (field_) {
    field = searching_ && search_field_ ? &*search_field_ : &*field_;
    field->set_range_max(range_max);
  }
  ++counters_.updates;
  bool search_over = false;
  bool injected_now = false;
  // The proposal exists only with the likelihood field (validate), so `field` is set wherever it
  // is used.
  if (global_proposal_pending_ && field) {
    // The first scan of a global start chooses the particles; weighing them by it again would
    // count it twice.
    filter_.set_particles(proposed_poses(*field, beams, static_cast<std::size_t>(config_.max_particles),
                                          static_cast<std::size_t>(config_.proposal.max_candidates)));
    global_proposal_pending_ = false;
  } else {
    likelihoods_.resize(filter_.size());
    if (field)
      field->weigh(filter_.poses(), laser_, beams, likelihoods_);
    else
      beam_model_->weigh(filter_.poses(), laser_, beams, range_max, likelihoods_);
    if (searching_ && tempered_search()) {
      // The ramp: (prod pz / pz(0))^(k r / n) with r rising to 1. The first updates of a search
      // compare modes whose particles the proposal's lattice or the random poses put a little
      // off their places: at full k that luck, not the scans, chose between look-alikes (the
      // symmetric corridors: the mirrored corridor claimed in 2 of 20 runs, none with the ramp).
      ++search_updates_;
      const double r = std::min(1.0, static_cast<double>(search_updates_) / std::max(1, config_.search_ramp_updates));
      if (r < 1.0)
        for (double& l : likelihoods_) l = std::pow(l, r);
    }
    filter_.weigh(likelihoods_);

    // The search ends once the weighed set (the posterior, before any recovery poses join it)
    // has one cluster with converged_weight of the weight within search_end_sigma_m. Judged
    // after resampling, the recovery's own poses would keep it going: they join wherever the
    // scan fits, widening the cluster, while the broad cloud's low likelihood keeps them coming.
    if (searching_) {
      const std::vector<ParticleCluster> posterior = cluster_particles(filter_.poses(), filter_.weights(), filter_.config().bins);
      search_over = amcl_concentrated(posterior, config_.converged_weight, config_.search_end_sigma_m);
    }

    // Every resample_interval updates (when selective resampling agrees), and whenever the
    // recovery asks for random poses.
    const bool due = ++resample_count_ % config_.resample_interval == 0;
    if ((due && filter_.wants_resample()) || filter_.injection_probability() > 0.0) {
      RandomPoseFn random_pose;
      std::vector<Pose2> pool;  // the recovery's poses from the scan (proposal.recovery)
      if (proposal_ && field && config_.proposal.recovery && filter_.injection_probability() > 0.0) {
        pool = proposed_poses(*field, beams, static_cast<std::size_t>(config_.proposal.injection_pool),
                              static_cast<std::size_t>(config_.proposal.injection_candidates));
        if (!pool.empty() && !scan_explained_better(pool.front(), beams, range_max)) pool.clear();
        if (!pool.empty())
          random_pose = [&pool](Rng& r) {
            return pool[static_cast<std::size_t>(r.uniform_int(0, static_cast<std::int64_t>(pool.size()) - 1))];
          };
      }
      if (!random_pose && !free_cells_.empty()) random_pose = [this](Rng& r) { return random_free_pose(r); };
      const ResampleResult r = filter_.resample(rng_, random_pose, searching_ && config_.search_holds_particles ? config_.max_particles : 0);
      ++counters_.resamples;
      if (r.injected > 0 && !pool.empty()) ++counters_.scan_injections;
      counters_.injected += r.injected;
      counters_.last_injected = r.injected;
      counters_.last_w_diff = r.w_diff;
      injected_now = r.injected > 0;
    }
  }
  // A scanner's update without motion leaves the reference where the motion was last applied:
  // the motion below the thresholds since then is applied with the next.
  if (motion) odom_reference_ = odom_pose;
  refresh_estimate();
  // Random poses start a search, unless the set still holds one tight cluster after them (a
  // few poses injected beside a converged set when the likelihood dips are weeded out by the
  // tracking models).
  const bool concentrated = amcl_concentrated(clusters_, config_.converged_weight, config_.search_end_sigma_m);
  if (injected_now && config_.search_phase && !searching_ && !concentrated) {
    searching_ = true;
    search_updates_ = 0;
  }
  // A tempered search ends only at full strength: before it, one cluster's share says more about
  // how the particles happened to lie than about the scans.
  const bool ramped = !tempered_search() || search_updates_ >= config_.search_ramp_updates;
  if (searching_ && ramped && (search_over || concentrated)) searching_ = false;
  estimate_.searching = searching_;
  map_to_odom_ = estimate_.pose.compose(odom_pose.inverse());
  return true;
}

std::vector<Pose2> Amcl::proposed_poses(const LikelihoodField& field, std::span<const ModelBeam> beams, std::size_t count,
                                        std::size_t limit) {
  const std::vector<ScoredPose> best = proposal_->best(field, laser_, beams, count, limit, rng_);
  if (best.empty()) {
    // A scan without a return says nothing about where the robot is: uniform poses then.
    std::vector<Pose2> poses(count);
    for (Pose2& p : poses) p = random_free_pose(rng_);
    return poses;
  }
  ++counters_.proposals;
  counters_.proposal_candidates += static_cast<long long>(proposal_->candidates_per_call(limit));
  std::vector<Pose2> poses(best.size());
  for (std::size_t k = 0; k < best.size(); ++k) poses[k] = best[k].pose;
  return poses;
}

bool Amcl::tempered_search() const { return search_field_ && search_field_->config().independent_beams > 0.0; }

bool Amcl::scan_explained_better(const Pose2& candidate, std::span<const ModelBeam> beams, double range_max) {
  // The set's best particle under the model that weighed it this update, then both under the
  // gate's field: one scale whatever phase the filter is in.
  const std::size_t best =
      static_cast<std::size_t>(std::max_element(likelihoods_.begin(), likelihoods_.end()) - likelihoods_.begin());
  if (best >= filter_.size()) return true;
  LikelihoodField& gate =
      config_.proposal.injection_gate == ScanProposalConfig::Gate::Search && search_field_ ? *search_field_ : *field_;
  gate.set_range_max(range_max);
  const double particle = gate.weight(filter_.poses()[best], laser_, beams);
  return gate.weight(candidate, laser_, beams) >= config_.proposal.injection_margin * particle;
}

Pose2 Amcl::pose_at(const Pose2& odom) const {
  return estimate_.updates == 0 ? estimate_.pose : map_to_odom_.compose(odom);
}

void Amcl::refresh_estimate() {
  clusters_ = cluster_particles(filter_.poses(), filter_.weights(), filter_.config().bins);
  AmclEstimate e;
  if (!clusters_.empty()) {
    const ParticleCluster& best = clusters_.front();
    e.pose = best.mean;
    e.covariance = best.covariance;
    e.cluster_weight = best.weight;
    e.converged = amcl_concentrated(clusters_, config_.converged_weight, config_.converged_sigma_m);
  }
  e.particles = static_cast<int>(filter_.size());
  e.clusters = static_cast<int>(clusters_.size());
  e.updates = counters_.updates;
  e.searching = searching_;
  estimate_ = e;
}

std::vector<Pose2> Amcl::particle_sample(std::size_t max) const {
  const std::span<const Pose2> all = particles();
  const std::size_t n = std::min(max, all.size());
  std::vector<Pose2> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(all[i * all.size() / n]);
  return out;
}

}  // namespace starnav
