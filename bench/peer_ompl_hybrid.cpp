// Hybrid-A* (plan/hybrid_astar) against OMPL 1.5 as a peer: OMPL's ReedsSheppStateSpace with RRT*
// and BIT*, both given the library's footprint checker as their state validity checker on the same
// map, on the same seeded parking-style queries (docs/benchmarks.md, "Hybrid-A* against OMPL").
// OMPL is linked into this executable only, never into the library.
//
// Per query: Hybrid-A*'s time, length and largest curvature; for each OMPL planner the time to its
// first solution, that solution's length, and the best length after 1 s and at the time limit
// (OMPL's intermediate-solution callback). Every path returned is checked with the footprint every
// 1 cm along it by brute force over the obstacle cells near each pose. Exit status: 0, or 1 when a
// Hybrid-A* path fails that check or turns tighter than 1/R, 2 for bad input, 77 when the default
// maps (../shared/benchmarks/movingai) are absent.
#include <CLI/CLI.hpp>
#include <ompl/base/ScopedState.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>
#include <ompl/config.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/map/clearance_window.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/plan/hybrid_astar.hpp"

namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;
using namespace starnav;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kCheckStep = 0.01;  // the path check's spacing (m)

struct Options {
  std::string shared_dir = STARNAV_SHARED_DIR;
  std::vector<std::string> maps;  // empty: the default rooms and street maps under shared_dir
  int queries = 40;
  double time_limit_s = 10.0;
  double checkpoint_s = 1.0;
  double resolution_m = 0.05;
  double min_distance_m = 1.5;
  double length_m = 1.8;
  double width_m = 0.9;
  double radius_m = 2.5;
  std::uint64_t seed = 45;
  int only = -1;  // >= 0: run only this query of the sequence
  bool hybrid_only = false;  // skip OMPL (Hybrid-A*'s columns alone, for quick timing)
  int repeat = 1;            // Hybrid-A*'s time: the median of this many runs of each query
  std::string csv;
  bool json = false;
  bool quiet = false;
};

const std::vector<std::string> kDefaultMaps = {"room/64room_000.map", "street/Berlin_0_256.map",
                                               "street/Boston_0_256.map", "street/Berlin_0_512.map",
                                               "street/Paris_0_512.map"};

// A MovingAI map read as a metric grid of `resolution` per cell, REP-103 rows (the file's last row
// is row 0).
OccupancyGrid metric_grid(const MovingAiMap& m, double resolution) {
  GridGeometry g;
  g.resolution = resolution;
  g.width = m.width;
  g.height = m.height;
  OccupancyGrid grid(g, kFreeOccupancy);
  for (int iy = 0; iy < m.height; ++iy)
    for (int ix = 0; ix < m.width; ++ix)
      grid(ix, iy) = MovingAiMap::passable(m.at(ix, m.height - 1 - iy)) ? kFreeOccupancy : kOccupiedOccupancy;
  return grid;
}

HybridAStarOptions car_options(const Options& o) {
  HybridAStarOptions h;
  h.motion_model = HybridMotionModel::ReedsShepp;
  h.minimum_turning_radius_m = o.radius_m;
  h.footprint_length_m = o.length_m;
  h.footprint_width_m = o.width_m;
  h.analytic_expansion_max_length_m = 0.0;  // try the curve to the goal from anywhere
  h.max_planning_time_s = o.time_limit_s;
  return h;
}

// One map: the grid, the footprint checker over one window covering it (the planner builds its own
// the same way), the cells the car's centre may occupy and their connected components.
struct MapCase {
  std::string name;
  OccupancyGrid grid;
  FootprintChecker checker;
  ClearanceWindow window;
  std::vector<std::size_t> centre_cells;  // grid indices of cells with clearance > the inscribed radius
  std::vector<int> component;             // per grid cell: its component, -1 for the others
  std::unique_ptr<HybridAStar> planner;

  bool collides(const Pose2& p) const { return checker.collides(window, p); }
};

std::unique_ptr<MapCase> load_map_case(const std::string& path, const Options& o) {
  auto mc = std::make_unique<MapCase>();
  mc->name = std::filesystem::path(path).stem().string();
  mc->grid = metric_grid(read_movingai_map(path), o.resolution_m);
  const HybridAStarOptions hopt = car_options(o);
  const FootprintModel model = hopt.footprint();
  mc->checker = FootprintChecker(model, 0.0);
  const GridGeometry& g = mc->grid.geometry();
  const double res = g.resolution;
  const Vec2 centre(0.5 * g.width * res, 0.5 * g.height * res);
  mc->window.build(mc->grid, centre, 0.5 * std::max(g.width, g.height) * res + res, model.bounding_radius_m() + 2.0 * res);
  // The car's centre stays in cells whose centre is farther than the inscribed radius from every
  // obstacle cell centre (closer, the checker's rule always finds a collision): 8-connected
  // components of those cells bound where a start can reach.
  const std::size_t n = mc->grid.cell_count();
  std::vector<std::uint8_t> ok(n, 0);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Cell c = mc->window.cell_of({(ix + 0.5) * res, (iy + 0.5) * res});
      if (mc->window.contains(c.x, c.y) && mc->window.clearance_m(mc->window.index(c.x, c.y)) > model.inscribed_radius_m())
        ok[g.index(ix, iy)] = 1;
    }
  mc->component.assign(n, -1);
  int next = 0;
  std::vector<std::size_t> stack;
  for (std::size_t s = 0; s < n; ++s) {
    if (!ok[s] || mc->component[s] >= 0) continue;
    mc->component[s] = next;
    stack.push_back(s);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      const int x = static_cast<int>(i % g.width), y = static_cast<int>(i / g.width);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!g.contains(x + dx, y + dy)) continue;
          const std::size_t j = g.index(x + dx, y + dy);
          if (ok[j] && mc->component[j] < 0) {
            mc->component[j] = next;
            stack.push_back(j);
          }
        }
    }
    ++next;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (ok[i]) mc->centre_cells.push_back(i);
  if (mc->centre_cells.empty()) throw Error("no cell has room for the car's footprint", path, 0, "map");
  mc->planner = std::make_unique<HybridAStar>(mc->grid, hopt);
  return mc;
}

struct Query {
  int map = 0;
  Pose2 start, goal;
};

// A random collision-free pose whose centre lies in one of the centre cells; its grid cell in `cell`.
bool random_pose(const MapCase& mc, Rng& rng, Pose2& pose, std::size_t& cell) {
  const double res = mc.grid.resolution();
  for (int attempt = 0; attempt < 1000; ++attempt) {
    cell = mc.centre_cells[static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(mc.centre_cells.size()) - 1))];
    const int ix = static_cast<int>(cell % mc.grid.width()), iy = static_cast<int>(cell / mc.grid.width());
    pose = Pose2((ix + rng.uniform()) * res, (iy + rng.uniform()) * res, rng.uniform(-kPi, kPi));
    if (!mc.collides(pose)) return true;
  }
  return false;
}

// Start and goal both collision-free, in the same component of centre cells, at least
// min_distance_m apart.
Query make_query(const MapCase& mc, int map, Rng& rng, const Options& o, const std::string& path) {
  for (int attempt = 0; attempt < 2000; ++attempt) {
    Query q;
    q.map = map;
    std::size_t sc = 0, gc = 0;
    if (!random_pose(mc, rng, q.start, sc)) continue;
    for (int k = 0; k < 50; ++k) {
      if (!random_pose(mc, rng, q.goal, gc)) break;
      if (mc.component[sc] == mc.component[gc] && std::hypot(q.goal.x - q.start.x, q.goal.y - q.start.y) >= o.min_distance_m)
        return q;
    }
  }
  std::ostringstream what;
  what << "found no collision-free start and goal poses " << o.min_distance_m << " m apart in one region";
  throw Error(what.str(), path, 0, "map");
}

// The largest curvature along a path given as segments of constant curvature (arcs and straights)
// sampled with their ends: between consecutive samples of a segment, the arc through both.
double max_curvature(const std::vector<std::vector<Pose2>>& segments) {
  double k = 0.0;
  for (const std::vector<Pose2>& poses : segments)
    for (std::size_t i = 1; i < poses.size(); ++i) {
      const double chord = std::hypot(poses[i].x - poses[i - 1].x, poses[i].y - poses[i - 1].y);
      if (chord < 1e-9) continue;
      k = std::max(k, 2.0 * std::abs(std::sin(0.5 * angle_diff(poses[i].yaw, poses[i - 1].yaw))) / chord);
    }
  return k;
}

std::vector<Pose2> concatenate(const std::vector<std::vector<Pose2>>& segments) {
  std::vector<Pose2> out;
  for (const auto& s : segments) out.insert(out.end(), s.begin(), s.end());
  return out;
}

// The footprint at every pose against every obstacle cell near it (the checker's brute-force rule
// on a small window of the grid built for the pose), independent of the planners' whole-map window.
// The first pose that collides is reported on stderr.
bool poses_free(const MapCase& mc, const std::vector<Pose2>& poses, const char* planner) {
  ClearanceWindow local;
  const double res = mc.grid.resolution();
  const double half = mc.checker.model().bounding_radius_m() + 2.0 * res;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Pose2& p = poses[i];
    local.build(mc.grid, {p.x, p.y}, half, 2.0 * res);
    if (mc.checker.collides_brute_force(local, p)) {
      std::fprintf(stderr, "%s: the footprint at sample %zu of %zu, pose (%.6f, %.6f, %.6f), collides on %s (whole-map checker: %s)\n",
                   planner, i, poses.size(), p.x, p.y, p.yaw, mc.name.c_str(), mc.collides(p) ? "collides" : "free");
      return false;
    }
  }
  return true;
}

struct HybridRun {
  bool found = false;
  std::string status;  // plan_status_reason
  double time_s = kNaN;  // thread CPU time of plan()
  double length_m = kNaN;
  double max_curvature = kNaN;
  int cusps = 0;
  bool free = true;
};

HybridRun run_hybrid(MapCase& mc, const Query& q, int repeat) {
  HybridRun out;
  PlanResult r;
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    const double t0 = thread_cpu_s();
    r = mc.planner->plan(q.start, q.goal);
    times.push_back(thread_cpu_s() - t0);
  }
  out.time_s = sample_stats(std::move(times)).median;
  out.found = r.found();
  out.status = plan_status_reason(r.status);
  if (!out.found) return out;
  std::vector<std::vector<Pose2>> segments;
  double length = 0.0;
  bool prev_reverse = false;
  for (std::size_t i = 0; i < mc.planner->motions().size(); ++i) {
    const HybridMotion& m = mc.planner->motions()[i];
    const double len = std::abs(m.length);
    length += len;
    if (i > 0 && m.reverse() != prev_reverse) ++out.cusps;
    prev_reverse = m.reverse();
    const int steps = std::max(1, static_cast<int>(std::ceil(len / kCheckStep)));
    auto& poses = segments.emplace_back();
    for (int s = 0; s <= steps; ++s) poses.push_back(m.pose_at(len * s / steps));
  }
  out.length_m = length;
  out.max_curvature = max_curvature(segments);
  out.free = poses_free(mc, concatenate(segments), "hybrid_astar");
  if (!out.free) {
    // Which motion, and whether the planner's own checks along it (every half cell) see it.
    for (std::size_t i = 0; i < segments.size(); ++i) {
      if (std::none_of(segments[i].begin(), segments[i].end(), [&](const Pose2& p) { return mc.collides(p); })) continue;
      const HybridMotion& m = mc.planner->motions()[i];
      const double len = std::abs(m.length), step = 0.5 * mc.grid.resolution();
      const int n = std::max(1, static_cast<int>(std::ceil(len / step - 1e-9)));
      bool seen = false;
      for (int k = 0; k <= n; ++k) seen = seen || mc.collides(m.pose_at(len * k / n));
      std::fprintf(stderr, "hybrid_astar: motion %zu of %zu (curvature %.4f 1/m, length %.4f m) collides; checked every %.3f m it %s\n",
                   i, segments.size(), m.curvature, m.length, len / n, seen ? "collides too" : "looks clear");
    }
  }
  return out;
}

enum class Peer { RRTstar, BITstar };

struct PeerRun {
  bool found = false;
  double first_s = kNaN;  // thread CPU time to the first exact solution
  double first_length_m = kNaN;
  double checkpoint_length_m = kNaN;  // best length found within checkpoint_s
  double end_length_m = kNaN;         // at the time limit
  double max_curvature = kNaN;
  int cusps = 0;
  bool free = true;
};

PeerRun run_peer(const MapCase& mc, const Query& q, Peer peer, const Options& o) {
  auto space = std::make_shared<ob::ReedsSheppStateSpace>(o.radius_m);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, 0.0);
  bounds.setLow(1, 0.0);
  bounds.setHigh(0, mc.grid.width() * mc.grid.resolution());
  bounds.setHigh(1, mc.grid.height() * mc.grid.resolution());
  space->setBounds(bounds);
  og::SimpleSetup ss(space);
  const ob::SpaceInformationPtr si = ss.getSpaceInformation();
  ss.setStateValidityChecker([&mc](const ob::State* s) {
    const auto* se2 = s->as<ob::SE2StateSpace::StateType>();
    return !mc.collides(Pose2(se2->getX(), se2->getY(), se2->getYaw()));
  });
  // Motions checked every map cell of path length (the Reeds-Shepp distance).
  si->setStateValidityCheckingResolution(mc.grid.resolution() / space->getMaximumExtent());
  ob::ScopedState<ob::SE2StateSpace> start(space), goal(space);
  start->setXY(q.start.x, q.start.y);
  start->setYaw(q.start.yaw);
  goal->setXY(q.goal.x, q.goal.y);
  goal->setYaw(q.goal.yaw);
  ss.setStartAndGoalStates(start, goal, 1e-6);
  ss.setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));
  if (peer == Peer::RRTstar)
    ss.setPlanner(std::make_shared<og::RRTstar>(si));
  else
    ss.setPlanner(std::make_shared<og::BITstar>(si));
  std::vector<std::pair<double, double>> improvements;  // (CPU seconds, length)
  double t0 = thread_cpu_s();
  ss.getProblemDefinition()->setIntermediateSolutionCallback(
      [&](const ob::Planner*, const std::vector<const ob::State*>&, const ob::Cost cost) {
        improvements.emplace_back(thread_cpu_s() - t0, cost.value());
      });
  // The limit in this thread's CPU time, as the other times here: another process sharing the core
  // leaves the planners the same work. The clock is read every 16th test (it is a system call).
  int polls = 0;
  const ob::PlannerTerminationCondition ptc([&] { return (++polls & 15) == 0 && thread_cpu_s() - t0 >= o.time_limit_s; });
  t0 = thread_cpu_s();
  const ob::PlannerStatus status = ss.solve(ptc);
  PeerRun out;
  out.found = status == ob::PlannerStatus::EXACT_SOLUTION;
  if (!out.found) return out;
  og::PathGeometric path = ss.getSolutionPath();
  out.end_length_m = path.length();
  if (improvements.empty()) {
    throw Error(std::string(peer == Peer::RRTstar ? "RRT*" : "BIT*") +
                " solved without reporting an intermediate solution: its time to first solution is unknown");
  }
  out.first_s = improvements.front().first;
  out.first_length_m = improvements.front().second;
  for (const auto& [t, len] : improvements)
    if (t <= o.checkpoint_s) out.checkpoint_length_m = len;
  // Every Reeds-Shepp segment of every edge sampled on its own, its ends included (a cusp pose is
  // checked; no pair of samples straddles a change of curvature or direction).
  std::vector<std::vector<Pose2>> segments;
  ob::ScopedState<ob::SE2StateSpace> tmp(space);
  double prev_sign = 0.0;
  for (std::size_t e = 0; e + 1 < path.getStateCount(); ++e) {
    const ob::State *a = path.getState(e), *b = path.getState(e + 1);
    const ob::ReedsSheppStateSpace::ReedsSheppPath rs = space->reedsShepp(a, b);
    const double total = rs.length();
    double done = 0.0;
    for (const double signed_len : rs.length_) {
      const double len = std::abs(signed_len);
      if (len < 1e-12) continue;
      const double sign = signed_len > 0.0 ? 1.0 : -1.0;
      if (prev_sign != 0.0 && sign != prev_sign) ++out.cusps;
      prev_sign = sign;
      const int steps = std::max(1, static_cast<int>(std::ceil(len * o.radius_m / kCheckStep)));
      auto& poses = segments.emplace_back();
      for (int k = 0; k <= steps; ++k) {
        space->interpolate(a, b, std::min(1.0, (done + len * k / steps) / total), tmp.get());
        poses.emplace_back(tmp->getX(), tmp->getY(), tmp->getYaw());
      }
      done += len;
    }
  }
  out.max_curvature = max_curvature(segments);
  out.free = poses_free(mc, concatenate(segments), peer == Peer::RRTstar ? "rrtstar" : "bitstar");
  return out;
}

struct Row {
  std::size_t index = 0;  // in the query sequence
  Query query;
  HybridRun hybrid;
  PeerRun rrt, bit;
};

std::string num(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string jnum(double v) { return std::isfinite(v) ? num(v) : "null"; }

void write_csv(const std::string& path, const std::vector<Row>& rows, const std::vector<std::unique_ptr<MapCase>>& maps) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write", path, 0, "--csv");
  f << "query,map,start_x,start_y,start_yaw,goal_x,goal_y,goal_yaw,"
       "hybrid_found,hybrid_status,hybrid_time_s,hybrid_length_m,hybrid_max_curvature,hybrid_cusps,hybrid_free";
  for (const char* p : {"rrtstar", "bitstar"})
    for (const char* c : {"found", "first_s", "first_length_m", "checkpoint_length_m", "end_length_m", "max_curvature", "cusps",
                          "free"})
      f << ',' << p << '_' << c;
  f << '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const Query& q = r.query;
    f << r.index << ',' << maps[static_cast<std::size_t>(q.map)]->name << ',' << num(q.start.x) << ',' << num(q.start.y) << ','
      << num(q.start.yaw) << ',' << num(q.goal.x) << ',' << num(q.goal.y) << ',' << num(q.goal.yaw) << ',' << r.hybrid.found
      << ',' << r.hybrid.status << ',' << num(r.hybrid.time_s) << ',' << num(r.hybrid.length_m) << ',' << num(r.hybrid.max_curvature) << ','
      << r.hybrid.cusps << ',' << r.hybrid.free;
    for (const PeerRun* p : {&r.rrt, &r.bit})
      f << ',' << p->found << ',' << num(p->first_s) << ',' << num(p->first_length_m) << ',' << num(p->checkpoint_length_m)
        << ',' << num(p->end_length_m) << ',' << num(p->max_curvature) << ',' << p->cusps << ',' << p->free;
    f << '\n';
  }
  if (!f.flush()) throw Error("cannot write", path, 0, "--csv");
}

struct Summary {
  int queries = 0, hybrid_found = 0, rrt_found = 0, bit_found = 0;
  int bit_solved = 0, hybrid_where_bit = 0;  // queries BIT* solved; of those, Hybrid-A* too
  double success_where_bit = kNaN;
  std::vector<double> time_ratios, length_ratios;
  double median_time_ratio = kNaN, median_length_ratio = kNaN;
  double median_hybrid_s = kNaN, median_rrt_first_s = kNaN, median_bit_first_s = kNaN;
  double hybrid_max_curvature = 0.0;
  int hybrid_not_free = 0, rrt_not_free = 0, bit_not_free = 0;
};

double median_of(std::vector<double> v) { return v.empty() ? kNaN : sample_stats(std::move(v)).median; }

Summary summarise(const std::vector<Row>& rows) {
  Summary s;
  s.queries = static_cast<int>(rows.size());
  std::vector<double> th, tr, tb;
  for (const Row& r : rows) {
    s.hybrid_found += r.hybrid.found;
    s.rrt_found += r.rrt.found;
    s.bit_found += r.bit.found;
    s.hybrid_not_free += r.hybrid.found && !r.hybrid.free;
    s.rrt_not_free += r.rrt.found && !r.rrt.free;
    s.bit_not_free += r.bit.found && !r.bit.free;
    if (r.hybrid.found) {
      th.push_back(r.hybrid.time_s);
      s.hybrid_max_curvature = std::max(s.hybrid_max_curvature, r.hybrid.max_curvature);
    }
    if (r.rrt.found) tr.push_back(r.rrt.first_s);
    if (r.bit.found) tb.push_back(r.bit.first_s);
    if (r.bit.found) {
      ++s.bit_solved;
      s.hybrid_where_bit += r.hybrid.found;
    }
    if (r.hybrid.found && r.rrt.found) s.time_ratios.push_back(r.rrt.first_s / std::max(r.hybrid.time_s, 1e-9));
    if (r.hybrid.found && r.bit.found) s.length_ratios.push_back(r.hybrid.length_m / r.bit.end_length_m);
  }
  if (s.bit_solved > 0) s.success_where_bit = 100.0 * s.hybrid_where_bit / s.bit_solved;
  s.median_time_ratio = median_of(s.time_ratios);
  s.median_length_ratio = median_of(s.length_ratios);
  s.median_hybrid_s = median_of(th);
  s.median_rrt_first_s = median_of(tr);
  s.median_bit_first_s = median_of(tb);
  return s;
}

const char* verdict(double value, bool met) { return std::isfinite(value) ? (met ? "met" : "NOT met") : "no data"; }

void print_text(const Summary& s, const Options& o) {
  std::printf("Hybrid-A* against OMPL %d.%d.%d (Reeds-Shepp, R %.2f m, car %.2f x %.2f m, %.3f m cells): %d queries, "
              "OMPL limit %.3g s, seed %llu\n",
              OMPL_MAJOR_VERSION, OMPL_MINOR_VERSION, OMPL_PATCH_VERSION, o.radius_m, o.length_m, o.width_m, o.resolution_m, s.queries, o.time_limit_s,
              static_cast<unsigned long long>(o.seed));
  std::printf("  solved: hybrid_astar %d, rrtstar %d, bitstar %d\n", s.hybrid_found, s.rrt_found, s.bit_found);
  std::printf("  Hybrid-A* solved %d of the %d queries BIT* solved (%.1f %%; target >= 99 %%: %s)\n", s.hybrid_where_bit,
              s.bit_solved, s.success_where_bit, verdict(s.success_where_bit, s.success_where_bit >= 99.0));
  std::printf("  median time to first solution RRT* / Hybrid-A*: %.1fx over %zu queries (target >= 20x: %s)\n",
              s.median_time_ratio, s.time_ratios.size(), verdict(s.median_time_ratio, s.median_time_ratio >= 20.0));
  std::printf("  median length Hybrid-A* / BIT* at the limit: %.3f over %zu queries (target <= 1.05: %s)\n",
              s.median_length_ratio, s.length_ratios.size(),
              verdict(s.median_length_ratio, s.median_length_ratio <= 1.05));
  std::printf("  median time (CPU s): hybrid_astar %.4f, rrtstar first %.4f, bitstar first %.4f\n", s.median_hybrid_s,
              s.median_rrt_first_s, s.median_bit_first_s);
  std::printf("  Hybrid-A* largest curvature %.6f 1/m (1/R = %.6f)\n", s.hybrid_max_curvature, 1.0 / o.radius_m);
  std::printf("  paths failing the footprint check every %.0f cm: hybrid_astar %d, rrtstar %d, bitstar %d\n",
              kCheckStep * 100, s.hybrid_not_free, s.rrt_not_free, s.bit_not_free);
}

void print_json(const Summary& s, const Options& o) {
  std::printf("{\"ompl_version\": \"%d.%d.%d\", \"queries\": %d, \"time_limit_s\": %s, \"checkpoint_s\": %s, \"seed\": %llu,\n",
              OMPL_MAJOR_VERSION, OMPL_MINOR_VERSION, OMPL_PATCH_VERSION, s.queries, jnum(o.time_limit_s).c_str(), jnum(o.checkpoint_s).c_str(),
              static_cast<unsigned long long>(o.seed));
  std::printf(" \"solved\": {\"hybrid_astar\": %d, \"rrtstar\": %d, \"bitstar\": %d},\n", s.hybrid_found, s.rrt_found,
              s.bit_found);
  std::printf(" \"hybrid_success_where_bitstar_solved\": {\"solved\": %d, \"of\": %d, \"percent\": %s, \"target_percent\": 99},\n",
              s.hybrid_where_bit, s.bit_solved, jnum(s.success_where_bit).c_str());
  std::printf(" \"median_time_ratio_rrtstar_first_over_hybrid\": {\"value\": %s, \"queries\": %zu, \"target_min\": 20},\n",
              jnum(s.median_time_ratio).c_str(), s.time_ratios.size());
  std::printf(" \"median_length_ratio_hybrid_over_bitstar_end\": {\"value\": %s, \"queries\": %zu, \"target_max\": 1.05},\n",
              jnum(s.median_length_ratio).c_str(), s.length_ratios.size());
  std::printf(" \"median_time_s\": {\"hybrid_astar\": %s, \"rrtstar_first\": %s, \"bitstar_first\": %s},\n",
              jnum(s.median_hybrid_s).c_str(), jnum(s.median_rrt_first_s).c_str(), jnum(s.median_bit_first_s).c_str());
  std::printf(" \"hybrid_max_curvature\": %s, \"inverse_radius\": %s,\n", jnum(s.hybrid_max_curvature).c_str(),
              jnum(1.0 / o.radius_m).c_str());
  std::printf(" \"paths_not_free\": {\"hybrid_astar\": %d, \"rrtstar\": %d, \"bitstar\": %d}}\n", s.hybrid_not_free,
              s.rrt_not_free, s.bit_not_free);
}

int run(const Options& o) {
  // A map is a file, or a path under the shared MovingAI folder (room/64room_000.map).
  const std::filesystem::path dir = std::filesystem::path(o.shared_dir) / "benchmarks" / "movingai";
  std::vector<std::string> paths;
  for (const std::string& m : o.maps.empty() ? kDefaultMaps : o.maps) {
    if (std::filesystem::is_regular_file(m)) {
      paths.push_back(m);
    } else if (std::filesystem::is_regular_file(dir / m)) {
      paths.push_back((dir / m).string());
    } else if (!std::filesystem::is_directory(dir)) {
      std::fprintf(stderr, "starnav_peer_ompl_hybrid: %s not present: skipped\n", dir.string().c_str());
      return 77;
    } else {
      throw Error("no such map file (nor under " + dir.string() + ")", m, 0, "--map");
    }
  }
  if (o.only >= o.queries) throw Error("must be below --queries", {}, 0, "--only");
  if (!o.csv.empty() && !std::ofstream(o.csv)) throw Error("cannot write", o.csv, 0, "--csv");  // before the long run
  // Only the maps the queries use are loaded (queries go round the list).
  const std::size_t used = std::min(paths.size(), static_cast<std::size_t>(o.queries));
  std::vector<std::unique_ptr<MapCase>> maps;
  for (std::size_t i = 0; i < used; ++i) maps.push_back(load_map_case(paths[i], o));
  ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
  ompl::RNG::setSeed(o.seed);
  Rng rng(o.seed);
  std::vector<Query> queries;
  for (int i = 0; i < o.queries; ++i) {
    const auto m = static_cast<std::size_t>(i) % used;
    queries.push_back(make_query(*maps[m], static_cast<int>(m), rng, o, paths[m]));
  }
  std::vector<Row> rows;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (o.only >= 0 && static_cast<int>(i) != o.only) continue;
    Row r;
    r.index = i;
    r.query = queries[i];
    MapCase& mc = *maps[static_cast<std::size_t>(r.query.map)];
    r.hybrid = run_hybrid(mc, r.query, o.repeat);
    if (!o.hybrid_only) {
      r.rrt = run_peer(mc, r.query, Peer::RRTstar, o);
      r.bit = run_peer(mc, r.query, Peer::BITstar, o);
    }
    if (!o.quiet)
      std::fprintf(stderr, "query %zu/%zu %s: hybrid_astar %s, rrtstar %s, bitstar %s (first solution, CPU s)\n", i + 1,
                   queries.size(), mc.name.c_str(), r.hybrid.found ? num(r.hybrid.time_s).c_str() : r.hybrid.status.c_str(),
                   r.rrt.found ? num(r.rrt.first_s).c_str() : "failed", r.bit.found ? num(r.bit.first_s).c_str() : "failed");
    rows.push_back(r);
  }
  if (!o.csv.empty()) write_csv(o.csv, rows, maps);
  const Summary s = summarise(rows);
  if (o.json)
    print_json(s, o);
  else
    print_text(s, o);
  const bool hybrid_ok = s.hybrid_not_free == 0 && s.hybrid_max_curvature <= 1.0 / o.radius_m + 1e-6;
  if (!hybrid_ok) std::fprintf(stderr, "starnav_peer_ompl_hybrid: a Hybrid-A* path collides or turns tighter than 1/R\n");
  return hybrid_ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Hybrid-A* against OMPL's RRT* and BIT* (Reeds-Shepp) on the same parking-style queries"};
  app.add_option("--map", o.maps,
                 "MovingAI .map files, or paths under SHARED/benchmarks/movingai (default: rooms and street maps)");
  app.add_option("--shared", o.shared_dir, "the shared data folder (its benchmarks/movingai holds the default maps)");
  app.add_option("--queries", o.queries, "number of queries, spread round the maps")->check(CLI::Range(1, 1000000));
  app.add_option("--time-limit", o.time_limit_s, "OMPL's planning time (CPU s; also Hybrid-A*'s wall-clock limit)")
      ->check(CLI::Range(0.01, 3600.0));
  app.add_option("--checkpoint", o.checkpoint_s, "OMPL's best length is also reported after this CPU time (s)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--resolution", o.resolution_m, "metres per map cell")->check(CLI::Range(0.001, 10.0));
  app.add_option("--min-distance", o.min_distance_m, "least distance between start and goal (m)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--seed", o.seed, "seed of the queries (and of OMPL's sampler)");
  app.add_option("--only", o.only, "run only query INDEX (from 0) of the sequence, to look at one again")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--hybrid-only", o.hybrid_only, "run Hybrid-A* alone (OMPL's columns empty, its ratios 'no data')");
  app.add_option("--repeat", o.repeat, "Hybrid-A*'s time is the median of this many runs of each query (profiling)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--csv", o.csv, "per-query results to this CSV file");
  app.add_flag("--json", o.json, "the summary as JSON");
  app.add_flag("--quiet", o.quiet, "no progress lines on stderr");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::cerr << "starnav: error: " << e.what() << "\n";
    return 2;
  }
  try {
    return run(o);
  } catch (const Error& e) {
    std::cerr << "starnav: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "starnav: error: " << e.what() << "\n";
    return 2;
  }
}
