#include "starnav/plan/car_curves.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {
namespace {

using Kind = CurveSegmentKind;
constexpr Kind kL = Kind::kLeft;
constexpr Kind kS = Kind::kStraight;
constexpr Kind kR = Kind::kRight;
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kTwoPi = 2.0 * kPi;

// How far below zero a length in units of R may fall and still count as zero: the formulas' round-off
// (a few ulps) must not reject an exact solution.
constexpr double kSignTolerance = 1e-10;
// Segments shorter than this (units of R) are dropped from a path.
constexpr double kZeroSegment = 1e-10;

// A word in units of R: the kinds and signed lengths of up to five segments.
struct Word {
  std::array<Kind, 5> kinds{};
  std::array<double, 5> lengths{};
  std::size_t count = 0;

  void push(Kind kind, double length) {
    kinds[count] = kind;
    lengths[count] = length;
    ++count;
  }
  double length() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) sum += std::abs(lengths[i]);
    return sum;
  }
};

Word word3(Kind a, double la, Kind b, double lb, Kind c, double lc) {
  Word w;
  w.push(a, la);
  w.push(b, lb);
  w.push(c, lc);
  return w;
}

// The goal in the start's frame, in units of R: (x, y, phi).
struct Local {
  double x = 0.0, y = 0.0, phi = 0.0;
};

Local to_local(const Pose2& start, const Pose2& goal, double radius) {
  const Vec2 p = start.inverse_transform(goal.translation()) / radius;
  return {p.x(), p.y(), wrap_angle(goal.yaw - start.yaw)};
}

void check_query(const Pose2& start, const Pose2& goal, double radius) {
  if (!(std::isfinite(radius) && radius > 0.0))
    throw Error("car curves: the turning radius must be positive and finite, got " + std::to_string(radius), {}, 0,
                "radius");
  for (const Pose2* p : {&start, &goal})
    if (!(std::isfinite(p->x) && std::isfinite(p->y) && std::isfinite(p->yaw)))
      throw Error("car curves: a pose is not finite", {}, 0, p == &start ? "start" : "goal");
}

// Drives `length` metres (signed) of a segment of `kind` from `pose`.
Pose2 advance(const Pose2& pose, Kind kind, double length, double radius) {
  if (kind == kS) return {pose.x + length * std::cos(pose.yaw), pose.y + length * std::sin(pose.yaw), pose.yaw};
  const double kappa = (kind == kL ? 1.0 : -1.0) / radius;
  const double yaw1 = pose.yaw + kappa * length;
  return {pose.x + (std::sin(yaw1) - std::sin(pose.yaw)) / kappa,
          pose.y + (std::cos(pose.yaw) - std::cos(yaw1)) / kappa, wrap_angle(yaw1)};
}

// The path of a word: scaled to metres, zero segments dropped, equal neighbours merged.
CarPath make_path(const Pose2& start, double radius, const Word& word) {
  CarPath path;
  path.start = start;
  path.radius = radius;
  for (std::size_t i = 0; i < word.count; ++i) {
    const double l = word.lengths[i];
    if (std::abs(l) < kZeroSegment) continue;
    if (path.segment_count > 0) {
      CurveSegment& last = path.segments[path.segment_count - 1];
      if (last.kind == word.kinds[i] && (last.length > 0.0) == (l > 0.0)) {
        last.length += l * radius;
        continue;
      }
    }
    path.segments[path.segment_count++] = {word.kinds[i], l * radius};
  }
  for (std::size_t i = 0; i < path.segment_count; ++i) path.length += std::abs(path.segments[i].length);
  return path;
}

// ---- Dubins ----------------------------------------------------------------------------------------

// An angle in [0, 2 pi), with values a round-off below 2 pi taken as 0 (a full turn is never meant).
double turn_angle(double a) {
  double r = std::fmod(a, kTwoPi);
  if (r < 0.0) r += kTwoPi;
  if (r > kTwoPi - kSignTolerance) r = 0.0;
  return r;
}

// The forward words that start with a left turn, from the tangents between the unit turning
// circles: the start's left circle is centred at (0, 1), the goal's left circle at
// (x - sin phi, y + cos phi) and its right circle at (x + sin phi, y - cos phi). A point on a left
// circle of centre c with heading h lies at c + (sin h, -cos h); on a right circle at c + (-sin h, cos h).
template <class Visit>
void dubins_left_words(const Local& g, Visit&& visit) {
  const double sp = std::sin(g.phi), cp = std::cos(g.phi);
  {  // LSL: the outer tangent between the two left circles, parallel to their centre line.
    const double dx = g.x - sp, dy = g.y - 1.0 + cp;
    const double h = std::atan2(dy, dx);
    visit(word3(kL, turn_angle(h), kS, std::hypot(dx, dy), kL, turn_angle(g.phi - h)));
  }
  {  // LSR: the inner tangent from the start's left circle to the goal's right circle.
    const double dx = g.x + sp, dy = g.y - 1.0 - cp;
    const double d2 = dx * dx + dy * dy;
    if (d2 >= 4.0) {
      const double u = std::sqrt(d2 - 4.0);
      const double h = std::atan2(dy, dx) + std::atan2(2.0, u);
      visit(word3(kL, turn_angle(h), kS, u, kR, turn_angle(h - g.phi)));
    }
  }
  {  // LRL: a right circle touching both left circles (two choices, on either side of their centre line).
    const double dx = g.x - sp, dy = g.y - 1.0 + cp;
    const double d = std::hypot(dx, dy);
    if (d <= 4.0) {
      const double theta = std::atan2(dy, dx), spread = std::acos(std::min(1.0, d / 4.0));
      for (const double gamma : {theta + spread, theta - spread}) {
        // Middle circle centre c1 = (0, 1) + 2 (cos gamma, sin gamma); goal left centre c2 = (0, 1) + (dx, dy).
        const double h1 = gamma + kHalfPi;
        const double delta = std::atan2(dy - 2.0 * std::sin(gamma), dx - 2.0 * std::cos(gamma));
        const double h2 = delta - kHalfPi;
        visit(word3(kL, turn_angle(h1), kR, turn_angle(h1 - h2), kL, turn_angle(g.phi - h2)));
      }
    }
  }
}

Word reflected(Word w) {
  for (std::size_t i = 0; i < w.count; ++i) w.kinds[i] = w.kinds[i] == kL ? kR : w.kinds[i] == kR ? kL : kS;
  return w;
}

template <class Visit>
void dubins_words(const Local& g, Visit&& visit) {
  dubins_left_words(g, visit);
  // Mirrored in the x axis, left and right swap: the words starting with a right turn.
  dubins_left_words(Local{g.x, -g.y, -g.phi}, [&](const Word& w) { visit(reflected(w)); });
}

// ---- Reeds-Shepp -----------------------------------------------------------------------------------
// The base formulas of Reeds & Shepp 1990, section 8 (with the corrections of 8.3/8.4 and 8.11 that
// OMPL documents), each for the goal (x, y, phi) in units of R. Notation: L+ a left turn forward,
// R- a right turn in reverse; t, u, v the segment lengths.

void polar(double x, double y, double& r, double& theta) {
  r = std::hypot(x, y);
  theta = std::atan2(y, x);
}

// The paper's tau and omega for the CCCC words (8.7, 8.8).
void tau_omega(double u, double v, double xi, double eta, double phi, double& tau, double& omega) {
  const double delta = wrap_angle(u - v);
  const double a = std::sin(u) - std::sin(delta), b = std::cos(u) - std::cos(delta) - 1.0;
  const double t1 = std::atan2(eta * a - xi * b, xi * a + eta * b);
  const double t2 = 2.0 * (std::cos(delta) - std::cos(v) - std::cos(u)) + 3.0;
  tau = t2 < 0.0 ? wrap_angle(t1 + kPi) : wrap_angle(t1);
  omega = wrap_angle(tau - u + v - phi);
}

bool nonneg(double a) { return a >= -kSignTolerance; }
bool nonpos(double a) { return a <= kSignTolerance; }

// 8.1: L+ S+ L+
bool lp_sp_lp(const Local& g, Word& w) {
  double u, t;
  polar(g.x - std::sin(g.phi), g.y - 1.0 + std::cos(g.phi), u, t);
  const double v = wrap_angle(g.phi - t);
  if (!nonneg(t) || !nonneg(v)) return false;
  w = word3(kL, t, kS, u, kL, v);
  return true;
}

// 8.2: L+ S+ R+
bool lp_sp_rp(const Local& g, Word& w) {
  double r, theta;
  polar(g.x + std::sin(g.phi), g.y - 1.0 - std::cos(g.phi), r, theta);
  if (r * r < 4.0) return false;
  const double u = std::sqrt(r * r - 4.0);
  const double t = wrap_angle(theta + std::atan2(2.0, u));
  const double v = wrap_angle(t - g.phi);
  if (!nonneg(t) || !nonneg(v)) return false;
  w = word3(kL, t, kS, u, kR, v);
  return true;
}

// 8.3 / 8.4: L+ R- L (the last arc either way)
bool lp_rm_l(const Local& g, Word& w) {
  double r, theta;
  polar(g.x - std::sin(g.phi), g.y - 1.0 + std::cos(g.phi), r, theta);
  if (r > 4.0) return false;
  const double u = -2.0 * std::asin(std::min(1.0, 0.25 * r));
  const double t = wrap_angle(theta + 0.5 * u + kPi);
  const double v = wrap_angle(g.phi - t + u);
  if (!nonneg(t) || !nonpos(u)) return false;
  w = word3(kL, t, kR, u, kL, v);
  return true;
}

// 8.7: L+ R+ L- R-  (the middle arcs of equal length u)
bool lp_rup_lum_rm(const Local& g, Word& w) {
  const double xi = g.x + std::sin(g.phi), eta = g.y - 1.0 - std::cos(g.phi);
  const double rho = 0.25 * (2.0 + std::hypot(xi, eta));
  if (rho > 1.0) return false;
  const double u = std::acos(rho);
  double t, v;
  tau_omega(u, -u, xi, eta, g.phi, t, v);
  if (!nonneg(t) || !nonpos(v)) return false;
  w = Word{};
  w.push(kL, t);
  w.push(kR, u);
  w.push(kL, -u);
  w.push(kR, v);
  return true;
}

// 8.8: L+ R- L- R+
bool lp_rum_lum_rp(const Local& g, Word& w) {
  const double xi = g.x + std::sin(g.phi), eta = g.y - 1.0 - std::cos(g.phi);
  const double rho = (20.0 - xi * xi - eta * eta) / 16.0;
  if (rho < 0.0 || rho > 1.0) return false;
  const double u = -std::acos(rho);
  if (u < -kHalfPi) return false;
  double t, v;
  tau_omega(u, u, xi, eta, g.phi, t, v);
  if (!nonneg(t) || !nonneg(v)) return false;
  w = Word{};
  w.push(kL, t);
  w.push(kR, u);
  w.push(kL, u);
  w.push(kR, v);
  return true;
}

// 8.9: L+ R-(pi/2) S- L-
bool lp_rm_sm_lm(const Local& g, Word& w) {
  double rho, theta;
  polar(g.x - std::sin(g.phi), g.y - 1.0 + std::cos(g.phi), rho, theta);
  if (rho < 2.0) return false;
  const double r = std::sqrt(rho * rho - 4.0);
  const double u = 2.0 - r;
  const double t = wrap_angle(theta + std::atan2(r, -2.0));
  const double v = wrap_angle(g.phi - kHalfPi - t);
  if (!nonneg(t) || !nonpos(u) || !nonpos(v)) return false;
  w = Word{};
  w.push(kL, t);
  w.push(kR, -kHalfPi);
  w.push(kS, u);
  w.push(kL, v);
  return true;
}

// 8.10: L+ R-(pi/2) S- R-
bool lp_rm_sm_rm(const Local& g, Word& w) {
  const double xi = g.x + std::sin(g.phi), eta = g.y - 1.0 - std::cos(g.phi);
  double rho, theta;
  polar(-eta, xi, rho, theta);
  if (rho < 2.0) return false;
  const double t = theta, u = 2.0 - rho;
  const double v = wrap_angle(t + kHalfPi - g.phi);
  if (!nonneg(t) || !nonpos(u) || !nonpos(v)) return false;
  w = Word{};
  w.push(kL, t);
  w.push(kR, -kHalfPi);
  w.push(kS, u);
  w.push(kR, v);
  return true;
}

// 8.11: L+ R-(pi/2) S- L-(pi/2) R+
bool lp_rm_s_lm_rp(const Local& g, Word& w) {
  const double xi = g.x + std::sin(g.phi), eta = g.y - 1.0 - std::cos(g.phi);
  double rho, theta;
  polar(xi, eta, rho, theta);
  if (rho < 2.0) return false;
  const double u = 4.0 - std::sqrt(rho * rho - 4.0);
  if (!nonpos(u)) return false;
  const double t = wrap_angle(std::atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta));
  const double v = wrap_angle(t - g.phi);
  if (!nonneg(t) || !nonneg(v)) return false;
  w = Word{};
  w.push(kL, t);
  w.push(kR, -kHalfPi);
  w.push(kS, u);
  w.push(kL, -kHalfPi);
  w.push(kR, v);
  return true;
}

using BaseFormula = bool (*)(const Local&, Word&);

// Applies a base formula under the symmetries of the problem. Time-flip (drive the word backwards in
// time: every segment reversed) answers the goal (-x, y, -phi); reflection (mirror in the x axis:
// left and right swapped) answers (x, -y, -phi); "backwards" (the word read from its end) answers
// the goal seen from the goal, (x cos phi + y sin phi, x sin phi - y cos phi, phi).
template <class Visit>
void under_symmetries(const Local& g, BaseFormula formula, bool with_backwards, Visit&& visit) {
  for (int backwards = 0; backwards <= (with_backwards ? 1 : 0); ++backwards) {
    Local b = g;
    if (backwards) {
      const double c = std::cos(g.phi), s = std::sin(g.phi);
      b = {g.x * c + g.y * s, g.x * s - g.y * c, g.phi};
    }
    for (int flip = 0; flip <= 1; ++flip) {
      for (int reflect = 0; reflect <= 1; ++reflect) {
        Local q = b;
        if (flip) q = {-q.x, q.y, -q.phi};
        if (reflect) q = {q.x, -q.y, -q.phi};
        Word w;
        if (!formula(q, w)) continue;
        if (backwards) {
          std::reverse(w.kinds.begin(), w.kinds.begin() + static_cast<std::ptrdiff_t>(w.count));
          std::reverse(w.lengths.begin(), w.lengths.begin() + static_cast<std::ptrdiff_t>(w.count));
        }
        if (flip)
          for (std::size_t i = 0; i < w.count; ++i) w.lengths[i] = -w.lengths[i];
        visit(reflect ? reflected(w) : w);
      }
    }
  }
}

template <class Visit>
void reeds_shepp_words(const Local& g, Visit&& visit) {
  under_symmetries(g, lp_sp_lp, false, visit);      // CSC
  under_symmetries(g, lp_sp_rp, false, visit);
  under_symmetries(g, lp_rm_l, true, visit);        // C|C|C, C|CC, CC|C
  under_symmetries(g, lp_rup_lum_rm, false, visit);  // CCu|CuC
  under_symmetries(g, lp_rum_lum_rp, false, visit);  // C|CuCu|C
  under_symmetries(g, lp_rm_sm_lm, true, visit);    // C|C(pi/2)SC, CSC(pi/2)|C
  under_symmetries(g, lp_rm_sm_rm, true, visit);
  under_symmetries(g, lp_rm_s_lm_rp, false, visit);  // C|C(pi/2)SC(pi/2)|C
}

template <class Words>
CarPath shortest_path(const Pose2& start, const Pose2& goal, double radius, Words&& words) {
  check_query(start, goal, radius);
  Word best;
  double best_length = kInfinity;
  words(to_local(start, goal, radius), [&](const Word& w) {
    const double l = w.length();
    if (l < best_length) {
      best_length = l;
      best = w;
    }
  });
  return make_path(start, radius, best);
}

template <class Words>
std::vector<CarPath> all_paths(const Pose2& start, const Pose2& goal, double radius, Words&& words) {
  check_query(start, goal, radius);
  std::vector<CarPath> paths;
  words(to_local(start, goal, radius), [&](const Word& w) { paths.push_back(make_path(start, radius, w)); });
  return paths;
}

const auto kDubinsWords = [](const Local& g, auto&& visit) { dubins_words(g, visit); };
const auto kReedsSheppWords = [](const Local& g, auto&& visit) { reeds_shepp_words(g, visit); };

}  // namespace

double CarPath::curvature(const CurveSegment& segment) const {
  switch (segment.kind) {
    case Kind::kLeft: return 1.0 / radius;
    case Kind::kRight: return -1.0 / radius;
    case Kind::kStraight: break;
  }
  return 0.0;
}

Pose2 CarPath::pose_at(double s) const {
  Pose2 pose = start;
  double remaining = std::clamp(s, 0.0, length);
  for (std::size_t i = 0; i < segment_count && remaining > 0.0; ++i) {
    const CurveSegment& seg = segments[i];
    const double driven = std::min(std::abs(seg.length), remaining);
    pose = advance(pose, seg.kind, std::copysign(driven, seg.length), radius);
    remaining -= driven;
  }
  pose.yaw = wrap_angle(pose.yaw);
  return pose;
}

std::size_t CarPath::cusp_count() const {
  std::size_t cusps = 0;
  for (std::size_t i = 1; i < segment_count; ++i)
    if ((segments[i].length > 0.0) != (segments[i - 1].length > 0.0)) ++cusps;
  return cusps;
}

std::vector<CarPathSample> sample_car_path(const CarPath& path, double step) {
  if (!(std::isfinite(step) && step > 0.0))
    throw Error("car curves: the sampling step must be positive and finite, got " + std::to_string(step), {}, 0,
                "step");
  std::vector<CarPathSample> samples;
  // A grid point this close to a stretch's end gives way to the end itself (no near-duplicates).
  const double merge = 1e-9 * std::max(1.0, step);
  double stretch_start = 0.0;
  std::size_t i = 0;
  while (i < path.segment_count) {
    const int direction = path.segments[i].length > 0.0 ? 1 : -1;
    double stretch_end = stretch_start;
    for (; i < path.segment_count && (path.segments[i].length > 0.0 ? 1 : -1) == direction; ++i)
      stretch_end += std::abs(path.segments[i].length);
    const bool first_stretch = samples.empty();
    for (std::size_t k = 0;; ++k) {
      const double s = stretch_start + static_cast<double>(k) * step;
      if (k > 0 && s > stretch_end - merge) break;
      samples.push_back({path.pose_at(s), s, direction, k == 0 && !first_stretch});
    }
    stretch_start = stretch_end;
  }
  const int last_direction =
      path.segment_count > 0 && path.segments[path.segment_count - 1].length < 0.0 ? -1 : 1;
  samples.push_back({path.pose_at(path.length), path.length, last_direction, false});
  return samples;
}

CarPath shortest_dubins_path(const Pose2& start, const Pose2& goal, double radius) {
  return shortest_path(start, goal, radius, kDubinsWords);
}

CarPath shortest_reeds_shepp_path(const Pose2& start, const Pose2& goal, double radius) {
  return shortest_path(start, goal, radius, kReedsSheppWords);
}

std::vector<CarPath> dubins_candidates(const Pose2& start, const Pose2& goal, double radius) {
  return all_paths(start, goal, radius, kDubinsWords);
}

std::vector<CarPath> reeds_shepp_candidates(const Pose2& start, const Pose2& goal, double radius) {
  return all_paths(start, goal, radius, kReedsSheppWords);
}

std::string car_path_word(const CarPath& path) {
  std::string word;
  for (std::size_t i = 0; i < path.segment_count; ++i) {
    const CurveSegment& seg = path.segments[i];
    word += seg.kind == Kind::kLeft ? 'L' : seg.kind == Kind::kRight ? 'R' : 'S';
    word += seg.length < 0.0 ? '-' : '+';
  }
  return word;
}

}  // namespace starnav
