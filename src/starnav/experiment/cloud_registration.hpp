#pragma once
// One 3D registration as a run: a scan (source) laid onto a reference cloud (target) by a matcher
// of the registry with its declared parameters, from a guess, the clouds optionally thinned by the
// voxel grid first. `starnav cloud register` runs it on files and prints its JSON; the Python
// bindings' starnav.register run it on arrays (docs/python.md), so the two give the same transform.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"

namespace starnav {

struct CloudRegistrationRequest {
  std::string matcher = "gicp";        // a registry name (or deprecated alias) of a 3D matcher
  std::vector<ParamSetting> settings;  // its declared parameters
  Rigid3 initial = Rigid3::Identity(); // the guess of source in target's frame
  double voxel_leaf_m = 0.0;           // > 0: both clouds through the voxel grid first
  std::string matcher_field = "matcher";  // where the name was given, for errors
};

struct CloudRegistration {
  std::string matcher;  // its registry name
  CloudMatch match;     // transform: source frame -> target frame (target ~= T * source)
  std::size_t source_points = 0, target_points = 0;  // after the voxel grid
};

// Errors: an unknown matcher (naming matcher_field), bad settings (naming the setting), a negative
// voxel leaf ("voxel_leaf_m"), a reference too small for the method. `warning` gets a deprecated
// alias's warning.
CloudRegistration register_cloud_points(std::span<const Vec3> source, std::span<const Vec3> target,
                                        const CloudRegistrationRequest& request, std::string* warning = nullptr);
// The same on cloud files (PCD, PLY, KITTI .bin; cloud/cloud_io.hpp).
CloudRegistration register_cloud_files(const std::string& source, const std::string& target,
                                       const CloudRegistrationRequest& request, std::string* warning = nullptr);

// One JSON line: matcher, converged, fitness, iterations, source_points, target_points, transform
// (4 x 4, row by row), time_s.
std::string cloud_registration_json(const CloudRegistration& r);

}  // namespace starnav
