#pragma once
// Elevation map: per cell a representative height, the min and max height seen in the cell
// (for 3D-node traversability), and whether the cell was observed at all. A NaN or infinite
// height is never stored: setters throw Error, and unobserved cells hold 0 with observed = false.
#include <cstdint>
#include <optional>
#include <vector>

#include "starnav/core/grid_geometry.hpp"

namespace starnav {

struct HeightRange {
  double min = 0.0;
  double max = 0.0;
};

class ElevationMap {
 public:
  ElevationMap() = default;
  // All cells unobserved. Throws Error for a bad geometry.
  explicit ElevationMap(const GridGeometry& geometry);

  const GridGeometry& geometry() const { return geometry_; }
  GridGeometry& mutable_geometry() { return geometry_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }
  double resolution() const { return geometry_.resolution; }
  const Pose2& origin() const { return geometry_.origin; }
  std::size_t cell_count() const { return height_.size(); }
  bool contains(int ix, int iy) const { return geometry_.contains(ix, iy); }

  // Unchecked reads for inner loops.
  double height_at(int ix, int iy) const { return height_[geometry_.index(ix, iy)]; }
  double min_height_at(int ix, int iy) const { return min_[geometry_.index(ix, iy)]; }
  double max_height_at(int ix, int iy) const { return max_[geometry_.index(ix, iy)]; }
  bool observed_at(int ix, int iy) const { return observed_[geometry_.index(ix, iy)] != 0; }
  double height_at_index(std::size_t i) const { return height_[i]; }
  bool observed_at_index(std::size_t i) const { return observed_[i] != 0; }

  // Checked read: nothing for an unobserved cell; std::out_of_range outside the map.
  std::optional<double> height_checked(int ix, int iy) const;

  // Marks a cell observed with one height (min = max = h). Throws Error for a non-finite h,
  // std::out_of_range outside the map.
  void set_height(int ix, int iy, double h);
  // Marks a cell observed with a height and its spread; requires min <= h <= max, all finite.
  void set_cell(int ix, int iy, double h, double min_h, double max_h);
  // Marks a cell unobserved.
  void clear_cell(int ix, int iy);

  // Range of observed heights (min of min, max of max); nothing when no cell is observed.
  std::optional<HeightRange> height_range() const;
  std::size_t observed_count() const;

  const std::vector<double>& heights() const { return height_; }
  const std::vector<double>& min_heights() const { return min_; }
  const std::vector<double>& max_heights() const { return max_; }
  const std::vector<std::uint8_t>& observed() const { return observed_; }

  friend bool operator==(const ElevationMap&, const ElevationMap&);

 private:
  void check_inside(int ix, int iy) const;
  GridGeometry geometry_;
  std::vector<double> height_;
  std::vector<double> min_;
  std::vector<double> max_;
  std::vector<std::uint8_t> observed_;
};

}  // namespace starnav
