// The recoveries: turn in place, back up, drive an arc (a car's), wait. Each moves the robot only while the map-level
// footprint check says the motion stays clear, looking at the map at most once per look period
// (the check looks 0.5 s ahead, ten control periods and more, so one look per period misses
// nothing).
#include <optional>
#include <type_traits>

#include "starnav/control/local_controller.hpp"
#include "starnav/control/recovery.hpp"
#include "starnav/core/angle.hpp"

namespace starnav {

namespace {

// The clear-ahead verdict for one motion, looked up anew at most once per look period.
class LookAhead {
 public:
  void forget() { t_ = -1e300; }
  bool clear(const RecoveryInput& in, const BodyTwist& twist) {
    if (t_ > -1e300 && in.t_s < t_ + in.look_period_s) return clear_;
    clear_ = in.motion == nullptr || in.motion->clear(in.pose, twist, 0.5);
    t_ = in.t_s;
    return clear_;
  }

 private:
  double t_ = -1e300;
  bool clear_ = false;
};

struct RotateConfig {
  double angle_rad = kPi / 2.0;
  double speed_radps = 0.5;
};

const ParamTable<RotateConfig>& rotate_params() {
  static const ParamTable<RotateConfig> table = [] {
    using C = RotateConfig;
    ParamTable<C> t;
    t.real("angle_deg", &C::angle_rad, open(0.0, 360.0), "deg", "turn in place this far (left if that is clear, else right)",
           kPi / 180.0);
    t.real("speed_degps", &C::speed_radps, positive(), "deg/s", "turning speed", kPi / 180.0);
    return t;
  }();
  return table;
}

class Rotate final : public Recovery {
 public:
  explicit Rotate(const RotateConfig& c) : c_(c) {}
  std::string_view name() const override { return "rotate"; }
  void start(const RecoveryInput& in) override {
    end_t_ = in.t_s + c_.angle_rad / c_.speed_radps;
    look_.forget();
    // The way that is clear for the whole turn, left first.
    sign_ = in.motion == nullptr || in.motion->clear(in.pose, {0.0, 0.0, c_.speed_radps}, end_t_ - in.t_s) ? 1.0 : -1.0;
  }
  std::optional<BodyTwist> step(const RecoveryInput& in) override {
    const BodyTwist w{0.0, 0.0, sign_ * c_.speed_radps};
    if (in.t_s < end_t_ && look_.clear(in, w)) return w;
    return std::nullopt;
  }

 private:
  RotateConfig c_;
  double end_t_ = 0.0, sign_ = 1.0;
  LookAhead look_;
};

struct BackUpConfig {
  double distance_m = 0.25;
  double speed_mps = 0.1;
};

const ParamTable<BackUpConfig>& back_up_params() {
  static const ParamTable<BackUpConfig> table = [] {
    using C = BackUpConfig;
    ParamTable<C> t;
    t.real("distance_m", &C::distance_m, open(0.0, 5.0), "m", "back up this far (while the footprint stays clear)");
    t.real("speed_mps", &C::speed_mps, open(0.0, 2.0), "m/s", "backing speed");
    return t;
  }();
  return table;
}

class BackUp final : public Recovery {
 public:
  explicit BackUp(const BackUpConfig& c) : c_(c) {}
  std::string_view name() const override { return "back_up"; }
  void start(const RecoveryInput& in) override {
    end_t_ = in.t_s + c_.distance_m / c_.speed_mps;
    look_.forget();
  }
  std::optional<BodyTwist> step(const RecoveryInput& in) override {
    const BodyTwist b{-c_.speed_mps, 0.0, 0.0};
    if (in.t_s < end_t_ && look_.clear(in, b)) return b;
    return std::nullopt;
  }

 private:
  BackUpConfig c_;
  double end_t_ = 0.0;
  LookAhead look_;
};

struct DriveArcConfig {
  double distance_m = 0.3;
  double speed_mps = 0.1;
  double radius_m = 0.0;
};

const ParamTable<DriveArcConfig>& drive_arc_params() {
  static const ParamTable<DriveArcConfig> table = [] {
    using C = DriveArcConfig;
    ParamTable<C> t;
    t.real("distance_m", &C::distance_m, open(0.0, 5.0), "m", "drive this far along the arc (while the footprint stays clear)");
    t.real("speed_mps", &C::speed_mps, open(0.0, 2.0), "m/s", "driving speed");
    t.real("radius_m", &C::radius_m, non_negative(), "m",
           "the arc's radius; 0: the robot's minimum turning radius (0.5 m for a robot that turns in place)");
    return t;
  }();
  return table;
}

// A car cannot turn in place: it changes its heading, and leaves a place it is stuck in, by arcs.
// Backwards first (a car is most often stuck nose-in), turning to whichever side is clear for the
// whole arc, else forwards the same way; nothing when no arc is clear.
class DriveArc final : public Recovery {
 public:
  DriveArc(const DriveArcConfig& c, const RecoveryContext& ctx)
      : c_(c), radius_(c.radius_m > 0.0 ? c.radius_m : min_turning_radius_of(ctx.robot) > 0.0 ? min_turning_radius_of(ctx.robot) : 0.5) {}
  std::string_view name() const override { return "drive_arc"; }
  void start(const RecoveryInput& in) override {
    const double duration = c_.distance_m / c_.speed_mps;
    end_t_ = in.t_s + duration;
    look_.forget();
    twist_.reset();
    for (const double vx : {-c_.speed_mps, c_.speed_mps})
      for (const double side : {1.0, -1.0}) {
        const BodyTwist t{vx, 0.0, side * c_.speed_mps / radius_};
        if (in.motion == nullptr || in.motion->clear(in.pose, t, duration)) {
          twist_ = t;
          return;
        }
      }
  }
  std::optional<BodyTwist> step(const RecoveryInput& in) override {
    if (twist_ && in.t_s < end_t_ && look_.clear(in, *twist_)) return *twist_;
    return std::nullopt;
  }

 private:
  DriveArcConfig c_;
  double radius_ = 0.5;
  double end_t_ = 0.0;
  std::optional<BodyTwist> twist_;
  LookAhead look_;
};

struct WaitConfig {
  double duration_s = 2.0;
};

const ParamTable<WaitConfig>& wait_params() {
  static const ParamTable<WaitConfig> table = [] {
    using C = WaitConfig;
    ParamTable<C> t;
    t.real("duration_s", &C::duration_s, open(0.0, 3600.0), "s", "stand still this long (a person may move away)");
    return t;
  }();
  return table;
}

class Wait final : public Recovery {
 public:
  explicit Wait(const WaitConfig& c) : c_(c) {}
  std::string_view name() const override { return "wait"; }
  void start(const RecoveryInput& in) override { end_t_ = in.t_s + c_.duration_s; }
  std::optional<BodyTwist> step(const RecoveryInput& in) override {
    if (in.t_s < end_t_) return BodyTwist{};
    return std::nullopt;
  }

 private:
  WaitConfig c_;
  double end_t_ = 0.0;
};

template <class Config, class Impl>
RecoveryDef recovery_def(const char* name, const char* summary, const ParamTable<Config>& (*params)()) {
  RecoveryDef d;
  d.info.role = Role::Recovery;
  d.info.name = name;
  d.info.section = name;
  d.info.summary = summary;
  d.info.params = params().specs();
  d.make = [params](const RecoveryContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Recovery> {
    // A recovery that depends on the robot (drive_arc's radius) is given its context too.
    if constexpr (std::is_constructible_v<Impl, const Config&, const RecoveryContext&>)
      return std::make_unique<Impl>(configured(params(), settings, ctx.file), ctx);
    else
      return std::make_unique<Impl>(configured(params(), settings, ctx.file));
  };
  return d;
}

}  // namespace

RecoveryDef rotate_recovery() {
  return recovery_def<RotateConfig, Rotate>("rotate", "Turn in place (left if clear, else right) while the footprint stays clear",
                                            rotate_params);
}
RecoveryDef back_up_recovery() {
  return recovery_def<BackUpConfig, BackUp>("back_up", "Back up straight while the footprint stays clear", back_up_params);
}
RecoveryDef drive_arc_recovery() {
  return recovery_def<DriveArcConfig, DriveArc>(
      "drive_arc", "Drive an arc (backwards, else forwards; either side) while the footprint stays clear: a car's recovery",
      drive_arc_params);
}
RecoveryDef wait_recovery() {
  return recovery_def<WaitConfig, Wait>("wait", "Stand still for a while", wait_params);
}

}  // namespace starnav
