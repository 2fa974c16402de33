#pragma once
// Point clouds as ASCII PLY (x y z float properties) and ASCII PCD v0.7 (FIELDS x y z), written
// with a fixed number format so the same points give the same bytes.
#include <span>
#include <string>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class PointCloudFormat { Ply, Pcd };

// The file's text (6 decimals, metres).
std::string format_point_cloud(std::span<const Vec3> points, PointCloudFormat format);
// Throws Error naming the file when it cannot be written.
void write_point_cloud(const std::string& path, std::span<const Vec3> points, PointCloudFormat format);

}  // namespace starnav
