// One 3D registration as a run (experiment/cloud_registration.hpp): a known motion recovered by the
// registry's matchers on points and on files, the voxel grid applied to both clouds, the JSON's
// transform the match's, and bad input named.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/experiment/cloud_registration.hpp"

namespace starnav {
namespace {

// A floor, two walls and a bump: every motion is observable.
PointCloud room() {
  Rng rng(5);
  PointCloud p;
  for (int i = 0; i < 1500; ++i) {
    p.emplace_back(rng.uniform(-5, 5), rng.uniform(-5, 5), 0.0);
    p.emplace_back(5.0, rng.uniform(-5, 5), rng.uniform(0, 3));
    p.emplace_back(rng.uniform(-5, 5), -5.0, rng.uniform(0, 3));
    const double u = rng.uniform(-1.5, 1.5), v = rng.uniform(-1.5, 1.5);
    p.emplace_back(u - 2, v + 2, std::exp(-(u * u + v * v)));
  }
  return p;
}

TEST(CloudRegistration, RecoversAKnownMotionAndReportsIt) {
  const PointCloud target = room();
  const Rigid3 truth = to_rigid(Pose3::from_rpy(Vec3(0.25, -0.15, 0.03), 0.01, -0.01, 0.06));
  const PointCloud source = transform_cloud(target, truth.inverse());
  for (const char* matcher : {"icp", "gicp", "ndt"}) {
    CloudRegistrationRequest rq;
    rq.matcher = matcher;
    if (std::string(matcher) == "ndt") rq.settings = {{"resolution_m", "1", "", 0, ""}};
    const CloudRegistration r = register_cloud_points(source, target, rq);
    EXPECT_EQ(r.matcher, matcher);
    EXPECT_TRUE(r.match.converged) << matcher;
    EXPECT_LT(translation_norm(truth.inverse() * r.match.transform), 0.01) << matcher;
    EXPECT_LT(rotation_angle(truth.inverse() * r.match.transform), 0.002) << matcher;
    EXPECT_EQ(r.source_points, source.size());
    const nlohmann::json j = nlohmann::json::parse(cloud_registration_json(r));
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col) EXPECT_EQ(j["transform"][row][col].get<double>(), r.match.transform(row, col));
    EXPECT_EQ(j["fitness"].get<double>(), r.match.fitness);
  }
}

TEST(CloudRegistration, FilesAndTheVoxelGridGiveWhatThePointsDo) {
  const PointCloud target = room();
  const PointCloud source = transform_cloud(target, to_rigid(Pose3::from_rpy(Vec3(-0.2, 0.1, 0.0), 0, 0, -0.04)));
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("starnav-cloudreg-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string s = (dir / "s.ply").string(), t = (dir / "t.pcd").string();
  write_point_cloud(s, source, PointCloudFormat::Ply, PointCloudEncoding::Binary);
  write_point_cloud(t, target, PointCloudFormat::Pcd, PointCloudEncoding::Binary);
  CloudRegistrationRequest rq;
  rq.voxel_leaf_m = 0.3;
  const CloudRegistration from_files = register_cloud_files(s, t, rq);
  const PointCloud s_read = read_point_cloud(s).points, t_read = read_point_cloud(t).points;
  CloudRegistrationRequest thinned = rq;
  thinned.voxel_leaf_m = 0.0;
  const CloudRegistration from_points =
      register_cloud_points(voxel_downsample(s_read, 0.3), voxel_downsample(t_read, 0.3), thinned);
  EXPECT_TRUE(from_files.match.transform.matrix() == from_points.match.transform.matrix());
  EXPECT_EQ(from_files.source_points, voxel_downsample(s_read, 0.3).size());
  std::filesystem::remove_all(dir);
}

TEST(CloudRegistration, BadInputIsNamed) {
  const PointCloud target = room();
  CloudRegistrationRequest rq;
  rq.matcher = "nosuch";
  rq.matcher_field = "--matcher";
  try {
    register_cloud_points(target, target, rq);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--matcher");
  }
  rq.matcher = "gicp";
  rq.voxel_leaf_m = -1;
  EXPECT_THROW(register_cloud_points(target, target, rq), Error);
  rq.voxel_leaf_m = 0;
  rq.settings = {{"max_iterations", "0", "", 0, "--set max_iterations"}};
  try {
    register_cloud_points(target, target, rq);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--set max_iterations: must be in [1, 10000], found '0'");
  }
}

}  // namespace
}  // namespace starnav
