// starnav's GICP-class matchers beside small_gicp's GICP and VGICP (Koide 2024), side by side
// in one process on the 27 KITTI pairs `starnav bench kitti` registers: the same frames, the
// same prefilter (3-80 m window, 0.25 m voxels), from the identity, one thread unless told.
// Built only when the peer's sources are given (cmake -DSTARNAV_PEER_SMALL_GICP=DIR, a checkout
// outside the tree; docs/benchmarks.md). Timed per match: both clouds' k-d trees and covariances,
// the voxel map where there is one, and the alignment (starnav's time also holds its fitness
// score, which small_gicp does not compute); the clouds handed over in each library's own point
// type, converted before the clock starts. Rounds are interleaved (round r runs every pair with
// every method before round r + 1); a method's time is the median over the rounds of its median
// over the pairs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <small_gicp/ann/gaussian_voxelmap.hpp>
#include <small_gicp/ann/kdtree.hpp>
#include <small_gicp/factors/gicp_factor.hpp>
#include <small_gicp/points/point_cloud.hpp>
#include <small_gicp/registration/reduction.hpp>
#include <small_gicp/registration/reduction_omp.hpp>
#include <small_gicp/registration/registration.hpp>
#include <small_gicp/util/normal_estimation.hpp>
#include <small_gicp/util/normal_estimation_omp.hpp>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/kitti_dataset.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/kitti_registration_experiment.hpp"
#include "starnav/registry/components.hpp"

namespace fs = std::filesystem;
using namespace starnav;

namespace {

struct Pair {
  std::size_t reference, scan;  // cloud indices
  Rigid3 truth;
};

struct Method {
  std::string label;
  // Registers scan onto reference; returns the transform (scan -> reference) and the iterations.
  std::function<Rigid3(std::size_t reference, std::size_t scan, int& iterations)> run;
  std::vector<std::vector<double>> times;  // [round][pair]
  std::vector<double> t_err, r_err;        // round 0
  double iterations = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

ParamSetting setting(const std::string& key, const std::string& value) {
  ParamSetting s;
  s.key = key;
  s.value = value;
  s.field = key;
  return s;
}

int usage() {
  std::fprintf(stderr,
               "usage: bench_peer_small_gicp [--dataset DIR] [--rounds N] [--threads N] [--neighbours K] [--only TEXT]\n"
               "  the 27 KITTI pairs of starnav bench kitti, starnav's gicp and vgicp beside small_gicp's\n"
               "  GICP and VGICP; --threads adds rows on N threads (default 1: none); --only keeps the\n"
               "  methods whose label holds TEXT\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) try {
  std::string dataset = "../shared/datasets/lidar3d/kitti_odometry_mini";
  int rounds = 5, threads = 1, k = 20;
  std::string only;  // run only the methods whose label holds this
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help") return usage(), 0;
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    if (a == "--dataset") dataset = v;
    else if (a == "--rounds") rounds = std::atoi(v.c_str());
    else if (a == "--threads") threads = std::atoi(v.c_str());
    else if (a == "--neighbours") k = std::atoi(v.c_str());
    else if (a == "--only") only = v;
    else return usage();
  }
  if (rounds < 1 || threads < 1 || k < 3) return usage();

  // The frames, prefiltered as starnav bench kitti does, and the reference motions.
  const KittiRegistrationConfig kc;
  std::vector<PointCloud> clouds;
  std::vector<Pair> pairs;
  for (const std::string& seq : kc.sequences) {
    const fs::path dir = fs::path(dataset) / "sequences" / seq;
    const bool semantic = seq == "00";
    const std::vector<Rigid3> poses =
        semantic ? read_kitti_poses((dir / "poses.txt").string())
                 : read_kitti_poses((fs::path(dataset) / "ground_truth" / "egusa" / (seq + ".txt")).string(), true);
    const Rigid3 tr = kitti_velodyne_to_camera(seq);
    const std::size_t first = clouds.size();
    for (int f = 0; f < kc.frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "%06d.bin.gz", f);
      fs::path file = dir / "velodyne" / name;
      if (!fs::exists(file)) file.replace_extension();  // plain .bin
      clouds.push_back(prefilter_cloud(read_point_cloud(file.string()).points, kc.prefilter));
      if (f > 0)
        pairs.push_back({first + f - 1, first + f,
                         kitti_lidar_pose(poses[f - 1], tr).inverse() * kitti_lidar_pose(poses[f], tr)});
    }
  }
  std::vector<small_gicp::PointCloud::Ptr> peer_clouds;
  for (const PointCloud& c : clouds) {
    std::vector<Eigen::Vector3d> pts(c.begin(), c.end());
    peer_clouds.push_back(std::make_shared<small_gicp::PointCloud>(pts));
  }

  std::vector<Method> methods;
  auto add_starnav = [&](const std::string& label, const std::string& name, std::vector<ParamSetting> settings) {
    std::shared_ptr<ScanMatcher3d> m = find_scan_matcher_3d(name).make({}, settings);
    methods.push_back({label, [&clouds, m](std::size_t r, std::size_t s, int& it) {
                         const CloudMatch cm = register_clouds(*m, clouds[r], clouds[s]);
                         it = cm.iterations;
                         return cm.transform;
                       }});
  };
  // small_gicp's own termination (registration_helper's defaults) for a row of starnav's beside it.
  const std::vector<ParamSetting> peer_limits = {setting("max_iterations", "20"), setting("translation_tolerance_m", "0.001"),
                                                 setting("rotation_tolerance_deg", "0.1")};
  auto add_peer = [&](const std::string& label, bool voxels, int n_threads) {
    methods.push_back({label, [&peer_clouds, voxels, n_threads, k](std::size_t r, std::size_t s, int& it) {
                         // The clouds' covariances are recomputed each time, as starnav's are.
                         auto target = std::make_shared<small_gicp::PointCloud>(*peer_clouds[r]);
                         auto source = std::make_shared<small_gicp::PointCloud>(*peer_clouds[s]);
                         small_gicp::KdTree<small_gicp::PointCloud> target_tree(target);
                         small_gicp::KdTree<small_gicp::PointCloud> source_tree(source);
                         if (n_threads == 1) {
                           small_gicp::estimate_covariances(*target, target_tree, k);
                           small_gicp::estimate_covariances(*source, source_tree, k);
                         } else {
                           small_gicp::estimate_covariances_omp(*target, target_tree, k, n_threads);
                           small_gicp::estimate_covariances_omp(*source, source_tree, k, n_threads);
                         }
                         small_gicp::RegistrationResult result;
                         if (n_threads == 1) {
                           small_gicp::Registration<small_gicp::GICPFactor, small_gicp::SerialReduction> reg;
                           if (voxels) {
                             small_gicp::GaussianVoxelMap voxelmap(1.0);
                             voxelmap.insert(*target);
                             result = reg.align(voxelmap, *source, voxelmap, Eigen::Isometry3d::Identity());
                           } else {
                             result = reg.align(*target, *source, target_tree, Eigen::Isometry3d::Identity());
                           }
                         } else {
                           small_gicp::Registration<small_gicp::GICPFactor, small_gicp::ParallelReductionOMP> reg;
                           reg.reduction.num_threads = n_threads;
                           if (voxels) {
                             small_gicp::GaussianVoxelMap voxelmap(1.0);
                             voxelmap.insert(*target);
                             result = reg.align(voxelmap, *source, voxelmap, Eigen::Isometry3d::Identity());
                           } else {
                             result = reg.align(*target, *source, target_tree, Eigen::Isometry3d::Identity());
                           }
                         }
                         it = static_cast<int>(result.iterations);
                         Rigid3 t = Rigid3::Identity();
                         t.matrix() = result.T_target_source.matrix();
                         return t;
                       }});
  };
  const std::string ks = std::to_string(k);
  add_starnav("starnav gicp", "gicp", {setting("covariance_neighbours", ks)});
  add_starnav("starnav vgicp", "vgicp", {setting("covariance_neighbours", ks)});
  {
    std::vector<ParamSetting> s = peer_limits;
    s.push_back(setting("covariance_neighbours", ks));
    add_starnav("starnav vgicp, small_gicp's termination", "vgicp", s);
  }
  add_peer("small_gicp GICP", false, 1);
  add_peer("small_gicp VGICP", true, 1);
  if (threads > 1) {
    const std::string ts = std::to_string(threads);
    add_starnav("starnav gicp, " + ts + " threads", "gicp", {setting("covariance_neighbours", ks), setting("threads", ts)});
    add_starnav("starnav vgicp, " + ts + " threads", "vgicp", {setting("covariance_neighbours", ks), setting("threads", ts)});
    add_peer("small_gicp VGICP, " + ts + " threads (OpenMP)", true, threads);
  }

  std::erase_if(methods, [&](const Method& m) { return m.label.find(only) == std::string::npos; });
  for (Method& m : methods) m.times.assign(static_cast<std::size_t>(rounds), std::vector<double>(pairs.size()));
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      for (Method& m : methods) {
        int iterations = 0;
        const auto start = std::chrono::steady_clock::now();
        const Rigid3 t = m.run(pairs[p].reference, pairs[p].scan, iterations);
        m.times[static_cast<std::size_t>(round)][p] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (round == 0) {
          const Rigid3 e = pairs[p].truth.inverse() * t;
          m.t_err.push_back(translation_norm(e));
          m.r_err.push_back(rotation_angle(e) * 180.0 / kPi);
          m.iterations += iterations / static_cast<double>(pairs.size());
        }
      }
    }
    std::fprintf(stderr, "round %d of %d done\n", round + 1, rounds);
  }
  std::printf("%zu pairs, %d rounds, %d covariance neighbours\n\n", pairs.size(), rounds, k);
  std::printf("| method | translation error mean / max (cm) | rotation error mean / max (deg) | iterations | time per match (ms) | rounds' medians (ms) |\n");
  std::printf("|---|---:|---:|---:|---:|---|\n");
  for (const Method& m : methods) {
    std::vector<double> per_round;
    for (const std::vector<double>& t : m.times) per_round.push_back(median(t));
    std::string rounds_text;
    for (double t : per_round) rounds_text += (rounds_text.empty() ? "" : " ") + std::to_string(1000 * t).substr(0, 5);
    double tm = 0, rm = 0;
    for (double e : m.t_err) tm += e / static_cast<double>(m.t_err.size());
    for (double e : m.r_err) rm += e / static_cast<double>(m.r_err.size());
    std::printf("| %s | %.3f / %.2f | %.4f / %.3f | %.1f | %.1f | %s |\n", m.label.c_str(), 100 * tm,
                100 * *std::max_element(m.t_err.begin(), m.t_err.end()), rm,
                *std::max_element(m.r_err.begin(), m.r_err.end()), m.iterations, 1000 * median(per_round),
                rounds_text.c_str());
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_peer_small_gicp: error: %s\n", e.what());
  return 1;
}
