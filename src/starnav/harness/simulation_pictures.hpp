#pragma once
// The pictures and point clouds of a scripted simulation run (`starnav sim` without a navigation
// section; docs/scenarios.md, "What starnav sim writes"): the top view with obstacles, reference
// line, trajectory and collisions; z(t); the XY track against the static obstacles; and a writer
// of every n-th LiDAR scan as a point cloud. Navigation runs have theirs in navigation_pictures.
#include <string>

#include "starnav/sim/simulation.hpp"

namespace starnav {

void write_scene_svg(const Simulation& sim, const std::string& path);
void write_height_trace(const Simulation& sim, const std::string& path);
void write_track(const Simulation& sim, const std::string& path);

// Point clouds of every n-th scan (scenario outputs.point_clouds) into OUT/clouds/ (a recorder of the
// first LiDAR's scans); nothing when the scenario asks for none. Throws Error naming the
// folder when it cannot be created.
void add_cloud_writer(Simulation& sim, const ScenarioSpec& spec, const std::string& out);

}  // namespace starnav
