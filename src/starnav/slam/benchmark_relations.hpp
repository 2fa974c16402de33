#pragma once
// Relation files made from a trajectory's truth as the SLAM benchmark's were made from corrected
// poses (Kümmerle et al. 2009): relations between nearby poses, a chain of key poses along the
// trajectory, plus relations across loops, pairs of key poses far apart along the trajectory but
// close in space. Written in the benchmark's .relations format (`t_i t_j dx dy 0 0 0 dyaw`, stamps
// with 6 decimals), so `starnav slam eval`, `slam run --relations` and `bench slam` evaluate them
// exactly like the real logs' files (docs/slam.md, "Large buildings").
//
// The rule, on the poses in time order:
// - key poses: the first pose, then every pose after `key_distance_m` of travel or `key_angle_deg`
//   of turning (the sum of the absolute yaw changes) since the previous key pose;
// - local relations: every pair of consecutive key poses;
// - loop relations: for every `loop_every`-th key pose i and each later visit to its place (a run
//   of consecutive key poses j, at least `loop_min_travel_m` of travel after i, within
//   `loop_max_distance_m` of it), one relation to the key pose of that visit nearest to i (the
//   earliest of equals). The travel floor is what makes a pair a loop: the odometry's error
//   between its ends has grown, and only a closed loop brings it back.
#include <vector>

#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/relative_pose_error.hpp"

namespace starnav {

struct RelationRule {
  double key_distance_m = 0.5;
  double key_angle_deg = 20.0;
  double loop_max_distance_m = 2.0;
  double loop_min_travel_m = 50.0;
  int loop_every = 4;
};

struct BenchmarkRelations {
  std::vector<PoseRelation> relations;  // the local ones first, then the loops, each in time order of t_i
  std::size_t key_poses = 0, local = 0, loops = 0;
};

// `poses`: in time order, stamps increasing (a simulator's truth at each scan). Throws Error for a
// rule out of range or stamps that do not increase.
BenchmarkRelations make_benchmark_relations(const std::vector<TrajectoryPose>& poses, const RelationRule& rule);

// The benchmark's format: one `t_i t_j dx dy 0.000000 0.000000 0.000000 dyaw` line per relation.
std::string relations_text(const std::vector<PoseRelation>& relations);

// The truth at every scan of a simulated log (TRUEPOS interpolated at the scan's stamp), as the
// laser's pose where the log states a mount (the benchmark's relations describe the laser).
std::vector<TrajectoryPose> log_truth_at_scans(const RobotLog& log);

}  // namespace starnav
