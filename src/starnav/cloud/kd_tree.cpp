#include "starnav/cloud/kd_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nanoflann.hpp>

#include "starnav/core/error.hpp"

namespace starnav {

// Named (not anonymous): KdTree3::Impl holds these.
namespace kd_tree_detail {

struct CloudAdaptor {
  std::vector<Vec3> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return points[i][static_cast<Eigen::Index>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudAdaptor>, CloudAdaptor, 3,
                                                 std::uint32_t>;

// Radius results with the radius inclusive (nanoflann's own set excludes it).
struct InclusiveRadiusSet {
  double radius_sq;
  std::vector<Neighbour>* out;
  std::size_t size() const { return out->size(); }
  bool full() const { return true; }
  bool addPoint(double dist, std::uint32_t index) {
    if (dist <= radius_sq) out->push_back({index, dist});
    return true;
  }
  // nanoflann admits points strictly nearer than this.
  double worstDist() const { return std::nextafter(radius_sq, kInfinity); }
};

// Counts points within the radius and stops the search once `enough` are found.
struct CountingRadiusSet {
  double radius_sq;
  std::size_t enough;
  std::size_t count = 0;
  std::size_t size() const { return count; }
  bool full() const { return true; }
  bool addPoint(double dist, std::uint32_t) {
    if (dist <= radius_sq) ++count;
    return enough == 0 || count < enough;
  }
  // nanoflann admits points strictly nearer than this.
  double worstDist() const { return std::nextafter(radius_sq, kInfinity); }
};

}  // namespace kd_tree_detail

namespace {

using kd_tree_detail::CloudAdaptor;
using kd_tree_detail::Tree;
using kd_tree_detail::InclusiveRadiusSet;
using kd_tree_detail::CountingRadiusSet;

bool nearer(const Neighbour& a, const Neighbour& b) {
  return a.squared_distance < b.squared_distance || (a.squared_distance == b.squared_distance && a.index < b.index);
}

}  // namespace

// After the build the tree's own copy of the points is put in the order of its leaves (each
// leaf's points side by side in memory) and the tree's index table made the identity, so a search
// visits exactly the points and distances it did before, in the same order, but reads memory
// in sequence; `order` maps a leaf position back to the caller's index.
constexpr std::size_t kLeafSize = 24;

struct KdTree3::Impl {
  CloudAdaptor cloud;
  Tree tree;
  std::vector<Vec3> original;
  std::vector<std::uint32_t> order;
  explicit Impl(std::span<const Vec3> pts)
      : cloud{std::vector<Vec3>(pts.begin(), pts.end())},
        tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)),
        original(cloud.points) {
    order.assign(tree.vAcc.begin(), tree.vAcc.end());
    for (std::size_t j = 0; j < order.size(); ++j) {
      cloud.points[j] = original[order[j]];
      tree.vAcc[j] = static_cast<std::uint32_t>(j);
    }
  }
};

KdTree3::KdTree3(std::span<const Vec3> points) {
  if (points.size() > std::numeric_limits<std::uint32_t>::max()) throw Error("a point cloud of more than 2^32 points");
  impl_ = std::make_unique<Impl>(points);
}
KdTree3::~KdTree3() = default;
KdTree3::KdTree3(KdTree3&&) noexcept = default;
KdTree3& KdTree3::operator=(KdTree3&&) noexcept = default;

std::size_t KdTree3::size() const { return impl_->cloud.points.size(); }
const std::vector<Vec3>& KdTree3::points() const { return impl_->original; }
const std::vector<std::uint32_t>& KdTree3::leaf_order() const { return impl_->order; }

bool KdTree3::nearest(const Vec3& query, Neighbour& out) const {
  if (impl_->cloud.points.empty()) return false;
  std::uint32_t index = 0;
  double dist = 0.0;
  nanoflann::KNNResultSet<double, std::uint32_t> set(1);
  set.init(&index, &dist);
  impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams());
  out = {impl_->order[index], dist};
  return true;
}

bool KdTree3::nearest_within(const Vec3& query, double max_squared_distance, Neighbour& out) const {
  if (impl_->cloud.points.empty() || !(max_squared_distance >= 0)) return false;
  std::uint32_t index = 0;
  double dist = 0.0;
  nanoflann::KNNResultSet<double, std::uint32_t> set(1);
  set.init(&index, &dist);
  dist = std::nextafter(max_squared_distance, kInfinity);  // the set admits points strictly nearer
  impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams());
  if (set.size() == 0) return false;
  out = {impl_->order[index], dist};
  return true;
}

void KdTree3::k_nearest(const Vec3& query, std::size_t k, std::vector<Neighbour>& out) const {
  out.clear();
  k = std::min(k, size());
  if (k == 0) return;
  // Small k (local shapes: 20) searches into the stack: this runs once per point of a cloud.
  constexpr std::size_t kOnStack = 64;
  std::uint32_t idx_stack[kOnStack];
  double dist_stack[kOnStack];
  std::vector<std::uint32_t> idx_heap;
  std::vector<double> dist_heap;
  std::uint32_t* idx = idx_stack;
  double* dist = dist_stack;
  if (k > kOnStack) {
    idx_heap.resize(k);
    dist_heap.resize(k);
    idx = idx_heap.data();
    dist = dist_heap.data();
  }
  const std::size_t n = impl_->tree.knnSearch(query.data(), k, idx, dist);
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back({impl_->order[idx[i]], dist[i]});
  std::sort(out.begin(), out.end(), nearer);
}

std::size_t KdTree3::k_nearest(const Vec3& query, std::size_t k, std::uint32_t* indices, double* squared_distances,
                              double bound_sq) const {
  k = std::min(k, size());
  if (k == 0) return 0;
  nanoflann::KNNResultSet<double, std::uint32_t> set(k);
  set.init(indices, squared_distances);
  // The set admits only points nearer than its last slot: the bound prunes from the start.
  if (bound_sq < kInfinity) squared_distances[k - 1] = bound_sq;
  impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams());
  std::size_t n = set.size();
  if (n < k && bound_sq < kInfinity) {
    set.init(indices, squared_distances);
    impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams());
    n = set.size();
  }
  for (std::size_t i = 0; i < n; ++i) indices[i] = impl_->order[indices[i]];
  return n;
}

void KdTree3::within_radius(const Vec3& query, double radius, std::vector<Neighbour>& out) const {
  out.clear();
  if (!(radius >= 0) || impl_->cloud.points.empty()) return;
  InclusiveRadiusSet set{radius * radius, &out};
  impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams(32, 0.0F, false));
  for (Neighbour& n : out) n.index = impl_->order[n.index];
  std::sort(out.begin(), out.end(), nearer);
}

std::size_t KdTree3::count_within_radius(const Vec3& query, double radius, std::size_t enough) const {
  if (!(radius >= 0) || impl_->cloud.points.empty()) return 0;
  CountingRadiusSet set{radius * radius, enough};
  impl_->tree.findNeighbors(set, query.data(), nanoflann::SearchParams(32, 0.0F, false));
  return set.count;
}

}  // namespace starnav
