#include "starnav/experiment/cloud_registration.hpp"

#include <memory>
#include <nlohmann/json.hpp>

#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/error.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace {

CloudRegistration run(std::span<const Vec3> source, std::span<const Vec3> target, const CloudRegistrationRequest& rq,
                      std::string* warning) {
  if (!(rq.voxel_leaf_m >= 0.0)) throw Error("must be >= 0 (0: no voxel grid)", {}, 0, "voxel_leaf_m");
  const std::unique_ptr<ScanMatcher3d> matcher =
      find_scan_matcher_3d(rq.matcher, rq.matcher_field, warning).make({}, rq.settings);
  PointCloud thinned_source, thinned_target;
  if (rq.voxel_leaf_m > 0.0) {
    thinned_source = voxel_downsample(source, rq.voxel_leaf_m);
    thinned_target = voxel_downsample(target, rq.voxel_leaf_m);
    source = thinned_source;
    target = thinned_target;
  }
  CloudRegistration r;
  r.match = register_clouds(*matcher, target, source, rq.initial);
  r.matcher = std::string(matcher->name());
  r.source_points = source.size();
  r.target_points = target.size();
  return r;
}

}  // namespace

CloudRegistration register_cloud_points(std::span<const Vec3> source, std::span<const Vec3> target,
                                        const CloudRegistrationRequest& request, std::string* warning) {
  return run(source, target, request, warning);
}

CloudRegistration register_cloud_files(const std::string& source, const std::string& target,
                                       const CloudRegistrationRequest& request, std::string* warning) {
  const PointCloud s = read_point_cloud(source).points, t = read_point_cloud(target).points;
  return run(s, t, request, warning);
}

std::string cloud_registration_json(const CloudRegistration& r) {
  const CloudMatch& m = r.match;
  nlohmann::ordered_json j;
  j["matcher"] = r.matcher;
  j["converged"] = m.converged;
  j["fitness"] = m.fitness;
  j["iterations"] = m.iterations;
  j["source_points"] = r.source_points;
  j["target_points"] = r.target_points;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int row = 0; row < 4; ++row)
    rows.push_back({m.transform(row, 0), m.transform(row, 1), m.transform(row, 2), m.transform(row, 3)});
  j["transform"] = rows;
  j["time_s"] = m.time_s;
  return j.dump() + "\n";
}

}  // namespace starnav
