#pragma once
// Pictures of a navigation run (paper Li 2019 Figs. 33-38):
//   scene    the final navigation map from above (observed cells grey, darker the higher their mid
//            height; one grey in 2D mode; unobserved near white), raw blocked cells red, the band pink, every
//            plan P1, P2, ... in its own colour and labelled at its start, the executed trajectory
//            thick black, start, goal and goal tolerance, the true obstacles' footprints as thin
//            outlines (dynamic ones where they appear, moving ones with their path dashed);
//   overlay  planned vs executed as an XY plot in metres with equal axes (LinePlot).
// Both are deterministic (no time stamps; the same run gives the same bytes).
//
// The pictures are drawn from a NavigationPictureData, which a NavigationRun fills
// (navigation_picture_data) and tests can fill by hand without running a simulation.
#include <span>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/nav/navigator.hpp"
#include "starnav/costmap/layered_costmap.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

// What the pictures show; views into the run (or the test's objects), which must outlive it.
struct NavigationPictureData {
  std::string name;                     // scenario name, for titles
  std::string status;                   // e.g. "arrived" (titles; empty: left out)
  double end_time_s = 0.0;              // the trajectory's last time (titles, moving obstacles)
  const LayeredCostmap* map = nullptr;  // required
  std::span<const NavPlan> plans;
  std::vector<Vec2> trajectory;         // executed x/y
  Pose2 start;
  Vec2 goal = Vec2::Zero();
  double goal_tolerance_m = 0.0;        // 0: no circle
  std::span<const Obstacle> obstacles;  // true obstacles (empty: none drawn)
  // The robot's outline along the executed trajectory and where its driving direction changed
  // (drawn for runs planned between poses, where the body's fit is the point; empty: none).
  std::vector<std::vector<Vec2>> footprints;  // closed outlines in the map frame
  std::vector<Vec2> reversals;
};

// Outlines of `body` at poses of `trajectory` every `spacing_m` of travel, at every change of
// driving direction and at the end, and the places of those changes. The direction is the sign of
// the body's forward speed where it moves faster than `moving_mps`.
struct FootprintTrail {
  std::vector<std::vector<Vec2>> outlines;
  std::vector<Vec2> reversals;
};
FootprintTrail footprint_trail(std::span<const TrajectorySample> trajectory, const FootprintModel& body,
                               double spacing_m = 0.25, double moving_mps = 0.01);

// The true obstacles' outlines from above (sim/outline), as both scene pictures draw them (this
// one and starnav sim's scripted scene.svg): an obstacle that appears after `end_time_s` is left
// out; one with a lifetime or a motion is drawn where it appears (or at t = 0) in `appearing`,
// the others in `fixed`; a moving one also gets its path up to min(disappear, end_time_s) in
// `motion`. The first outline of each kind carries its label.
struct ObstacleOutlineStyle {
  viz::LineStyle fixed, appearing, motion;
  std::string fixed_label, appearing_label;
};
void add_obstacle_outlines(viz::MapPicture& pic, std::span<const Obstacle> obstacles, double end_time_s,
                           const ObstacleOutlineStyle& style);

// From a run (after run(): the final map, every plan, the recorded trajectory).
NavigationPictureData navigation_picture_data(const NavigationRun& run);

// The pictures themselves (throw Error for a missing map or non-finite coordinates).
viz::MapPicture navigation_scene_picture(const NavigationPictureData& data);
viz::LinePlot navigation_overlay_plot(const NavigationPictureData& data);
// The same layers over the map's extent as a raster-capable picture (overlay.png).
viz::MapPicture navigation_overlay_raster(const NavigationPictureData& data);

// .svg or .png by the file's extension. Throw Error naming the file for another extension or
// when it cannot be written.
void write_navigation_scene(const NavigationRun& run, const std::string& path);
void write_navigation_scene(const NavigationPictureData& data, const std::string& path);
void write_navigation_overlay(const NavigationRun& run, const std::string& path);
void write_navigation_overlay(const NavigationPictureData& data, const std::string& path);

}  // namespace starnav
