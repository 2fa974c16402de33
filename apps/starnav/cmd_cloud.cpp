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
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/experiment/cloud_registration.hpp"
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
  CloudRegistrationRequest rq;
  rq.matcher = o.matcher;
  rq.matcher_field = "--matcher";
  rq.settings = parse_set_options(o.sets);
  if (!o.initial.empty()) {
    const std::vector<double> p = parse_number_list(o.initial, "--initial", 6, "X,Y,Z,ROLL,PITCH,YAW (m, degrees)");
    rq.initial = to_rigid(Pose3::from_rpy(Vec3(p[0], p[1], p[2]), deg_to_rad(p[3]), deg_to_rad(p[4]), deg_to_rad(p[5])));
  }
  rq.voxel_leaf_m = o.voxel_m;
  std::string warning;
  CloudRegistration r;
  try {
    r = register_cloud_files(o.source, o.target, rq, &warning);
  } catch (const Error& e) {
    if (e.field() == "voxel_leaf_m") throw Error(e.message(), {}, 0, "--voxel-m");
    throw;
  }
  if (!warning.empty()) print_warning("--matcher: " + warning);
  const CloudMatch& m = r.match;
  if (o.json) {
    std::cout << cloud_registration_json(r);
  } else {
    std::cout << "matcher:     " << r.matcher << (m.converged ? " (converged" : " (not converged") << " after "
              << m.iterations << " iterations)\n";
    std::cout << "points:      " << r.source_points << " source, " << r.target_points << " target\n";
    std::cout << "fitness:     " << m.fitness << " m^2\n";
    std::cout << "transform:   (source -> target)\n";
    for (int row = 0; row < 4; ++row)
      std::cout << "  " << m.transform(row, 0) << " " << m.transform(row, 1) << " " << m.transform(row, 2) << " "
                << m.transform(row, 3) << "\n";
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
