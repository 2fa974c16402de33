// AMCL as a localizer (estimate/amcl): odometry poses in, scans of a 2D LiDAR weigh the particles,
// the pose out is map <- odom of the last filter update applied to the odometry now (as Nav2
// publishes the map -> odom transform), so the estimate moves smoothly between updates.
#include <algorithm>
#include <memory>
#include <optional>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/estimate/amcl.hpp"
#include "starnav/estimate/localizer.hpp"

namespace starnav {

namespace {

struct AmclLocalizerConfig {
  AmclConfig filter;
  std::string initial = "start";  // start | global
  std::string robot_model = "auto";
};

const ParamTable<AmclLocalizerConfig>& amcl_localizer_params() {
  static const ParamTable<AmclLocalizerConfig> table = [] {
    using C = AmclLocalizerConfig;
    ParamTable<C> t;
    const auto f = [](double AmclConfig::*m) { return [m](C& c) -> double& { return c.filter.*m; }; };
    const auto i = [](int AmclConfig::*m) { return [m](C& c) -> int& { return c.filter.*m; }; };
    t.choice("initial", {"start", "global"}, [](C& c, const std::string& v) { c.initial = v; },
             [](const C& c) { return c.initial; },
             "start: a Gaussian cloud around the scenario's start; global: particles over the whole free space");
    t.choice("robot_model_type", {"auto", "differential", "omnidirectional"}, [](C& c, const std::string& v) { c.robot_model = v; },
             [](const C& c) { return c.robot_model; }, "odometry motion model; auto: omnidirectional for a Mecanum base");
    t.real("alpha1", f(&AmclConfig::alpha1), closed(0.0, 10.0), "-", "rotation noise from rotation");
    t.real("alpha2", f(&AmclConfig::alpha2), closed(0.0, 10.0), "-", "rotation noise from translation");
    t.real("alpha3", f(&AmclConfig::alpha3), closed(0.0, 10.0), "-", "translation noise from translation");
    t.real("alpha4", f(&AmclConfig::alpha4), closed(0.0, 10.0), "-", "translation noise from rotation");
    t.real("alpha5", f(&AmclConfig::alpha5), closed(0.0, 10.0), "-", "strafe noise from translation (omnidirectional)");
    t.choice("laser_model_type", {"likelihood_field", "beam"},
             [](C& c, const std::string& v) { c.filter.laser_model = v == "beam" ? LaserModelType::Beam : LaserModelType::LikelihoodField; },
             [](const C& c) { return std::string(c.filter.laser_model == LaserModelType::Beam ? "beam" : "likelihood_field"); },
             "laser model");
    t.real("z_hit", f(&AmclConfig::z_hit), closed(0.0, 1.0), "-", "weight of the hit term");
    t.real("z_rand", f(&AmclConfig::z_rand), closed(0.0, 1.0), "-", "weight of random readings");
    t.real("z_short", f(&AmclConfig::z_short), closed(0.0, 1.0), "-", "weight of short readings (beam model)");
    t.real("z_max", f(&AmclConfig::z_max), closed(0.0, 1.0), "-", "weight of max-range readings (beam model)");
    t.real("sigma_hit_m", f(&AmclConfig::sigma_hit_m), closed(1e-4, 10.0), "m", "standard deviation of a hit");
    t.real("lambda_short", f(&AmclConfig::lambda_short), closed(0.0, 100.0), "1/m", "decay of short readings (beam model)");
    t.real("laser_likelihood_max_dist_m", f(&AmclConfig::laser_likelihood_max_dist_m), closed(1e-3, 100.0), "m",
           "distance to an obstacle beyond which the field is flat");
    t.real("laser_max_range_m", f(&AmclConfig::laser_max_range_m), closed(-1.0, 1000.0), "m", "<= 0: the LiDAR's");
    t.real("laser_min_range_m", f(&AmclConfig::laser_min_range_m), closed(-1.0, 1000.0), "m", "<= 0: the LiDAR's");
    t.integer("max_beams", i(&AmclConfig::max_beams), closed(2, 100000), "-", "beams used per scan");
    t.choice("field_reference", {"surface", "centre"},
             [](C& c, const std::string& v) { c.filter.field_reference = v == "centre" ? FieldReference::Centre : FieldReference::Surface; },
             [](const C& c) { return std::string(c.filter.field_reference == FieldReference::Centre ? "centre" : "surface"); },
             "distances to the occupied cells' squares (surface) or to their centres (centre: Nav2)");
    t.integer("min_particles", i(&AmclConfig::min_particles), closed(1, 1000000), "-", "fewest particles");
    t.integer("max_particles", i(&AmclConfig::max_particles), closed(1, 1000000), "-", "most particles");
    t.real("pf_err", f(&AmclConfig::pf_err), closed(1e-6, 1.0), "-", "KLD error bound");
    t.real("pf_z", f(&AmclConfig::pf_z), closed(1e-6, 10.0), "-", "KLD normal quantile (Nav2 passes 0.99 as z)");
    t.real("kld_bin_xy_m", f(&AmclConfig::kld_bin_xy_m), closed(1e-3, 100.0), "m", "KLD histogram bin size");
    t.real("kld_bin_yaw_deg", f(&AmclConfig::kld_bin_yaw_rad), closed(0.1, 180.0), "deg", "KLD histogram bin size",
           kPi / 180.0);
    t.choice("resampler", {"low_variance", "multinomial"},
             [](C& c, const std::string& v) { c.filter.resampler = v == "multinomial" ? Resampler::Multinomial : Resampler::LowVariance; },
             [](const C& c) { return std::string(c.filter.resampler == Resampler::Multinomial ? "multinomial" : "low_variance"); },
             "resampling scheme");
    t.boolean("selective_resampling", [](C& c) -> bool& { return c.filter.selective_resampling; },
              "resample only when the effective sample size falls below half the particles");
    t.integer("resample_interval", i(&AmclConfig::resample_interval), closed(1, 1000), "-", "filter updates per resampling");
    t.real("recovery_alpha_slow", f(&AmclConfig::recovery_alpha_slow), closed(0.0, 1.0), "-",
           "long-term likelihood average rate (0: no recovery)");
    t.real("recovery_alpha_fast", f(&AmclConfig::recovery_alpha_fast), closed(0.0, 1.0), "-",
           "short-term likelihood average rate (0: no recovery)");
    t.choice("recovery_reset", {"fast_to_slow", "zero"},
             [](C& c, const std::string& v) { c.filter.recovery_reset = v == "zero" ? RecoveryReset::Zero : RecoveryReset::FastToSlow; },
             [](const C& c) { return std::string(c.filter.recovery_reset == RecoveryReset::Zero ? "zero" : "fast_to_slow"); },
             "after an injection: the fast average set to the slow one, or both zeroed (Nav2; recovers rarely)");
    t.real("update_min_d_m", f(&AmclConfig::update_min_d_m), closed(0.0, 100.0), "m", "translation between filter updates");
    t.real("update_min_a_deg", f(&AmclConfig::update_min_a_rad), closed(0.0, 360.0), "deg", "rotation between filter updates",
           kPi / 180.0);
    t.real("initial_sigma_xy_m", f(&AmclConfig::initial_sigma_xy_m), closed(0.0, 100.0), "m", "initial cloud (initial: start)");
    t.real("initial_sigma_yaw_deg", f(&AmclConfig::initial_sigma_yaw_rad), closed(0.0, 180.0), "deg",
           "initial cloud (initial: start)", kPi / 180.0);
    t.boolean("search_phase", [](C& c) -> bool& { return c.filter.search_phase; },
              "after a global start or an injection, until converged: the search_* models (docs/localization.md)");
    t.real("search_alpha", f(&AmclConfig::search_alpha), closed(0.0, 10.0), "-", "search phase: every alpha at least this");
    t.real("search_z_hit", f(&AmclConfig::search_z_hit), closed(0.0, 1.0), "-", "search phase: z_hit");
    t.real("search_z_rand", f(&AmclConfig::search_z_rand), closed(0.0, 1.0), "-", "search phase: z_rand");
    t.real("search_sigma_hit_m", f(&AmclConfig::search_sigma_hit_m), closed(1e-4, 10.0), "m", "search phase: sigma_hit");
    t.real("search_independent_beams", f(&AmclConfig::search_independent_beams), closed(0.0, kMaxIndependentBeams), "-",
           "search phase: the scan counts as this many independent beams (tempered product of the beams); 0: Nav2's 1 + sum pz^3");
    t.integer("search_ramp_updates", i(&AmclConfig::search_ramp_updates), closed(0, 1000), "-",
              "search phase: the tempered product reaches full strength over this many updates, and the search lasts at least as long");
    t.boolean("search_holds_particles", [](C& c) -> bool& { return c.filter.search_holds_particles; },
              "search phase: the set keeps max_particles (KLD sizes it after the search)");
    t.real("search_end_sigma_m", f(&AmclConfig::search_end_sigma_m), closed(1e-3, 100.0), "m",
           "the search ends when one cluster holds converged_weight within this spread");
    t.boolean("scan_proposal", [](C& c) -> bool& { return c.filter.scan_proposal; },
              "global start and recovery draw the poses that best explain the scan, not uniform ones (docs/localization.md)");
    const auto pf = [](double ScanProposalConfig::*m) { return [m](C& c) -> double& { return c.filter.proposal.*m; }; };
    const auto pi = [](int ScanProposalConfig::*m) { return [m](C& c) -> int& { return c.filter.proposal.*m; }; };
    t.real("proposal_spacing_m", pf(&ScanProposalConfig::spacing_m), closed(0.01, 100.0), "m",
           "scan proposal: one candidate position per block of this size");
    t.real("proposal_yaw_step_deg", pf(&ScanProposalConfig::yaw_step_rad), closed(0.1, 360.0), "deg",
           "scan proposal: headings per position every this", kPi / 180.0);
    t.integer("proposal_coarse_beams", pi(&ScanProposalConfig::coarse_beams), closed(1, 100000), "-",
              "scan proposal: beams of the first scoring of every candidate");
    t.integer("proposal_refine", pi(&ScanProposalConfig::refine), closed(1, 10000), "-",
              "scan proposal: candidates rescored with every beam, per pose wanted");
    t.integer("proposal_max_candidates", pi(&ScanProposalConfig::max_candidates), closed(1, 100000000), "-",
              "scan proposal: candidates a global start scores at most (a random subset of the positions above it)");
    t.integer("proposal_injection_candidates", pi(&ScanProposalConfig::injection_candidates), closed(1, 100000000), "-",
              "scan proposal: candidates an injection scores at most");
    t.boolean("proposal_recovery", [](C& c) -> bool& { return c.filter.proposal.recovery; },
              "scan proposal: the recovery draws from the scan too (default false: uniform free poses, as Nav2; docs/localization.md)");
    t.integer("proposal_injection_pool", pi(&ScanProposalConfig::injection_pool), closed(1, 1000000), "-",
              "scan proposal: the recovery draws from this many best candidates");
    t.real("proposal_injection_margin", pf(&ScanProposalConfig::injection_margin), closed(0.0, 1e6), "-",
           "scan proposal: the recovery draws from the scan only when its best candidate fits this many times better than the best particle");
    t.choice("proposal_injection_gate", {"search", "tracking"},
             [](C& c, const std::string& v) {
               c.filter.proposal.injection_gate = v == "tracking" ? ScanProposalConfig::Gate::Tracking : ScanProposalConfig::Gate::Search;
             },
             [](const C& c) {
               return std::string(c.filter.proposal.injection_gate == ScanProposalConfig::Gate::Tracking ? "tracking" : "search");
             },
             "scan proposal: the likelihood that margin is measured in: the search phase's (the tempered product) or the tracking field's");
    t.real("converged_weight", f(&AmclConfig::converged_weight), closed(0.0, 1.0), "-",
           "converged: the best cluster holds at least this share of the weight ...");
    t.real("converged_sigma_m", f(&AmclConfig::converged_sigma_m), closed(0.0, 100.0), "m",
           "... and its position standard deviation is at most this");
    return t;
  }();
  return table;
}

// Its own random stream of the scenario's seed (ground_truth 101, ekf 103).
constexpr std::uint64_t kAmclStream = 102;

class AmclLocalizer final : public Localizer {
 public:
  AmclLocalizer(const AmclLocalizerConfig& c, const LocalizerContext& ctx) : start_(ctx.start), odometry_(ctx.start) {
    config_ = c.filter;
    const bool omni = c.robot_model == "omnidirectional" ||
                      (c.robot_model == "auto" && ctx.robot && ctx.robot->drive == DriveKind::Mecanum);
    config_.robot_model = omni ? MotionModelType::Omnidirectional : MotionModelType::Differential;
    config_.validate();
    if (ctx.laser_lines > 1) throw Error("amcl needs a 2D LiDAR (one line)", {}, 0, "sensors.lidar");
    if (!ctx.map) return;  // checked for its parameters only; a scan without a map is an error
    amcl_.emplace(*ctx.map, ctx.thresholds, config_, ctx.laser_in_base, Rng(ctx.seed).fork(kAmclStream).next());
    if (c.initial == "global")
      amcl_->initialize_global();
    else
      amcl_->initialize(ctx.start);
  }
  std::string_view name() const override { return "amcl"; }
  void on_odometry(const OdometryMessage& o) override {
    odometry_ = o.pose;
    odometry_t_s_ = o.header.t_s;
    twist_ = o.twist;
    has_odometry_ = true;
  }
  void on_scan(const ScanMessage& scan) override {
    if (!amcl_) throw Error("amcl needs a map (world.occupancy_map or localization.map)", {}, 0, "localization.map");
    scan_.ranges.assign(scan.ranges_m.begin(), scan.ranges_m.end());
    scan_.angles_rad.resize(scan.ranges_m.size());
    for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) scan_.angles_rad[i] = scan.angle(i);
    scan_.range_min_m = scan.range_min_m;
    scan_.range_max_m = scan.range_max_m;
    // Each stream is a scanner of its own: the first is the robot's laser (its mount given when
    // built), the others carry theirs.
    auto stream = std::find(streams_.begin(), streams_.end(), scan.header.stream);
    if (stream == streams_.end()) {
      if (streams_.size() == kMaxAmclSensors)
        throw Error("more than " + std::to_string(kMaxAmclSensors) + " scan streams", {}, 0, "sensors.lidars");
      stream = streams_.insert(streams_.end(), scan.header.stream);
    }
    scan_.sensor = static_cast<std::size_t>(stream - streams_.begin());
    scan_.laser_in_base.reset();
    if (scan_.sensor > 0) scan_.laser_in_base = scan.mount.to_pose2();
    amcl_->update(odometry_at(scan.header.t_s), scan_);
    t_s_ = scan.header.t_s;
  }
  PoseEstimate estimate() const override {
    PoseEstimate e;
    e.t_s = std::max(t_s_, odometry_t_s_);
    if (!amcl_) {
      e.pose = start_;
      return e;
    }
    const AmclEstimate& a = amcl_->estimate();
    e.pose = amcl_->pose_at(odometry_);
    e.covariance = a.covariance;
    e.valid = a.updates > 0;
    e.particles = a.particles;
    e.updates = a.updates;
    e.converged = a.converged;
    return e;
  }
  std::vector<Pose2> belief_samples(std::size_t max) const override {
    return amcl_ ? amcl_->particle_sample(max) : std::vector<Pose2>{};
  }

 private:
  // The odometry at the scan's time: the last sample moved on by its twist (they coincide when
  // the encoders sample at the scan's instant, as in the simulator).
  Pose2 odometry_at(double t_s) const {
    if (!has_odometry_ || t_s <= odometry_t_s_) return odometry_;
    return advance_on_arc(odometry_, twist_.vx, twist_.vy, twist_.wz, t_s - odometry_t_s_);
  }

  AmclConfig config_;
  Pose2 start_;
  std::optional<Amcl> amcl_;
  Pose2 odometry_;
  double odometry_t_s_ = 0.0;
  BodyTwist twist_;
  bool has_odometry_ = false;
  double t_s_ = 0.0;
  PlanarScan scan_;
  std::vector<std::string> streams_;  // the scan streams seen, in order (index = the filter's sensor)
};

}  // namespace

LocalizerDef amcl_localizer() {
  LocalizerDef d;
  d.info.role = Role::Localizer;
  d.info.name = "amcl";
  d.info.section = "amcl";
  d.info.summary = "Adaptive Monte Carlo localization on a known map (Nav2's AMCL: KLD sampling, recovery, global start)";
  d.info.capabilities = {Capability::NeedsMap};
  d.info.nav2_counterpart = "nav2_amcl::AmclNode";
  d.info.params = amcl_localizer_params().specs();
  d.make = [](const LocalizerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Localizer> {
    return std::make_unique<AmclLocalizer>(configured(amcl_localizer_params(), settings, ctx.file), ctx);
  };
  return d;
}

AmclConfig amcl_config_from_settings(std::span<const ParamSetting> settings, const std::string& file) {
  const AmclLocalizerConfig c = configured(amcl_localizer_params(), settings, file);
  AmclConfig config = c.filter;
  config.robot_model = c.robot_model == "omnidirectional" ? MotionModelType::Omnidirectional : MotionModelType::Differential;
  try {
    config.validate();
  } catch (const Error& e) {
    rethrow_at_setting(e, settings, file);
  }
  return config;
}

}  // namespace starnav
