#include "starnav/sim/vehicle.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

constexpr double kProbeSpacing = 0.01;  // m: no body point moves further within one sub-step
constexpr double kLineSpacing = 0.1;    // m: spacing of the test lines across the body's faces
constexpr double kBumperRange = 0.01;   // m: an obstacle this close to the front face is a contact
constexpr int kBisections = 5;          // a blocked sub-step is cut to 1/32
constexpr int kMaxSubsteps = 100000;
constexpr double kGravity = 9.81;         // m/s^2
constexpr double kRoughnessRef = 0.01;    // m: contact-plane RMS residual that gives the full slip sigma
constexpr double kMaxRoughnessScale = 3.0;

// The pose reached from `p` after `t` seconds of constant body twist `v` (exact arc) plus a
// constant world-frame drift.
Pose2 advance(const Pose2& p, const BodyTwist& v, const Vec2& drift, double t) {
  const Pose2 q = advance_on_arc(p, v.vx, v.vy, v.wz, t);
  return {q.x + drift.x() * t, q.y + drift.y() * t, q.yaw};
}

bool overlaps(const Aabb& a, const Aabb& b) {
  return a.lo.x() <= b.hi.x() && b.lo.x() <= a.hi.x() && a.lo.y() <= b.hi.y() && b.lo.y() <= a.hi.y() &&
         a.lo.z() <= b.hi.z() && b.lo.z() <= a.hi.z();
}

bool finite_twist(const BodyTwist& v) { return std::isfinite(v.vx) && std::isfinite(v.vy) && std::isfinite(v.wz); }

}  // namespace

void VehicleConfig::validate() const {
  robot.validate();
  if (!(std::isfinite(friction) && friction >= 0.0)) throw Error("must be finite and >= 0", {}, 0, "vehicle.friction");
  if (!(std::isfinite(rough_slip_sigma) && rough_slip_sigma >= 0.0))
    throw Error("must be finite and >= 0", {}, 0, "vehicle.rough_slip_sigma");
}

Vehicle::Vehicle(const World& world, const VehicleConfig& config, const Pose2& start, Rng rng, double t0)
    : world_(&world), config_(config), drive_(config.robot), rng_(rng) {
  config_.validate();
  if (!std::isfinite(start.x) || !std::isfinite(start.y) || !std::isfinite(start.yaw))
    throw Error("start pose must be finite", {}, 0, "start");
  contacts_ = drive_.model().wheel_contacts();
  if (contacts_.size() != here_.wheel_z.size()) throw Error("robot model must have 4 contact points", {}, 0, "robot");

  // The body box and the lines on it that the collision test checks (see docs/simulator.md).
  const RobotConfig& rc = config_.robot;
  const double a = 0.5 * rc.body_length_m, b = 0.5 * rc.body_width_m;
  const double z0 = rc.ground_clearance_m, z1 = z0 + rc.body_height_m, zm = 0.5 * (z0 + z1);
  int k = 0;
  for (const double x : {-a, a})
    for (const double y : {-b, b})
      for (const double z : {z0, z1}) corners_[static_cast<std::size_t>(k++)] = Vec3(x, y, z);
  // Everything below is built about the body's centre, then shifted to base_link.
  const Vec2 centre = drive_.model().body_center();
  const Vec3 shift(centre.x(), centre.y(), 0.0);
  reach_m_ = 0.0;
  for (Vec3& c : corners_) {
    c += shift;
    reach_m_ = std::max(reach_m_, std::hypot(c.x(), c.y()));
  }
  for (const Vec2& c : contacts_) reach_m_ = std::max(reach_m_, c.norm());
  const Vec3 ux = Vec3::UnitX(), uy = Vec3::UnitY(), uz = Vec3::UnitZ();
  const double L = rc.body_length_m, W = rc.body_width_m, H = rc.body_height_m;
  for (const double z : {z0, zm, z1}) {
    for (const double y : {-b, b}) body_segments_.push_back({Vec3(-a, y, z), ux, L});
    for (const double x : {-a, a}) body_segments_.push_back({Vec3(x, -b, z), uy, W});
  }
  const int nx = std::max(1, static_cast<int>(std::ceil(L / kLineSpacing)));
  const int ny = std::max(1, static_cast<int>(std::ceil(W / kLineSpacing)));
  for (int i = 0; i <= ny; ++i) {
    const double y = -b + W * i / ny;
    if (i > 0 && i < ny) body_segments_.push_back({Vec3(-a, y, z0), ux, L});  // across the bottom
    for (const double x : {-a, a}) body_segments_.push_back({Vec3(x, y, z0), uz, H});  // up the front and rear
    for (const double z : {z0, zm, z1}) bumper_segments_.push_back({Vec3(a, y, z), ux, kBumperRange});
  }
  for (int i = 1; i < nx; ++i) {
    const double x = -a + L * i / nx;
    body_segments_.push_back({Vec3(x, -b, z0), uy, W});
    for (const double y : {-b, b}) body_segments_.push_back({Vec3(x, y, z0), uz, H});  // up the sides
  }
  for (const double z : {z0, zm, z1}) bumper_segments_.push_back({Vec3(a + kBumperRange, -b, z), uy, W});
  for (Segment& seg : body_segments_) seg.origin += shift;
  for (Segment& seg : bumper_segments_) seg.origin += shift;

  const std::vector<Obstacle>& obstacles = world.obstacles();
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const Obstacle& o = obstacles[i];
    if (o.moving()) {
      moving_obstacles_.push_back(static_cast<int>(i));
      continue;
    }
    for (std::size_t j = 0; j < o.parts.size(); ++j) {
      PosedPrimitive p = pose_primitive(o.parts[j]);
      p.appear = o.appear;
      p.disappear = o.disappear;
      p.obstacle = static_cast<int>(i);
      p.part = static_cast<int>(j);
      static_parts_.push_back(p);
    }
  }

  Block block;
  if (!place(start, t0, here_, block))
    throw Error("no ground under a wheel at the start pose (" + format_number(start.x) + ", " +
                    format_number(start.y) + ")",
                {}, 0, "start");
  state_.t_s = t0;
  state_.pose = here_.pose;
  state_.wheel_angle_rad.assign(static_cast<std::size_t>(drive_.model().actuator_count()), 0.0);
  state_.wheel_speed_radps = state_.wheel_angle_rad;
  bumper_ = front_contact(here_.pose, t0);
}

void Vehicle::teleport(const Pose2& to, double t) {
  if (!std::isfinite(to.x) || !std::isfinite(to.y) || !std::isfinite(to.yaw))
    throw Error("the target pose must be finite", {}, 0, "teleport");
  Placement target;
  Block block;
  if (!place(to, t, target, block)) throw Error("no ground under a wheel at the target", {}, 0, "teleport");
  refresh_moving(t);
  if (body_overlap(target.pose, t, block))
    throw Error("the body would overlap " + block.detail + " at the target", {}, 0, "teleport");
  here_ = target;
  drive_.reset();
  slide_velocity_ = Vec2::Zero();
  last_block_.clear();
  state_.t_s = t;
  state_.pose = here_.pose;
  state_.twist = {};
  std::fill(state_.wheel_speed_radps.begin(), state_.wheel_speed_radps.end(), 0.0);
  bumper_ = front_contact(here_.pose, t);
}

double Vehicle::ground(double x, double y, double t) const {
  const double h = world_->surface_height(x, y, t);
  // Without a terrain the ground is the plane z = 0 (obstacles stand on it).
  if (!world_->terrain()) return std::isnan(h) ? 0.0 : std::max(0.0, h);
  return h;
}

bool Vehicle::place(const Pose2& planar, double t, Placement& out, Block& block) const {
  out.planar = planar;
  Vec3 pts[4];
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec2 w = planar.transform(contacts_[i]);
    const double h = ground(w.x(), w.y(), t);
    if (std::isnan(h)) {
      block = {"off_terrain", "wheel " + std::to_string(i) + " has no ground under it", w, "off_terrain"};
      return false;
    }
    out.wheel_z[i] = h;
    pts[i] = Vec3(contacts_[i].x(), contacts_[i].y(), h);
  }
  // Least-squares plane through the contacts in the heading frame; base_link sits on it.
  out.plane = fit_plane(pts);
  const Attitude att = attitude_from_slopes(out.plane.px, out.plane.py);
  out.pose = Pose3::from_rpy(Vec3(planar.x, planar.y, out.plane.z0), att.roll, att.pitch, planar.yaw);
  return true;
}

void Vehicle::refresh_moving(double t) {
  if (moving_obstacles_.empty() || t == moving_time_) return;
  moving_time_ = t;
  moving_parts_.clear();
  const std::vector<Obstacle>& obstacles = world_->obstacles();
  for (const int i : moving_obstacles_) {
    const Obstacle& o = obstacles[static_cast<std::size_t>(i)];
    if (!o.exists_at(t)) continue;
    const Vec3 offset = o.offset_at(t);
    for (std::size_t j = 0; j < o.parts.size(); ++j) {
      PosedPrimitive p = pose_primitive(translated(o.parts[j], offset));
      p.appear = o.appear;
      p.disappear = o.disappear;
      p.obstacle = i;
      p.part = static_cast<int>(j);
      moving_parts_.push_back(p);
    }
  }
}

// Candidates: primitives existing at t whose bounds meet the body's bounds grown by the bumper
// range. Exact tests: every body corner inside a primitive, every test line crossing its boundary.
bool Vehicle::body_overlap(const Pose3& pose, double t, Block& block) {
  refresh_moving(t);
  const Eigen::Matrix3d r = pose.rotation();
  Vec3 corners[8];
  Aabb box;
  for (std::size_t i = 0; i < 8; ++i) {
    corners[i] = pose.position + r * corners_[i];
    box.extend(corners[i]);
  }
  box.lo.array() -= kBumperRange;
  box.hi.array() += kBumperRange;
  candidates_.clear();
  for (const PosedPrimitive& p : static_parts_)
    if (p.exists_at(t) && overlaps(box, p.box)) candidates_.push_back(&p);
  for (const PosedPrimitive& p : moving_parts_)
    if (overlaps(box, p.box)) candidates_.push_back(&p);
  for (const PosedPrimitive* p : candidates_) {
    const auto hit_at = [&](const Vec3& where) {
      const std::string& name = world_->obstacles()[static_cast<std::size_t>(p->obstacle)].name;
      block = {"collision", name.empty() ? "obstacle " + std::to_string(p->obstacle) : name,
               Vec2(where.x(), where.y()), "collision:" + std::to_string(p->obstacle)};
      return true;
    };
    for (const Vec3& c : corners)
      if (contains(*p, c)) return hit_at(c);
    for (const Segment& s : body_segments_) {
      const Vec3 o = pose.position + r * s.origin, d = r * s.dir;
      PrimitiveHit hit;
      if (intersect(*p, o, d, s.length, hit)) return hit_at(o + hit.distance * d);
    }
  }
  return false;
}

// Uses the candidates of the last body_overlap() call at the same pose (bounds include the range).
bool Vehicle::front_contact(const Pose3& pose, double t) {
  Block unused;
  if (body_overlap(pose, t, unused)) return true;  // touching or overlapping counts as contact
  const Eigen::Matrix3d r = pose.rotation();
  for (const PosedPrimitive* p : candidates_)
    for (const Segment& s : bumper_segments_) {
      const Vec3 o = pose.position + r * s.origin, d = r * s.dir;
      PrimitiveHit hit;
      if (contains(*p, o) || intersect(*p, o, d, s.length, hit)) return true;
    }
  return false;
}

bool Vehicle::admissible(const Placement& from, const Placement& to, double t, Block& block) {
  for (std::size_t i = 0; i < 4; ++i) {
    const double rise = to.wheel_z[i] - from.wheel_z[i];
    if (rise > config_.robot.max_step_m) {
      const Vec2 w = to.planar.transform(contacts_[i]);
      block = {"step", "wheel " + std::to_string(i) + " meets a step of " + std::to_string(rise) + " m", w,
               "step:" + std::to_string(i)};
      return false;
    }
  }
  return !body_overlap(to.pose, t, block);
}

void Vehicle::step(const BodyTwist& command, double dt, std::vector<VehicleEvent>& events) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("time step must be finite and > 0", {}, 0, "dt");
  if (!finite_twist(command)) throw Error("command twist must be finite", {}, 0, "command");
  const std::size_t n_act = state_.wheel_speed_radps.size();
  drive_.step(command, dt);
  // The mean actuator values over the step give the twist to integrate (and the wheel angles),
  // then slip on rough ground.
  const std::span<const double> mean = drive_.actuator_mean();
  BodyTwist motion = drive_.model().forward(mean);
  if (config_.rough_slip_sigma > 0.0) {
    const double s =
        config_.rough_slip_sigma * std::min(here_.plane.rms_residual / kRoughnessRef, kMaxRoughnessScale);
    const double n1 = rng_.normal(), n2 = rng_.normal(), n3 = rng_.normal();
    motion.vx *= 1.0 + s * n1;
    motion.vy *= 1.0 + s * n2;
    motion.wz *= 1.0 + s * n3;
  }
  const double t_end = state_.t_s + dt;

  // Slide: Coulomb friction on the contact plane; beyond tan(slope) = friction the robot
  // accelerates downhill, below it an existing drift is braked.
  const double cy = std::cos(here_.planar.yaw), sy = std::sin(here_.planar.yaw);
  const Vec2 gradient(cy * here_.plane.px - sy * here_.plane.py, sy * here_.plane.px + cy * here_.plane.py);
  const double g = gradient.norm(), theta = std::atan(g);
  const bool was_sliding = slide_velocity_.squaredNorm() > 0.0;
  if (g > config_.friction) {
    const double accel = kGravity * (std::sin(theta) - config_.friction * std::cos(theta)) * std::cos(theta);
    slide_velocity_ -= gradient / g * (accel * dt);
  } else if (was_sliding) {
    const double decel = kGravity * (config_.friction * std::cos(theta) - std::sin(theta)) * std::cos(theta);
    const double speed = slide_velocity_.norm();
    slide_velocity_ *= std::max(0.0, speed - decel * dt) / speed;
  }
  if (!was_sliding && slide_velocity_.squaredNorm() > 0.0)
    events.push_back({state_.t_s, "slide",
                      "slope " + std::to_string(rad_to_deg(theta)) + " deg exceeds friction " +
                          std::to_string(config_.friction),
                      here_.planar.translation()});

  // Sub-steps along the arc so that no body point moves more than kProbeSpacing per sub-step.
  const Pose2 start = here_.planar;
  const Vec2 drift = slide_velocity_;
  const double travel = (std::hypot(motion.vx, motion.vy) + std::abs(motion.wz) * reach_m_ + drift.norm()) * dt;
  const int n = static_cast<int>(std::clamp(std::ceil(travel / kProbeSpacing), 1.0, double(kMaxSubsteps)));
  Placement last = here_, cand;
  Block block;
  const auto try_at = [&](double f) {
    return place(advance(start, motion, drift, f * dt), t_end, cand, block) && admissible(last, cand, t_end, block);
  };
  double done = 0.0;
  bool stopped = false;
  for (int k = 1; k <= n && !stopped; ++k) {
    const double f = static_cast<double>(k) / n;
    if (try_at(f)) {
      last = cand;
      done = f;
      continue;
    }
    stopped = true;
    Block first = block;  // report what stopped the full sub-step
    double hi = f;
    for (int i = 0; i < kBisections; ++i) {
      const double mid = 0.5 * (done + hi);
      if (try_at(mid)) {
        last = cand;
        done = mid;
      } else {
        hi = mid;
      }
    }
    block = first;
  }
  here_ = last;

  const double moved = done * dt;
  const bool ackermann = drive_.model().kind() == DriveKind::Ackermann;
  for (std::size_t i = 0; i < n_act; ++i) {
    const double after = drive_.actuator_state()[i];
    if (ackermann && i == 1)
      state_.wheel_angle_rad[i] = after;  // the steering angle itself
    else
      state_.wheel_angle_rad[i] += mean[i] * moved;
  }
  const Vec2 drift_body(cy * drift.x() + sy * drift.y(), -sy * drift.x() + cy * drift.y());
  state_.twist = {done * (motion.vx + drift_body.x()), done * (motion.vy + drift_body.y()), done * motion.wz};
  if (stopped) {
    // The impact stops the robot: wheels and drift to rest (the steering stays where it is).
    drive_.stop_wheels();
    slide_velocity_ = Vec2::Zero();
    if (block.key != last_block_) events.push_back({t_end, block.kind, block.detail, block.where});
    last_block_ = block.key;
  } else {
    last_block_.clear();
  }
  std::copy_n(drive_.actuator_state().begin(), n_act, state_.wheel_speed_radps.begin());
  state_.t_s = t_end;
  state_.pose = here_.pose;
  bumper_ = front_contact(here_.pose, t_end);
}

}  // namespace starnav
