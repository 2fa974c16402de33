// The ground-truth localizer: the simulator's true pose, optionally with independent Gaussian
// noise per axis (a stand-in for a localizer of known accuracy). With zero noise the navigation
// loop sees exactly what it saw before localizers existed.
#include <memory>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/localizer.hpp"

namespace starnav {

namespace {

struct GroundTruthConfig {
  double sigma_xy_m = 0.0;
  double sigma_yaw_rad = 0.0;
};

const ParamTable<GroundTruthConfig>& ground_truth_params() {
  static const ParamTable<GroundTruthConfig> table = [] {
    using C = GroundTruthConfig;
    ParamTable<C> t;
    t.real("sigma_xy_m", &C::sigma_xy_m, closed(0.0, 10.0), "m", "standard deviation of the noise on x and on y");
    t.real("sigma_yaw_deg", &C::sigma_yaw_rad, closed(0.0, 180.0), "deg", "standard deviation of the noise on yaw",
           kPi / 180.0);
    return t;
  }();
  return table;
}

// Its own random stream of the scenario's seed (the simulator's sensors use forks 1-4).
constexpr std::uint64_t kNoiseStream = 101;

class GroundTruthLocalizer final : public Localizer {
 public:
  GroundTruthLocalizer(const GroundTruthConfig& c, const LocalizerContext& ctx)
      : c_(c), rng_(Rng(ctx.seed).fork(kNoiseStream)) {
    estimate_.pose = ctx.start;
  }
  std::string_view name() const override { return "ground_truth"; }
  void on_ground_truth(double t_s, const Pose2& pose) override {
    estimate_.t_s = t_s;
    estimate_.pose = pose;
    if (c_.sigma_xy_m > 0.0 || c_.sigma_yaw_rad > 0.0) {
      estimate_.pose.x += c_.sigma_xy_m * rng_.normal();
      estimate_.pose.y += c_.sigma_xy_m * rng_.normal();
      estimate_.pose.yaw = wrap_angle(estimate_.pose.yaw + c_.sigma_yaw_rad * rng_.normal());
    }
    estimate_.covariance = Eigen::Vector3d(c_.sigma_xy_m * c_.sigma_xy_m, c_.sigma_xy_m * c_.sigma_xy_m,
                                           c_.sigma_yaw_rad * c_.sigma_yaw_rad)
                               .asDiagonal();
    estimate_.valid = true;
  }
  PoseEstimate estimate() const override { return estimate_; }

 private:
  GroundTruthConfig c_;
  Rng rng_;
  PoseEstimate estimate_;
};

}  // namespace

LocalizerDef ground_truth_localizer() {
  LocalizerDef d;
  d.info.role = Role::Localizer;
  d.info.name = "ground_truth";
  d.info.section = "ground_truth";
  d.info.summary = "The simulator's true pose, with optional Gaussian noise (simulation only)";
  d.info.params = ground_truth_params().specs();
  d.make = [](const LocalizerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Localizer> {
    return std::make_unique<GroundTruthLocalizer>(configured(ground_truth_params(), settings, ctx.file), ctx);
  };
  return d;
}

}  // namespace starnav
