// starnav cloud register: one 3D registration of a scan (SOURCE) onto a reference cloud (TARGET)
// with a matcher from the registry (docs/mapping3d.md), as the Python bindings' starnav.register
// runs it (docs/python.md).
//
//   starnav cloud register SOURCE TARGET [--matcher gicp] [--set KEY=VALUE ...]
//                          [--initial X,Y,Z,ROLL,PITCH,YAW] [--voxel-m L] [--json]
//
// The clouds are PCD, PLY or KITTI .bin files (cloud/cloud_io.hpp). The transform maps SOURCE's
// points into TARGET's frame (target ~= T * source); --initial is the guess it starts from (m,
// degrees). --voxel-m thins both clouds with the voxel grid first. Exit 0 when the match
// converged, 1 when it stopped at max_iterations, 2 bad input.
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::cli {

namespace {

struct RegisterOptions {
  std::string source, target;
  std::string matcher = "gicp";
  std::vector<std::string> sets;
  std::string initial;
  double voxel_m = 0.0;
  bool json = false;
};

void run_cloud_register(const RegisterOptions& o, Context& ctx) {
  const std::vector<ParamSetting> settings = parse_set_options(o.sets);
  std::unique_ptr<ScanMatcher3d> matcher = find_scan_matcher_3d(o.matcher, "--matcher").make({}, settings);
  Rigid3 initial = Rigid3::Identity();
  if (!o.initial.empty()) {
    const std::vector<double> p = parse_number_list(o.initial, "--initial", 6, "X,Y,Z,ROLL,PITCH,YAW (m, degrees)");
    initial = to_rigid(Pose3::from_rpy(Vec3(p[0], p[1], p[2]), deg_to_rad(p[3]), deg_to_rad(p[4]), deg_to_rad(p[5])));
  }
  if (!(o.voxel_m >= 0.0)) throw Error("must be >= 0 (0: no voxel grid)", {}, 0, "--voxel-m");
  PointCloud source = read_point_cloud(o.source).points, target = read_point_cloud(o.target).points;
  if (o.voxel_m > 0.0) {
    source = voxel_downsample(source, o.voxel_m);
    target = voxel_downsample(target, o.voxel_m);
  }
  const CloudMatch m = register_clouds(*matcher, target, source, initial);
  nlohmann::ordered_json j;
  j["matcher"] = std::string(matcher->name());
  j["converged"] = m.converged;
  j["fitness"] = m.fitness;
  j["iterations"] = m.iterations;
  j["source_points"] = source.size();
  j["target_points"] = target.size();
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m.transform(r, 0), m.transform(r, 1), m.transform(r, 2), m.transform(r, 3)});
  j["transform"] = rows;
  j["time_s"] = m.time_s;
  if (o.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "matcher:     " << j["matcher"].get<std::string>() << (m.converged ? " (converged" : " (not converged")
              << " after " << m.iterations << " iterations)\n";
    std::cout << "points:      " << source.size() << " source, " << target.size() << " target\n";
    std::cout << "fitness:     " << m.fitness << " m^2\n";
    std::cout << "transform:   (source -> target)\n";
    for (int r = 0; r < 4; ++r)
      std::cout << "  " << m.transform(r, 0) << " " << m.transform(r, 1) << " " << m.transform(r, 2) << " "
                << m.transform(r, 3) << "\n";
  }
  ctx.exit_code = m.converged ? 0 : 1;
}

}  // namespace

void register_cloud_commands(CLI::App& app, Context& ctx) {
  auto* cloud = app.add_subcommand("cloud", "point clouds: 3D registration (docs/mapping3d.md)");
  cloud->require_subcommand(1);
  auto o = std::make_shared<RegisterOptions>();
  std::string names;
  for (const ScanMatcher3dDef& d : scan_matchers_3d()) names += (names.empty() ? "" : ", ") + d.info.name;
  auto* reg = cloud->add_subcommand(
      "register", "the rigid transform that lays SOURCE onto TARGET (PCD, PLY or KITTI .bin) with a 3D matcher");
  reg->add_option("SOURCE", o->source, "the scan to move")->required();
  reg->add_option("TARGET", o->target, "the reference cloud")->required();
  reg->add_option("--matcher", o->matcher, names + " (default gicp; parameters: starnav params --role scan_matcher_3d)");
  reg->add_option("--set", o->sets, "a parameter of the matcher, KEY=VALUE (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  reg->add_option("--initial", o->initial, "the guess X,Y,Z,ROLL,PITCH,YAW of source in target (m, degrees; default identity)");
  reg->add_option("--voxel-m", o->voxel_m, "thin both clouds with a voxel grid of this leaf first (m; 0: none)");
  reg->add_flag("--json", o->json, "one JSON object: matcher, converged, fitness, iterations, source_points, target_points, "
                                   "transform (4 x 4, row by row), time_s");
  reg->callback([o, &ctx] { run_cloud_register(*o, ctx); });
}

}  // namespace starnav::cli
