#pragma once
// The KITTI odometry benchmark's files (Geiger et al. 2012) and SemanticKITTI's labels (Behley et
// al. 2019): pose files (per line the row-major 3 x 4 matrix [R|t] of the left camera at frame k
// in the camera frame of frame 0, optionally after a time column), the Velodyne-to-camera
// calibration Tr of each sequence, and per-point labels (uint32: class in the low 16 bits).
// Frames themselves are read by cloud_io (read_point_cloud: .bin, gzipped too).
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/cloud/point_cloud.hpp"

namespace starnav {

// Pose files; `time_column`: each line starts with the frame's time (13 values). Errors name the
// file and line.
std::vector<Rigid3> read_kitti_poses(const std::string& path, bool time_column = false);

// Tr (p_cam0 = Tr p_velo) of an odometry sequence "00".."10", from KITTI's data_odometry_calib
// (sequences 00-02 share one calibration day, 04-10 another; 03 is not known here: Error).
Rigid3 kitti_velodyne_to_camera(const std::string& sequence);

// The rigid transform of a row-major 3 x 4 [R|t] as KITTI writes it (9 digits), its rotation
// re-orthonormalised so that products of many stay rigid. Error naming `path`, `line` and `field`
// when R is not a rotation (to 1e-3).
Rigid3 rigid_from_kitti_3x4(const double (&m)[12], const std::string& path, int line, const std::string& field);

// The LiDAR's pose in the reference frame of the camera poses: L_k = P_k Tr.
Rigid3 kitti_lidar_pose(const Rigid3& camera_pose, const Rigid3& velodyne_to_camera);

// The semantic class of every point of a .label file (gzipped too).
std::vector<std::uint16_t> read_kitti_labels(const std::string& path);

// SemanticKITTI's ground classes: road, parking, sidewalk, other-ground, lane-marking, terrain.
bool is_kitti_ground_class(std::uint16_t label);

}  // namespace starnav
