#pragma once
// Shortest paths of a car-like robot between two poses, ignoring obstacles: Dubins curves (forward
// only) and Reeds-Shepp curves (forward and reverse), for a minimum turning radius R. They are the
// analytic expansions and the non-holonomic heuristic of a state-lattice or Hybrid-A* search.
//
// Conventions (REP-103): x forward, y left, headings in radians counter-clockwise from +x; lengths
// and R in metres. A path is a list of at most five segments, each a left turn (L, curvature
// +1/R), a straight (S) or a right turn (R, curvature -1/R), with a signed length: positive drives
// forward, negative in reverse. A Reeds-Shepp path reverses at a cusp where consecutive segments
// have opposite signs. The path's length is the sum of the absolute segment lengths.
//
// Dubins: the shortest of the six words LSL, RSR, LSR, RSL, RLR, LRL (Dubins 1957), found from
// the tangents between the turning circles. Reeds-Shepp: the shortest of the 48 words of Reeds &
// Shepp 1990 (the formulas of their section 8, each with its time-flip, reflection and, for the
// CCC and CCSC families, backwards variants, as OMPL's ReedsSheppStateSpace enumerates them).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class CurveSegmentKind : std::uint8_t { kLeft, kStraight, kRight };

struct CurveSegment {
  CurveSegmentKind kind = CurveSegmentKind::kStraight;
  double length = 0.0;  // metres, signed: negative drives in reverse
};

// A path from `start`: the segments in driving order. Segments of zero length are left out and
// consecutive segments of the same kind and direction merged, so a cusp is exactly a sign change
// between neighbours.
struct CarPath {
  Pose2 start;
  double radius = 1.0;  // metres
  std::array<CurveSegment, 5> segments{};
  std::size_t segment_count = 0;
  double length = 0.0;  // metres, sum of |segment length|

  // The signed curvature of a segment of this path (1/m): +1/R left, -1/R right, 0 straight.
  double curvature(const CurveSegment& segment) const;
  // The pose after driving `s` metres of the path from its start (s clamped to [0, length]).
  Pose2 pose_at(double s) const;
  // The pose at the end of the path.
  Pose2 end() const { return pose_at(length); }
  // Number of direction reversals.
  std::size_t cusp_count() const;
};

struct CarPathSample {
  Pose2 pose;          // heading wrapped into (-pi, pi]
  double s = 0.0;      // metres driven from the start (arc length, whatever the direction)
  int direction = 1;   // +1 forward, -1 reverse: the motion that leaves this sample (the last
                       // sample: the motion that arrives at it)
  bool cusp = false;   // the robot stops here and reverses
};

// Samples along the path: each stretch between cusps is sampled from its first point every `step`
// metres of arc length, plus its last point (a cusp or the goal), so consecutive samples are
// exactly `step` apart along the path except the last of each stretch, which is closer. The first
// sample is the start, the last the end; every cusp is a sample. Throws Error unless step > 0.
std::vector<CarPathSample> sample_car_path(const CarPath& path, double step);

// The shortest Dubins path (forward only) from `start` to `goal` with turning radius `radius` (m).
// Throws Error for a radius that is not positive and finite or a pose that is not finite.
CarPath shortest_dubins_path(const Pose2& start, const Pose2& goal, double radius);
// The shortest Reeds-Shepp path (forward and reverse); same contract.
CarPath shortest_reeds_shepp_path(const Pose2& start, const Pose2& goal, double radius);

// Every candidate word the searches above compare (the valid solutions of each formula under each
// symmetry), shortest or not: to check each formula reaches the goal.
std::vector<CarPath> dubins_candidates(const Pose2& start, const Pose2& goal, double radius);
std::vector<CarPath> reeds_shepp_candidates(const Pose2& start, const Pose2& goal, double radius);

// The word of a path, e.g. "L+S+R-" (kinds with the sign of each segment); "" for an empty path.
std::string car_path_word(const CarPath& path);

}  // namespace starnav
