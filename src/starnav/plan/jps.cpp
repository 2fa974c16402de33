#include "starnav/plan/jps.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/plan/bit_grid.hpp"
#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/jps_tables.hpp"

namespace starnav {
namespace {

constexpr std::uint8_t kStartDir = 8;  // the start node: every direction is a successor

using Clock = std::chrono::steady_clock;

// Per-cell search memory (16 bytes), valid when the generation in `meta` is the current one.
// meta = generation << 5 | closed << 4 | direction of the last move into the node (8 = start).
struct NodeState {
  std::uint32_t meta;
  std::uint32_t parent;
  std::uint32_t ga;  // straight moves of the best known path
  std::uint32_t gb;  // diagonal moves of the best known path
};
static_assert(sizeof(NodeState) == 16, "search state: 16 bytes per cell");
constexpr std::uint32_t kClosedBit = 1u << 4;
constexpr std::uint32_t kDirMask = 15u;
constexpr std::uint32_t kGenerationShift = 5;
constexpr std::uint32_t kMaxGeneration = (1u << (32 - kGenerationShift)) - 1;

// Open-list key: one 128-bit integer ordered like (f, larger g, lower cell index), as
// conventions.md asks. f = A + B*sqrt(2) for integer move counts A, B, so distinct f differ by far
// more than the 2^-28 resolution of the fixed-point f and equal counts give equal keys: the
// order is exact. g (used on equal f only) is kept to 2^-12, exact for paths below ~1000
// diagonal moves and deterministic always. The cell index is the low 32 bits.
__extension__ using OpenKey = unsigned __int128;

inline OpenKey open_key(double f, double g, std::uint32_t id) {
  const auto fk = static_cast<std::uint64_t>(f * 268435456.0 + 0.5);  // 2^28
  const double gs = g * 4096.0;
  const std::uint64_t gk = gs >= 4294967295.0 ? 0xFFFFFFFFull : static_cast<std::uint64_t>(gs);
  return (static_cast<OpenKey>(fk) << 64) | ((0xFFFFFFFFull - gk) << 32) | id;
}
inline std::uint32_t open_key_id(OpenKey k) { return static_cast<std::uint32_t>(k); }

// Binary heap of keys with lazy deletion: a node improved while open is pushed again; the stale
// entry is skipped when popped because the node is closed by then. Storage is kept across
// queries.
class OpenList {
 public:
  void clear() { heap_.clear(); }
  bool empty() const { return heap_.empty(); }
  void reserve(std::size_t n) { heap_.reserve(n); }
  void push(OpenKey e) {
    std::size_t hole = heap_.size();
    heap_.push_back(e);
    OpenKey* h = heap_.data();
    while (hole > 0) {
      const std::size_t parent = (hole - 1) >> 1;
      if (!(e < h[parent])) break;
      h[hole] = h[parent];
      hole = parent;
    }
    h[hole] = e;
  }
  OpenKey pop() {
    OpenKey* h = heap_.data();
    const OpenKey top = h[0];
    const OpenKey last = h[heap_.size() - 1];
    heap_.pop_back();
    const std::size_t n = heap_.size();
    if (n > 0) {
      std::size_t hole = 0;
      for (;;) {
        std::size_t child = 2 * hole + 1;
        if (child >= n) break;
        if (child + 1 < n && h[child + 1] < h[child]) ++child;
        if (!(h[child] < last)) break;
        h[hole] = h[child];
        hole = child;
      }
      h[hole] = last;
    }
    return top;
  }

 private:
  std::vector<OpenKey> heap_;
};

// Online jumps: block-based scans of the bit grid (rows) and its transpose (columns).
class OnlineJumper {
 public:
  OnlineJumper(const BitGrid& rows, const BitGrid& cols) : r_(rows), t_(cols) {}

  void set_goal(int gx, int gy) {
    goal_r_ = r_.index(gx, gy);
    goal_t_ = t_.index(gy, gx);
  }

  // Calls emit(x, y, dir) for every jump point (or the goal) found from (x, y) along `dir`.
  template <class Emit>
  void jump(int dir, int x, int y, std::uint32_t /*id*/, Emit& emit) const {
    switch (dir) {
      case kJpsNorth: {
        const std::uint32_t k = t_.scan_backward(t_.index(y, x), goal_t_);
        if (k) emit(x, y - static_cast<int>(k), kJpsNorth);
        break;
      }
      case kJpsSouth: {
        const std::uint32_t k = t_.scan_forward(t_.index(y, x), goal_t_);
        if (k) emit(x, y + static_cast<int>(k), kJpsSouth);
        break;
      }
      case kJpsEast: {
        const std::uint32_t k = r_.scan_forward(r_.index(x, y), goal_r_);
        if (k) emit(x + static_cast<int>(k), y, kJpsEast);
        break;
      }
      case kJpsWest: {
        const std::uint32_t k = r_.scan_backward(r_.index(x, y), goal_r_);
        if (k) emit(x - static_cast<int>(k), y, kJpsWest);
        break;
      }
      case kJpsNorthEast: diagonal<1, -1>(x, y, emit); break;
      case kJpsSouthEast: diagonal<1, 1>(x, y, emit); break;
      case kJpsSouthWest: diagonal<-1, 1>(x, y, emit); break;
      case kJpsNorthWest: diagonal<-1, -1>(x, y, emit); break;
      default: break;
    }
  }

 private:
  template <int DX, int DY, class Emit>
  void diagonal(int x, int y, Emit& emit) const {
    constexpr std::uint8_t ddir = DX > 0 ? (DY < 0 ? kJpsNorthEast : kJpsSouthEast)
                                         : (DY < 0 ? kJpsNorthWest : kJpsSouthWest);
    constexpr std::uint8_t hdir = DX > 0 ? kJpsEast : kJpsWest;
    constexpr std::uint8_t vdir = DY > 0 ? kJpsSouth : kJpsNorth;
    const std::uint32_t rs = r_.stride(), ts = t_.stride();
    const std::uint32_t rvert = DY > 0 ? rs : 0u - rs;             // one row down / up
    const std::uint32_t rdiag = rvert + static_cast<std::uint32_t>(DX);
    const std::uint32_t tdiag = (DX > 0 ? ts : 0u - ts) + static_cast<std::uint32_t>(DY);
    std::uint32_t r = r_.index(x, y), t = t_.index(y, x);
    for (;;) {
      // No corner cutting: both orthogonal neighbours and the diagonal one must be free.
      if (!r_.free(r + static_cast<std::uint32_t>(DX)) || !r_.free(r + rvert) || !r_.free(r + rdiag)) return;
      r += rdiag;
      t += tdiag;
      x += DX;
      y += DY;
      if (r == goal_r_) {
        emit(x, y, ddir);
        return;
      }
      const std::uint32_t kv = DY > 0 ? t_.scan_forward(t, goal_t_) : t_.scan_backward(t, goal_t_);
      if (kv) emit(x, y + DY * static_cast<int>(kv), vdir);
      const std::uint32_t kh = DX > 0 ? r_.scan_forward(r, goal_r_) : r_.scan_backward(r, goal_r_);
      if (kh) emit(x + DX * static_cast<int>(kh), y, hdir);
    }
  }

  const BitGrid& r_;
  const BitGrid& t_;
  std::uint32_t goal_r_ = 0;
  std::uint32_t goal_t_ = 0;
};

// JPS+ jumps: table look-ups, with the goal checked against each jump's reach.
class TableJumper {
 public:
  TableJumper(const JumpTable& table, int width) : tab_(table), width_(width) {}

  void set_goal(int gx, int gy) {
    gx_ = gx;
    gy_ = gy;
  }

  template <class Emit>
  void jump(int dir, int x, int y, std::uint32_t id, Emit& emit) const {
    switch (dir) {
      case kJpsNorth: straight<kJpsNorth>(x, y, id, emit); break;
      case kJpsSouth: straight<kJpsSouth>(x, y, id, emit); break;
      case kJpsEast: straight<kJpsEast>(x, y, id, emit); break;
      case kJpsWest: straight<kJpsWest>(x, y, id, emit); break;
      case kJpsNorthEast: diagonal<1, -1>(x, y, id, emit); break;
      case kJpsSouthEast: diagonal<1, 1>(x, y, id, emit); break;
      case kJpsSouthWest: diagonal<-1, 1>(x, y, id, emit); break;
      case kJpsNorthWest: diagonal<-1, -1>(x, y, id, emit); break;
      default: break;
    }
  }

 private:
  template <int DIR>
  std::uint32_t step() const {
    return static_cast<std::uint32_t>(kJpsDy[DIR] * width_ + kJpsDx[DIR]);
  }

  // Steps from (x, y) to the goal when it lies ahead on this straight line, else 0.
  template <int DIR>
  int goal_ahead(int x, int y) const {
    constexpr int dx = kJpsDx[DIR], dy = kJpsDy[DIR];
    int k = 0;
    if constexpr (dx != 0) {
      if (gy_ == y) k = (gx_ - x) * dx;
    } else {
      if (gx_ == x) k = (gy_ - y) * dy;
    }
    return k > 0 ? k : 0;
  }

  // The straight jump from (x, y): the goal if the jump reaches it, else the first jump point.
  template <int DIR, class Emit>
  void straight(int x, int y, std::uint32_t id, Emit& emit) const {
    const int k = goal_ahead<DIR>(x, y);
    int travelled = 0;
    for (;;) {
      const std::int8_t v = tab_.at(id, DIR);
      if (v == kJumpHop) {
        if (k > 0 && k - travelled <= kJumpHopSteps) break;
        travelled += kJumpHopSteps;
        id += static_cast<std::uint32_t>(kJumpHopSteps) * step<DIR>();
        continue;
      }
      if (k > 0 && k - travelled <= (v < 0 ? -v : v)) break;
      if (v > 0) {
        const int n = travelled + v;
        emit(x + kJpsDx[DIR] * n, y + kJpsDy[DIR] * n, static_cast<std::uint8_t>(DIR));
      }
      return;
    }
    emit(gx_, gy_, static_cast<std::uint8_t>(DIR));
  }

  // True when a straight jump from `id` reaches a target k > 0 steps ahead (no obstacle and no
  // jump point before it).
  template <int DIR>
  bool reaches(std::uint32_t id, int k) const {
    for (;;) {
      const std::int8_t v = tab_.at(id, DIR);
      if (v != kJumpHop) return k <= (v < 0 ? -v : v);
      if (k <= kJumpHopSteps) return true;
      k -= kJumpHopSteps;
      id += static_cast<std::uint32_t>(kJumpHopSteps) * step<DIR>();
    }
  }

  template <int DX, int DY, class Emit>
  void diagonal(int x, int y, std::uint32_t id, Emit& emit) const {
    constexpr int ddir = DX > 0 ? (DY < 0 ? kJpsNorthEast : kJpsSouthEast) : (DY < 0 ? kJpsNorthWest : kJpsSouthWest);
    constexpr int hdir = DX > 0 ? kJpsEast : kJpsWest;
    constexpr int vdir = DY > 0 ? kJpsSouth : kJpsNorth;
    const std::uint32_t dstep = step<ddir>();
    for (;;) {
      const std::int8_t d = tab_.at(id, ddir);
      if (d == 0) return;
      const bool hop = d == kJumpHop;
      const int r = hop ? kJumpHopSteps : (d < 0 ? -d : d);
      // The goal strictly inside this diagonal's quadrant, within reach: the diagonal crosses
      // the goal's row or column at t; from there a straight jump may reach the goal.
      const int kx = (gx_ - x) * DX, ky = (gy_ - y) * DY;
      if (kx > 0 && ky > 0) {
        const int m = std::min(kx, ky);
        if (m <= r) {
          if (kx == ky) {
            emit(gx_, gy_, static_cast<std::uint8_t>(ddir));
            return;
          }
          const std::uint32_t t = id + static_cast<std::uint32_t>(m) * dstep;
          if (kx < ky ? reaches<vdir>(t, ky - m) : reaches<hdir>(t, kx - m))
            emit(gx_, gy_, static_cast<std::uint8_t>(kx < ky ? vdir : hdir));
        }
      }
      if (!hop && d < 0) return;
      x += DX * r;
      y += DY * r;
      id += static_cast<std::uint32_t>(r) * dstep;
      if (!hop) {  // a diagonal jump point: its straight jumps are successors of the node
        straight<vdir>(x, y, id, emit);
        straight<hdir>(x, y, id, emit);
      }
    }
  }

  const JumpTable& tab_;
  int width_;
  int gx_ = 0;
  int gy_ = 0;
};

void check_options(const GridPlannerOptions& options, const char* name) {
  if (options.connectivity != 8)
    throw Error(std::string(name) + " needs 8-connected moves (connectivity 8), got connectivity " +
                    std::to_string(options.connectivity),
                {}, 0, "connectivity");
  if (options.weight != 1.0)
    throw Error(std::string(name) + " is optimal A* on jump points and takes no weight (weight must be 1)", {}, 0,
                "weight");
  if (!options.heuristic.empty() && options.heuristic != "octile")
    throw Error(std::string(name) + " uses the octile heuristic only, got '" + options.heuristic + "'", {}, 0,
                "heuristic");
}

template <bool kPlus>
class JpsPlanner final : public GridPlanner {
 public:
  JpsPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options)
      : geometry_(grid.geometry()), record_trace_(options.record_trace) {
    const auto t0 = Clock::now();
    width_ = grid.width();
    height_ = grid.height();
    const std::vector<std::uint8_t> blocked = grid.blocked_mask(options.thresholds, options.unknown_is_free);
    rows_ = BitGrid(blocked, width_, height_, false);
    if constexpr (kPlus) {
      table_ = JumpTable(rows_);
    } else {
      cols_ = BitGrid(blocked, width_, height_, true);
    }
    states_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), NodeState{0, 0, 0, 0});
    open_.reserve(1024);
    preprocess_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }

  std::string_view name() const override { return kPlus ? "jpsplus" : "jps"; }
  bool admissible() const override { return true; }
  double preprocess_ms() const override { return preprocess_ms_; }
  const std::vector<Cell>& trace() const override { return trace_; }

  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits) override {
    PlanResult result;
    trace_.clear();
    if (!geometry_.contains(start)) {
      result.status = PlanStatus::StartOutsideMap;
      return result;
    }
    if (!geometry_.contains(goal)) {
      result.status = PlanStatus::GoalOutsideMap;
      return result;
    }
    if (!rows_.free(rows_.index(start.x, start.y))) {
      result.status = PlanStatus::StartBlocked;
      return result;
    }
    if (!rows_.free(rows_.index(goal.x, goal.y))) {
      result.status = PlanStatus::GoalBlocked;
      return result;
    }
    const auto t0 = Clock::now();
    result.status = search(start, goal, limits, result);
    if (result.status == PlanStatus::Found) build_path(start, goal);
    result.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (result.status == PlanStatus::Found) {
      const NodeState& g = states_[cell_id(goal.x, goal.y)];
      result.cost = (static_cast<double>(g.ga) + static_cast<double>(g.gb) * kSqrt2) * geometry_.resolution;
      result.length = result.cost;
      result.path_cells = path_;
      result.path_world.reserve(path_.size());
      for (const Cell& c : path_) result.path_world.push_back(geometry_.cell_center(c));
    }
    return result;
  }

 private:
  std::uint32_t cell_id(int x, int y) const {
    return static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(width_) + static_cast<std::uint32_t>(x);
  }

  void next_generation() {
    if (++generation_ > kMaxGeneration) {  // wrapped: forget every stamp once
      for (NodeState& s : states_) s.meta = 0;
      generation_ = 1;
    }
  }

  PlanStatus search(Cell start, Cell goal, const SearchLimits& limits, PlanResult& result) {
    next_generation();
    open_.clear();
    const std::uint32_t gen = generation_;
    const std::uint32_t gen_bits = gen << kGenerationShift;
    const int gx = goal.x, gy = goal.y;
    const std::uint32_t goal_id = cell_id(gx, gy);
    const std::uint32_t start_id = cell_id(start.x, start.y);
    const bool timed = limits.time_budget_s > 0.0 && limits.time_budget_s < 1e9;  // beyond: no limit
    const auto deadline = timed ? Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                     std::chrono::duration<double>(limits.time_budget_s))
                                : Clock::time_point{};
    std::uint64_t expanded = 0, generated = 0;

    auto jumper = make_jumper();
    jumper.set_goal(gx, gy);

    auto h_of = [gx, gy](int x, int y, std::uint32_t& ha, std::uint32_t& hb) {
      const std::uint32_t dx = static_cast<std::uint32_t>(std::abs(x - gx));
      const std::uint32_t dy = static_cast<std::uint32_t>(std::abs(y - gy));
      hb = std::min(dx, dy);
      ha = std::max(dx, dy) - hb;
    };

    {
      NodeState& s = states_[start_id];
      s.meta = gen_bits | kStartDir;
      s.parent = start_id;
      s.ga = 0;
      s.gb = 0;
      std::uint32_t ha, hb;
      h_of(start.x, start.y, ha, hb);
      open_.push(open_key(static_cast<double>(ha) + static_cast<double>(hb) * kSqrt2, 0.0, start_id));
      ++generated;
    }

    PlanStatus status = PlanStatus::NoPath;
    const std::uint32_t stride = rows_.stride();
    while (!open_.empty()) {
      const std::uint32_t id = open_key_id(open_.pop());
      NodeState& node = states_[id];
      if (node.meta & kClosedBit) continue;  // stale entry of a node improved after it was pushed
      if (limits.max_expansions && expanded >= limits.max_expansions) {
        status = PlanStatus::ExpansionLimit;
        break;
      }
      if (limits.cancel && limits.cancel->load(std::memory_order_relaxed)) {
        status = PlanStatus::Cancelled;
        break;
      }
      if (timed && (expanded & 63u) == 0 && Clock::now() >= deadline) {
        status = PlanStatus::TimeLimit;
        break;
      }
      node.meta |= kClosedBit;
      ++expanded;
      const int x = static_cast<int>(id % static_cast<std::uint32_t>(width_));
      const int y = static_cast<int>(id / static_cast<std::uint32_t>(width_));
      if (record_trace_) trace_.push_back({x, y});
      if (id == goal_id) {
        status = PlanStatus::Found;
        break;
      }
      const std::uint32_t ga = node.ga, gb = node.gb;

      auto emit = [&](int sx, int sy, std::uint8_t sdir) {
        const std::uint32_t sid = cell_id(sx, sy);
        const std::uint32_t adx = static_cast<std::uint32_t>(std::abs(sx - x));
        const std::uint32_t ady = static_cast<std::uint32_t>(std::abs(sy - y));
        const std::uint32_t eb = std::min(adx, ady);
        const std::uint32_t na = ga + (std::max(adx, ady) - eb), nb = gb + eb;
        const double g = static_cast<double>(na) + static_cast<double>(nb) * kSqrt2;
        NodeState& s = states_[sid];
        if ((s.meta >> kGenerationShift) == gen) {
          if (s.meta & kClosedBit) return;
          if (!(g < static_cast<double>(s.ga) + static_cast<double>(s.gb) * kSqrt2)) return;
        }
        s.meta = gen_bits | sdir;
        s.parent = id;
        s.ga = na;
        s.gb = nb;
        std::uint32_t ha, hb;
        h_of(sx, sy, ha, hb);
        open_.push(open_key(static_cast<double>(na + ha) + static_cast<double>(nb + hb) * kSqrt2, g, sid));
        ++generated;
      };

      // Successor directions: natural and forced neighbours (2014 rules, no corner cutting).
      unsigned dirs;
      const std::uint32_t d = node.meta & kDirMask;
      if (d >= kStartDir) {
        dirs = 0xFFu;
      } else if (d >= kJpsNorthEast) {
        // Diagonal arrival: the two straight components and the diagonal itself.
        static constexpr unsigned kDiag[4] = {
            (1u << kJpsNorth) | (1u << kJpsEast) | (1u << kJpsNorthEast),
            (1u << kJpsSouth) | (1u << kJpsEast) | (1u << kJpsSouthEast),
            (1u << kJpsSouth) | (1u << kJpsWest) | (1u << kJpsSouthWest),
            (1u << kJpsNorth) | (1u << kJpsWest) | (1u << kJpsNorthWest),
        };
        dirs = kDiag[d - kJpsNorthEast];
      } else {
        const std::uint32_t i = rows_.index(x, y);
        const std::uint32_t up = rows_.bits3(i - stride - 1);  // bit 0 NW, 1 N, 2 NE
        const std::uint32_t mid = rows_.bits3(i - 1);          // bit 0 W, 2 E
        const std::uint32_t dn = rows_.bits3(i + stride - 1);  // bit 0 SW, 1 S, 2 SE
        switch (d) {
          case kJpsEast:
            dirs = 1u << kJpsEast;
            if ((up & 3u) == 2u) dirs |= (1u << kJpsNorth) | (1u << kJpsNorthEast);
            if ((dn & 3u) == 2u) dirs |= (1u << kJpsSouth) | (1u << kJpsSouthEast);
            break;
          case kJpsWest:
            dirs = 1u << kJpsWest;
            if ((up & 6u) == 2u) dirs |= (1u << kJpsNorth) | (1u << kJpsNorthWest);
            if ((dn & 6u) == 2u) dirs |= (1u << kJpsSouth) | (1u << kJpsSouthWest);
            break;
          case kJpsNorth:
            dirs = 1u << kJpsNorth;
            if ((mid & 1u) && !(dn & 1u)) dirs |= (1u << kJpsWest) | (1u << kJpsNorthWest);
            if ((mid & 4u) && !(dn & 4u)) dirs |= (1u << kJpsEast) | (1u << kJpsNorthEast);
            break;
          default:  // kJpsSouth
            dirs = 1u << kJpsSouth;
            if ((mid & 1u) && !(up & 1u)) dirs |= (1u << kJpsWest) | (1u << kJpsSouthWest);
            if ((mid & 4u) && !(up & 4u)) dirs |= (1u << kJpsEast) | (1u << kJpsSouthEast);
            break;
        }
      }
      while (dirs) {
        const int dir = __builtin_ctz(dirs);
        dirs &= dirs - 1;
        jumper.jump(dir, x, y, id, emit);
      }
    }
    result.expanded = expanded;
    result.generated = generated;
    return status;
  }

  auto make_jumper() const {
    if constexpr (kPlus) return TableJumper(table_, width_);
    else return OnlineJumper(rows_, cols_);
  }

  // The cell path: jump points from the parent links, each leg walked diagonal-first (every
  // leg of this search is an octile-shortest move sequence of that shape).
  void build_path(Cell start, Cell goal) {
    jump_points_.clear();
    const std::uint32_t start_id = cell_id(start.x, start.y);
    for (std::uint32_t id = cell_id(goal.x, goal.y);; id = states_[id].parent) {
      jump_points_.push_back(id);
      if (id == start_id) break;
    }
    path_.clear();
    path_.push_back(start);
    for (std::size_t k = jump_points_.size() - 1; k-- > 0;) {
      const std::uint32_t to = jump_points_[k];
      const int tx = static_cast<int>(to % static_cast<std::uint32_t>(width_));
      const int ty = static_cast<int>(to / static_cast<std::uint32_t>(width_));
      Cell c = path_.back();
      const int sx = tx > c.x ? 1 : (tx < c.x ? -1 : 0);
      const int sy = ty > c.y ? 1 : (ty < c.y ? -1 : 0);
      while (c.x != tx && c.y != ty) {
        c.x += sx;
        c.y += sy;
        path_.push_back(c);
      }
      while (c.x != tx) {
        c.x += sx;
        path_.push_back(c);
      }
      while (c.y != ty) {
        c.y += sy;
        path_.push_back(c);
      }
    }
  }

  GridGeometry geometry_;
  bool record_trace_ = false;
  int width_ = 0;
  int height_ = 0;
  BitGrid rows_;
  BitGrid cols_;       // transposed copy (online JPS only)
  JumpTable table_;  // JPS+ only
  std::vector<NodeState> states_;
  std::uint32_t generation_ = 0;
  OpenList open_;
  std::vector<std::uint32_t> jump_points_;
  std::vector<Cell> path_;
  std::vector<Cell> trace_;
  double preprocess_ms_ = 0.0;
};

}  // namespace

std::unique_ptr<GridPlanner> make_jps_planner(const OccupancyGrid& grid, const GridPlannerOptions& options,
                                              bool jump_tables) {
  check_options(options, jump_tables ? "jpsplus" : "jps");
  if (jump_tables) return std::make_unique<JpsPlanner<true>>(grid, options);
  return std::make_unique<JpsPlanner<false>>(grid, options);
}

}  // namespace starnav
