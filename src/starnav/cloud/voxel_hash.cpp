#include "starnav/cloud/voxel_hash.hpp"

#include <cmath>

#include "starnav/core/error.hpp"

namespace starnav {

VoxelHash::VoxelHash(double resolution_m) : resolution_(resolution_m), inv_resolution_(1.0 / resolution_m) {
  if (!(std::isfinite(resolution_m) && resolution_m > 0)) throw Error("voxel hash: the resolution must be > 0");
  keys_.assign(16, kNoKey);
  slots_.assign(16, 0);
  mask_ = 15;
}

std::uint64_t VoxelHash::key_of_coords(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
  if (ix < -kAxisLimit || iy < -kAxisLimit || iz < -kAxisLimit || ix >= kAxisLimit || iy >= kAxisLimit ||
      iz >= kAxisLimit)
    return kNoKey;
  const auto u = [](std::int64_t i) { return static_cast<std::uint64_t>(i + kAxisLimit); };
  return (u(iz) << 42) | (u(iy) << 21) | u(ix);
}

bool VoxelHash::coords_of(const Vec3& p, std::int64_t out[3]) const {
  const double x = std::floor(p.x() * inv_resolution_), y = std::floor(p.y() * inv_resolution_),
               z = std::floor(p.z() * inv_resolution_);
  constexpr double lim = static_cast<double>(kAxisLimit);
  // Written so that NaN fails too.
  if (!(std::abs(x) <= lim && std::abs(y) <= lim && std::abs(z) <= lim)) return false;
  out[0] = static_cast<std::int64_t>(x);
  out[1] = static_cast<std::int64_t>(y);
  out[2] = static_cast<std::int64_t>(z);
  return true;
}

std::uint64_t VoxelHash::key_of(const Vec3& p, int dx, int dy, int dz) const {
  std::int64_t c[3];
  if (!coords_of(p, c)) return kNoKey;
  return key_of_coords(c[0] + dx, c[1] + dy, c[2] + dz);
}

std::uint32_t VoxelHash::insert(std::uint64_t key) {
  if (key == kNoKey) throw Error("voxel hash: a point outside the hash's range");
  if (2 * (size_ + 1) > keys_.size()) grow();
  std::uint64_t h = mix(key) & mask_;
  while (keys_[h] != kNoKey) {
    if (keys_[h] == key) return slots_[h];
    h = (h + 1) & mask_;
  }
  keys_[h] = key;
  slots_[h] = static_cast<std::uint32_t>(size_);
  return static_cast<std::uint32_t>(size_++);
}

void VoxelHash::grow() {
  std::vector<std::uint64_t> old_keys(2 * keys_.size(), kNoKey);
  std::vector<std::uint32_t> old_slots(2 * slots_.size(), 0);
  old_keys.swap(keys_);
  old_slots.swap(slots_);
  mask_ = keys_.size() - 1;
  for (std::size_t i = 0; i < old_keys.size(); ++i) {
    if (old_keys[i] == kNoKey) continue;
    std::uint64_t h = mix(old_keys[i]) & mask_;
    while (keys_[h] != kNoKey) h = (h + 1) & mask_;
    keys_[h] = old_keys[i];
    slots_[h] = old_slots[i];
  }
}

}  // namespace starnav
