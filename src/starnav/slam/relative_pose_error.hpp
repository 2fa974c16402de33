#pragma once
// The relative-pose error of Kümmerle et al. 2009 ("On measuring the accuracy of SLAM
// algorithms"): for each relation (i, j, delta*) of a benchmark file, the estimated relation
// delta = x_i^-1 * x_j is compared with delta*: the translation error |t(delta*^-1 * delta)| (m,
// equal to |t(delta) - t(delta*)|) and the rotation error |wrap(yaw(delta) - yaw(delta*))|. The
// benchmark's tables give their mean and standard deviation over all relations.
//
// Relation files: `t_i t_j dx dy dz droll dpitch dyaw` per line (whitespace separated, '#'
// comments). A relation stamp is matched to the trajectory pose nearest in time within one unit of
// its last printed decimal (1 us for 6 decimals, exact for the bag-made logs; 10 us for
// mit-csail's 5 decimals, whose stamps sit up to 5e-6 s off the log's).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/slam/log_mapping.hpp"

namespace starnav {

struct PoseRelation {
  std::int64_t t_i_us = 0, t_j_us = 0;
  std::int64_t tolerance_us = 0;  // one unit of the printed stamps' last decimal
  Pose2 delta;                    // pose j in the frame of pose i
  int line = 0;
};

// Throws Error naming the file, line and column; `whole` false: the head of a file (a file
// without a relation is refused only whole).
std::vector<PoseRelation> parse_relations(std::string_view text, const std::string& path, bool whole = true);
std::vector<PoseRelation> read_relations(const std::string& path);

struct RelativePoseError {
  SampleStats translation_m;  // of the evaluated relations (n of them)
  SampleStats rotation_deg;
  double translation_p95_m = 0;  // the 95th percentile (linear between order statistics)
  std::size_t relations = 0;   // in the file
  std::size_t unmatched = 0;   // relations with an end not in the trajectory
  std::vector<double> translation_each_m;  // per relation in file order; NaN where unmatched
};

// How many relations `e` gets wrong by more than `reference` does plus `margin_m` (translation),
// both evaluated on the same relations (a SLAM run against the odometry's). Throws when the two
// were not made from the same relations.
std::size_t relations_worse_than(const RelativePoseError& e, const RelativePoseError& reference, double margin_m = 0.0);

// The translation errors of short relations (their poses at most `max_short_s` apart in time: the
// benchmark's relations between nearby poses, which a local matcher's accuracy sets) and of long
// ones (across loops, which closures set), each with its 95th percentile. Throws when `e` was not
// made from `relations`.
inline constexpr double kShortRelationS = 10.0;
struct RelationSpans {
  SampleStats short_m, long_m;
  double short_p95_m = 0.0, long_p95_m = 0.0;
};
RelationSpans relation_spans(const RelativePoseError& e, const std::vector<PoseRelation>& relations, double max_short_s = kShortRelationS);

// `trajectory`: one pose per scan (any order; stamps unique). `offset` moves every pose by it
// before comparing (base -> laser: the laser's mount on the base).
RelativePoseError relative_pose_error(const std::vector<TrajectoryPose>& trajectory, const std::vector<PoseRelation>& relations,
                                      const Pose2& offset = {});

// The report of `starnav slam eval`: text or one JSON object, for the base and for the laser.
std::string rpe_text(const RelativePoseError& base, const std::optional<RelativePoseError>& laser, const Pose2& offset);
std::string rpe_json(const RelativePoseError& base, const std::optional<RelativePoseError>& laser, const Pose2& offset);

}  // namespace starnav
