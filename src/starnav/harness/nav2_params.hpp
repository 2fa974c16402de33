#pragma once
// Nav2 parameter files (the `NODE: ros__parameters: KEY: VALUE` YAML that nav2_bringup ships and
// robots configure) read as starnav settings (docs/ros2.md, "Nav2 parameter files"): the keys starnav
// has an equivalent for are mapped to its declared parameters with their units converted (Nav2's
// angles are radians, starnav's degrees), every other key is listed as ignored with the reason.
// `sim --params FILE` and `localize --params FILE` apply the mapped settings before `--set`;
// `starnav params --nav2 FILE` prints the whole mapping.
//
//  - amcl: alpha1-5, laser_model_type, z_hit/z_rand/z_short/z_max, sigma_hit, lambda_short,
//    laser_likelihood_max_dist, laser_max_range/laser_min_range (-1: the laser's own),
//    max_beams, min/max_particles, pf_err, pf_z, recovery_alpha_slow/fast, resample_interval,
//    update_min_d, update_min_a (rad -> deg), robot_model_type -> localization.amcl.* (sim, when
//    the scenario's localizer is amcl) or amcl.* (localize);
//  - controller_server: the DWB plugin's velocity and acceleration limits (rad -> deg), samples,
//    sim_time and critics' scales -> navigation.dwa.* (when the scenario's controller is dwa);
//    Regulated Pure Pursuit's desired_linear_vel and lookahead_dist -> navigation.follower.*
//    (when it is path_follower); the goal checker's xy/yaw_goal_tolerance -> navigation.*;
//  - local_costmap: inflation_layer.inflation_radius and cost_scaling_factor -> navigation.dwa.*;
//    global_costmap: robot_radius -> navigation.map.barrier_distance_m.
// A mapped value outside the starnav parameter's range is an Error naming the file, the line and
// both keys.
#include <string>
#include <vector>

#include "starnav/core/params.hpp"

namespace starnav {

// What the settings are for: a scenario run (its components decide which sections exist) or
// `starnav localize` (AMCL only).
struct Nav2Target {
  enum class Kind { Scenario, Localize } kind = Kind::Scenario;
  bool navigation = false;         // the scenario has a navigation section
  std::string localizer;           // the scenario's localizer ("" without localization)
  std::string controller;          // the scenario's controller
  std::string goal_checker = "latching";  // the scenario's goal checker
};

struct Nav2Key {
  std::string nav2;       // "amcl.update_min_a", "controller_server.FollowPath.max_vel_x"
  int line = 0;
  std::string value;      // as the file writes it
  std::string starnav;    // "localization.amcl.update_min_a_deg"; empty when ignored
  std::string converted;  // the value in starnav's unit
  std::string note;       // mapped: the conversion ("rad -> deg"); ignored: why
};

struct Nav2Params {
  std::string file;
  std::vector<Nav2Key> mapped, ignored;
  // The mapped keys as settings ("localization.amcl.alpha1" = "0.2", from FILE:LINE).
  std::vector<ParamSetting> settings() const;
};

// Throws Error naming the file (and line and keys) for a file that is not a Nav2 parameter file or a
// mapped value starnav refuses.
Nav2Params read_nav2_params(const std::string& path, const Nav2Target& target);

std::string nav2_params_text(const Nav2Params& p);
std::string nav2_params_json(const Nav2Params& p);

}  // namespace starnav
