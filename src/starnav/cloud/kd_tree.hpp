#pragma once
// A k-d tree over a 3D point cloud (nanoflann underneath, exact searches): nearest neighbour,
// k nearest and all within a radius. The tree keeps its own copy of the points, so the cloud it
// was built from may go away. Results are deterministic: ties keep the lower index first.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"

namespace starnav {

struct Neighbour {
  std::uint32_t index = 0;
  double squared_distance = 0.0;
};

class KdTree3 {
 public:
  explicit KdTree3(std::span<const Vec3> points);
  ~KdTree3();
  KdTree3(KdTree3&&) noexcept;
  KdTree3& operator=(KdTree3&&) noexcept;
  KdTree3(const KdTree3&) = delete;
  KdTree3& operator=(const KdTree3&) = delete;

  std::size_t size() const;
  const std::vector<Vec3>& points() const;
  // The points' indices in the order of the tree's leaves: queries made in this order find their
  // neighbours in memory the previous query touched.
  const std::vector<std::uint32_t>& leaf_order() const;

  // The nearest point; false for an empty tree.
  bool nearest(const Vec3& query, Neighbour& out) const;
  // The nearest point at most sqrt(max_squared_distance) away; false when there is none. Faster
  // than nearest() where far points are not wanted: the search prunes with the limit from the start.
  bool nearest_within(const Vec3& query, double max_squared_distance, Neighbour& out) const;
  // Up to k nearest points, nearest first (fewer when the tree is smaller).
  void k_nearest(const Vec3& query, std::size_t k, std::vector<Neighbour>& out) const;
  // The same into caller's arrays of k, without the tie order: nearest first as the search
  // found them; returns how many. A bound_sq at least the k-th squared distance (strictly above
  // it) only speeds the search up; a bound too small costs a second search, never a wrong answer.
  std::size_t k_nearest(const Vec3& query, std::size_t k, std::uint32_t* indices, double* squared_distances,
                        double bound_sq = kInfinity) const;
  // Every point within `radius` (inclusive), nearest first.
  void within_radius(const Vec3& query, double radius, std::vector<Neighbour>& out) const;
  // How many points lie within `radius`, stopping early once `enough` are found (0: count all).
  std::size_t count_within_radius(const Vec3& query, double radius, std::size_t enough = 0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace starnav
