#pragma once
// Point-cloud files: PCD v0.7 (ascii, binary and binary_compressed, as PCL writes them), PLY
// (ascii, binary little and big endian) and KITTI's Velodyne .bin frames (float32 x, y, z,
// reflectance; gzipped too). Only x, y and z are read; other fields are skipped. Points with a
// non-finite coordinate (an organised cloud's holes) are dropped and counted. Writers use a fixed
// number format, so the same points give the same bytes.
//
// Every reader fails with one Error naming the file and the field ("FIELDS", "POINTS", "DATA",
// "element vertex", "size", ...), and refuses a file claiming more than kMaxCloudPoints points
// before allocating for it.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/core/input_file.hpp"  // kMaxCloudPoints

namespace starnav {

enum class PointCloudFormat { Ply, Pcd };
enum class PointCloudEncoding { Ascii, Binary };

struct PointCloudFile {
  PointCloud points;
  std::size_t dropped_non_finite = 0;
};

// By content: "ply" magic, a PCD header, else (extension .bin, gzipped or not) a KITTI frame.
PointCloudFile read_point_cloud(const std::string& path);
// From bytes already in memory; `path` names them in errors.
PointCloudFile parse_pcd(std::string_view bytes, const std::string& path);
PointCloudFile parse_ply(std::string_view bytes, const std::string& path);
PointCloudFile parse_kitti_bin(std::string_view bytes, const std::string& path);

// The file's text or bytes (ascii: 6 decimals, metres; binary: float32).
std::string format_point_cloud(std::span<const Vec3> points, PointCloudFormat format,
                               PointCloudEncoding encoding = PointCloudEncoding::Ascii);
// Throws Error naming the file when it cannot be written.
void write_point_cloud(const std::string& path, std::span<const Vec3> points, PointCloudFormat format,
                       PointCloudEncoding encoding = PointCloudEncoding::Ascii);

// The LZF decompression of PCD's binary_compressed data (exactly `size` bytes out).
std::string lzf_decompress(std::string_view in, std::size_t size, const std::string& path);

}  // namespace starnav
