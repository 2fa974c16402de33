#pragma once
// A flat hash from voxel keys to dense indices 0, 1, 2, ... in the order the voxels were first
// inserted (open addressing, linear probing, at most half full): neighbours by voxel lookup where
// exact nearest neighbours are not needed (VGICP). A voxel of side `resolution` at integer
// coordinates (ix, iy, iz) = floor(p / resolution) has one 63-bit key; coordinates beyond
// +-2^20 voxels on an axis (1,048 km at 1 m) have none.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "starnav/core/geometry.hpp"

namespace starnav {

class VoxelHash {
 public:
  static constexpr std::uint64_t kNoKey = ~std::uint64_t{0};
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  static constexpr std::int64_t kAxisLimit = std::int64_t{1} << 20;

  explicit VoxelHash(double resolution_m = 1.0);
  double resolution() const { return resolution_; }
  std::size_t size() const { return size_; }

  // The key of the voxel holding p, moved by (dx, dy, dz) voxels; kNoKey when out of range or p
  // is not finite.
  std::uint64_t key_of(const Vec3& p, int dx = 0, int dy = 0, int dz = 0) const;
  // The integer coordinates of the voxel holding p; false when out of range or not finite.
  bool coords_of(const Vec3& p, std::int64_t out[3]) const;
  static std::uint64_t key_of_coords(std::int64_t ix, std::int64_t iy, std::int64_t iz);
  // The index of `key`, added as size() when new. `key` must not be kNoKey.
  std::uint32_t insert(std::uint64_t key);
  // The index of `key`, or kNone.
  std::uint32_t find(std::uint64_t key) const {
    if (key == kNoKey) return kNone;
    for (std::uint64_t h = mix(key) & mask_;; h = (h + 1) & mask_) {
      if (keys_[h] == key) return slots_[h];
      if (keys_[h] == kNoKey) return kNone;
    }
  }

 private:
  static std::uint64_t mix(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    return x;
  }
  void grow();

  double resolution_ = 1.0, inv_resolution_ = 1.0;
  std::vector<std::uint64_t> keys_;  // kNoKey marks an empty slot
  std::vector<std::uint32_t> slots_;
  std::uint64_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace starnav
