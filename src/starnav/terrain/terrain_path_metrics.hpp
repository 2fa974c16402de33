#pragma once
// Metrics of a path on terrain (docs/papers/liu2024.md, the paper's Tables 2-4):
//
//   lv  3D length: sum over moves of sqrt(d^2 + (z2 - z1)^2), d the horizontal move length;
//   av  mean slope a = atan(h / d) over the path's moves (rad);
//   hv  mean height difference h = |z2 - z1| over the moves (m);
//   Sv  mean ruggedness S over the path's cells, start and goal included (m^2).
//   Moves with an unobserved end count in lv with their horizontal length and are left out of
//   av and hv; unobserved cells are left out of Sv (the counts say how many were used).
//
// Attitude: at every path node the robot's footprint (length x width, default 0.6 m x 0.4 m)
// is centred on the cell centre, heading along the path (the direction from the previous node
// to the next one; at the ends the direction of the first / last move). The heights under its
// four corners are interpolated bilinearly between cell centres (clamped to the outermost cell
// centres at the map border), and the least-squares plane through them gives, in the robot's
// heading frame, slopes px = dz/dx_forward and py = dz/dy_left (core/plane_fit.hpp):
//   pitch = -atan(px)                 (REP-103: positive pitch is nose down),
//   roll  = atan2(py, sqrt(1 + px^2)) (positive roll: left side up),
//   tilt  = atan(sqrt(px^2 + py^2))   (angle between the robot's z axis and the vertical),
// the roll and pitch of R = Rz(yaw) Ry(pitch) Rx(roll) whose x axis lies along the heading in
// the plane and whose z axis is the plane's normal. Summaries as Liu et al. 2024 report them: *_mean_deg is
// |mean of the signed angle| and *_max_deg the largest absolute angle, in degrees; the mean of
// the absolute angles is given too (*_mean_abs_deg). A node whose corners touch an unobserved
// cell (and no observed one to interpolate from) is left out of the attitude summaries.
#include <cstddef>
#include <span>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/plane_fit.hpp"
#include "starnav/terrain/terrain_analysis.hpp"

namespace starnav {

struct AttitudeSample {
  double s_m = 0.0;      // horizontal distance along the path from the start
  Vec2 position{0, 0};   // world
  double heading = 0.0;  // rad, world frame
  Attitude attitude;
};

struct TerrainPathMetrics {
  std::size_t nodes = 0;
  std::size_t moves = 0;
  std::size_t moves_measured = 0;  // moves with both ends observed (av, hv)
  std::size_t cells_measured = 0;  // observed path cells (Sv)
  std::size_t attitude_nodes = 0;  // nodes with a valid attitude
  double length_2d_m = 0.0;
  double lv_m = 0.0;
  double av_rad = 0.0;
  double hv_m = 0.0;
  double sv_m2 = 0.0;
  double roll_mean_deg = 0.0;  // |mean of roll|
  double roll_max_deg = 0.0;   // max |roll|
  double roll_mean_abs_deg = 0.0;
  double pitch_mean_deg = 0.0;
  double pitch_max_deg = 0.0;
  double pitch_mean_abs_deg = 0.0;
  double tilt_mean_deg = 0.0;
  double tilt_max_deg = 0.0;
};

// Height at a world point, bilinear between cell centres over the observed cells among the
// four (weights renormalised); clamped to the outermost centres at the border. False when none
// of the four is observed.
bool terrain_height_at(const TerrainAnalysis& analysis, const Vec2& world, double& z);

// Attitude of the footprint centred at `centre` (world) with heading `heading` (world yaw).
Attitude footprint_attitude(const TerrainAnalysis& analysis, const Vec2& centre, double heading,
                            const Footprint& footprint = {});

// Metrics of a path of 8-neighbour cells (every consecutive pair must be neighbours or equal;
// Error otherwise). `samples`, when given, receives the attitude at every node (the paper's
// Fig. 8 profiles).
TerrainPathMetrics terrain_path_metrics(const TerrainAnalysis& analysis, const std::vector<Cell>& path,
                                        const Footprint& footprint = {},
                                        std::vector<AttitudeSample>* samples = nullptr);

}  // namespace starnav
