#pragma once
// Occupancy grid as ROS nav_msgs/OccupancyGrid: int8 0..100 (percent occupied), -1 unknown.
// Row-major, row iy = 0 at the bottom for metric maps (conventions.md); MovingAI maps keep their
// own rows (y_down). Planners read the three derived states, or a precomputed blocked mask.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/core/grid_geometry.hpp"

namespace starnav {

enum class CellState : std::uint8_t { Free, Occupied, Unknown };

inline constexpr std::int8_t kUnknownOccupancy = -1;
inline constexpr std::int8_t kFreeOccupancy = 0;
inline constexpr std::int8_t kOccupiedOccupancy = 100;

// How occupancy values become states (conventions.md defaults: >= 65 occupied, <= 19.6 free,
// values between are occupied unless `between_is_free`).
struct OccupancyThresholds {
  double occupied_percent = 65.0;
  double free_percent = 19.6;
  bool between_is_free = false;

  CellState classify(std::int8_t v) const {
    if (v < 0) return CellState::Unknown;
    if (v >= occupied_percent) return CellState::Occupied;
    if (v <= free_percent) return CellState::Free;
    return between_is_free ? CellState::Free : CellState::Occupied;
  }
};

struct OccupancyCounts {
  std::size_t free = 0;
  std::size_t occupied = 0;
  std::size_t unknown = 0;
};

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  // Throws Error for a non-positive size or resolution, or a non-finite origin.
  explicit OccupancyGrid(const GridGeometry& geometry, std::int8_t fill = kFreeOccupancy);

  const GridGeometry& geometry() const { return geometry_; }
  GridGeometry& mutable_geometry() { return geometry_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }
  double resolution() const { return geometry_.resolution; }
  const Pose2& origin() const { return geometry_.origin; }
  std::size_t cell_count() const { return data_.size(); }
  bool contains(int ix, int iy) const { return geometry_.contains(ix, iy); }

  // Unchecked access for inner loops.
  std::int8_t operator()(int ix, int iy) const { return data_[geometry_.index(ix, iy)]; }
  std::int8_t& operator()(int ix, int iy) { return data_[geometry_.index(ix, iy)]; }
  std::int8_t operator[](std::size_t i) const { return data_[i]; }

  // Checked access: throws std::out_of_range outside the map; `set` throws Error for a value
  // outside -1..100.
  std::int8_t at(int ix, int iy) const;
  void set(int ix, int iy, std::int8_t value);

  CellState state(int ix, int iy, const OccupancyThresholds& t = {}) const { return t.classify((*this)(ix, iy)); }

  std::span<const std::int8_t> data() const { return data_; }
  std::span<std::int8_t> data() { return data_; }

  OccupancyCounts counts(const OccupancyThresholds& t = {}) const;

  // 1 where a planner may not enter: occupied cells, and unknown cells unless unknown_is_free.
  std::vector<std::uint8_t> blocked_mask(const OccupancyThresholds& t = {}, bool unknown_is_free = false) const;
  // The same into `mask` (resized; its memory is reused when it already holds enough).
  void blocked_mask(std::vector<std::uint8_t>& mask, const OccupancyThresholds& t = {},
                    bool unknown_is_free = false) const;

  friend bool operator==(const OccupancyGrid& a, const OccupancyGrid& b) {
    return a.geometry_.width == b.geometry_.width && a.geometry_.height == b.geometry_.height &&
           a.geometry_.resolution == b.geometry_.resolution && a.geometry_.origin.x == b.geometry_.origin.x &&
           a.geometry_.origin.y == b.geometry_.origin.y && a.geometry_.origin.yaw == b.geometry_.origin.yaw &&
           a.geometry_.y_down == b.geometry_.y_down && a.data_ == b.data_;
  }

 private:
  GridGeometry geometry_;
  std::vector<std::int8_t> data_;
};

// Validates a geometry (positive size and resolution, finite origin, at most 2^31 cells);
// throws Error naming `what` otherwise.
void validate_geometry(const GridGeometry& g, const char* what = "map");

}  // namespace starnav
