// 3D pose-graph optimisation against independent answers: residuals of hand-built errors (a known
// relative error, a node lifted off or tilted against the floor), analytic Jacobians against
// central differences, consistent graphs reproduced exactly, noisy loops brought closer to the
// truth than dead reckoning, the floor plane pulling a drifting run back down, robust losses
// against a false closure, fixed nodes, bad input refused with the field named, and the time of a
// 1,000-node graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/slam/pose_graph_3d.hpp"

namespace starnav {
namespace {

using Pg3TestVector6 = Eigen::Matrix<double, 6, 1>;
using Pg3TestMatrix6 = Eigen::Matrix<double, 6, 6>;

Rigid3 pg3_pose(double x, double y, double z, double roll, double pitch, double yaw) {
  return to_rigid(Pose3::from_rpy(Vec3(x, y, z), roll, pitch, yaw));
}

// One turn of a rising helix (radius 5 m, 40 poses) with the heading along the path and a
// wobbling roll and pitch, so every rotation axis is exercised.
std::vector<Rigid3> pg3_helix(int count = 40) {
  std::vector<Rigid3> poses;
  for (int k = 0; k < count; ++k) {
    const double a = 2.0 * kPi * k / count;
    poses.push_back(pg3_pose(5.0 * std::sin(a), 5.0 - 5.0 * std::cos(a), 0.05 * k, 0.1 * std::sin(3 * a),
                             0.08 * std::cos(2 * a), a));
  }
  return poses;
}

Pg3TestMatrix6 pg3_information(double translation_std, double rotation_std) {
  Pg3TestVector6 d;
  d << Eigen::Vector3d::Constant(1.0 / (translation_std * translation_std)),
      Eigen::Vector3d::Constant(1.0 / (rotation_std * rotation_std));
  return d.asDiagonal();
}

PoseGraph3Edge pg3_true_edge(const std::vector<Rigid3>& truth, std::size_t i, std::size_t j) {
  PoseGraph3Edge e;
  e.from = i;
  e.to = j;
  e.measurement = truth[i].inverse() * truth[j];
  e.information = pg3_information(0.02, 0.01);
  return e;
}

// The floor z = 0 as a plane fitter would report it in the frame of `pose`: three floor points
// taken into that frame, the plane through them (normal on the floor's upper side).
Plane3 pg3_floor_in_frame(const Rigid3& pose) {
  const Rigid3 inv = pose.inverse();
  const Vec3 a = inv * Vec3(0, 0, 0), b = inv * Vec3(1, 0, 0), c = inv * Vec3(0, 1, 0);
  Plane3 p;
  p.normal = (b - a).cross(c - a).normalized();
  p.d = -p.normal.dot(a);
  return p;
}

Rigid3 pg3_random_motion(Rng& rng, double rotation_std, double translation_std) {
  Pg3TestVector6 xi;
  for (int k = 0; k < 3; ++k) xi(k) = rotation_std * rng.normal();
  for (int k = 3; k < 6; ++k) xi(k) = translation_std * rng.normal();
  return se3_exp(xi);
}

double pg3_ate(const std::vector<Rigid3>& poses, const std::vector<Rigid3>& truth) {
  double sum = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) sum += (poses[i].translation() - truth[i].translation()).squaredNorm();
  return std::sqrt(sum / static_cast<double>(poses.size()));
}

double pg3_pose_difference(const Rigid3& a, const Rigid3& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

// Pitch of a pose (R = Rz Ry Rx): the elevation of its x axis, + nose down.
double pg3_pitch(const Rigid3& pose) { return -std::asin(std::clamp(pose.linear()(2, 0), -1.0, 1.0)); }

std::string pg3_error_field(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.field();
  }
  return "(no error)";
}

TEST(PoseGraph3d, RelativeResidualIsTheKnownErrorTranslationFirst) {
  const Rigid3 from = pg3_pose(1, -2, 0.5, 0.3, -0.2, 2.0);
  const Rigid3 z = pg3_pose(0.7, 0.1, -0.05, 0.02, 0.1, -0.4);
  // `to` off the measurement by a translation of (0.2, -0.1, 0.3) and a rotation of 0.3 rad
  // about (1, 2, 2)/3, both in the measurement's frame: the error is exactly that motion.
  Rigid3 delta = Rigid3::Identity();
  delta.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 2) / 3.0).toRotationMatrix();
  delta.translation() = Vec3(0.2, -0.1, 0.3);
  const Pg3TestVector6 r = pose_graph_3d_residual(from, from * z * delta, z);
  Pg3TestVector6 expected;
  expected << 0.2, -0.1, 0.3, 0.1, 0.2, 0.2;
  EXPECT_LT((r - expected).norm(), 1e-12) << r.transpose();
  EXPECT_LT(pose_graph_3d_residual(from, from * z, z).norm(), 1e-12);
}

TEST(PoseGraph3d, AnalyticJacobiansMatchCentralDifferences) {
  Rng rng(21);
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Rigid3 from = pg3_random_motion(rng, 1.0, 3.0), to = pg3_random_motion(rng, 1.0, 3.0);
    // Measurements near and far from the poses' relative motion (rotation errors up to ~2.5 rad).
    const Rigid3 z = (from.inverse() * to) * pg3_random_motion(rng, trial < 10 ? 0.05 : 1.0, 0.5);
    const PoseGraph3Jacobians j = pose_graph_3d_jacobians(from, to, z);
    for (int k = 0; k < 6; ++k) {
      Pg3TestVector6 xi = Pg3TestVector6::Zero();
      xi(k) = h;
      const Pg3TestVector6 d_from = (pose_graph_3d_residual(se3_exp(xi) * from, to, z) -
                                     pose_graph_3d_residual(se3_exp(-xi) * from, to, z)) / (2 * h);
      const Pg3TestVector6 d_to = (pose_graph_3d_residual(from, se3_exp(xi) * to, z) -
                                   pose_graph_3d_residual(from, se3_exp(-xi) * to, z)) / (2 * h);
      EXPECT_LT((j.from.col(k) - d_from).norm(), 1e-6) << "trial " << trial << " column " << k;
      EXPECT_LT((j.to.col(k) - d_to).norm(), 1e-6) << "trial " << trial << " column " << k;
    }
  }
}

TEST(PoseGraph3d, PlaneResidualOfALiftedNodeIsTheHeight) {
  const double h = 0.37;
  const Plane3 floor;  // z = 0
  const Plane3 seen{Vec3::UnitZ(), 0.0};  // the floor as seen from the true pose on it
  const Rigid3 lifted = pg3_pose(3, -2, h, 0, 0, 0.7);
  const Eigen::Vector3d r = plane_edge_3d_residual(lifted, floor, seen);
  EXPECT_NEAR(r(0), 0.0, 1e-12);
  EXPECT_NEAR(r(1), 0.0, 1e-12);
  EXPECT_NEAR(r(2), h, 1e-12);
  // A fitter's opposite orientation of the same plane is the same measurement.
  EXPECT_LT((plane_edge_3d_residual(lifted, floor, Plane3{-Vec3::UnitZ(), -0.0}) - r).norm(), 1e-12);
  // A node on the plane exactly as measured: no error, whatever its pose.
  const Rigid3 general = pg3_pose(-4, 1, 0.8, 0.2, -0.3, 2.5);
  EXPECT_LT(plane_edge_3d_residual(general, floor, pg3_floor_in_frame(general)).norm(), 1e-12);
}

TEST(PoseGraph3d, PlaneResidualOfATiltedNodeIsTheTilt) {
  const Plane3 floor, seen{Vec3::UnitZ(), 0.0};
  // Pitch theta: the expected normal (-sin, 0, cos) is rotated onto x about y, which takes the
  // measured normal z to (cos, 0, -sin): alpha 0, beta -theta.
  const double theta = 0.05;
  const Eigen::Vector3d rp = plane_edge_3d_residual(pg3_pose(0, 0, 0, 0, theta, 0.4), floor, seen);
  EXPECT_NEAR(rp(0), 0.0, 1e-12);
  EXPECT_NEAR(rp(1), -theta, 1e-12);
  EXPECT_NEAR(rp(2), 0.0, 1e-12);
  // Roll phi: expected normal (0, sin, cos); the shortest arc onto x takes z to
  // (cos, -sin cos, sin^2): alpha = -atan(sin phi), beta = atan2(sin^2, cos sqrt(1 + sin^2)).
  const double phi = 0.05, s = std::sin(phi), c = std::cos(phi);
  const Eigen::Vector3d rr = plane_edge_3d_residual(pg3_pose(0, 0, 0, phi, 0, 0), floor, seen);
  EXPECT_NEAR(rr(0), -std::atan(s), 1e-12);
  EXPECT_NEAR(rr(1), std::atan2(s * s, c * std::sqrt(1 + s * s)), 1e-12);
  EXPECT_NEAR(rr(2), 0.0, 1e-12);
  EXPECT_NEAR(std::acos(std::cos(rr(0)) * std::cos(rr(1))), phi, 1e-9);  // the angle between the normals
}

TEST(PoseGraph3d, ExactMeasurementsCostNothingAndMoveNothing) {
  const std::vector<Rigid3> truth = pg3_helix();
  std::vector<PoseGraph3Edge> edges;
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) edges.push_back(pg3_true_edge(truth, i, i + 1));
  edges.push_back(pg3_true_edge(truth, truth.size() - 1, 0));
  std::vector<PlaneEdge3> planes;
  for (std::size_t i = 0; i < truth.size(); i += 5) planes.push_back({i, pg3_floor_in_frame(truth[i])});
  std::vector<Rigid3> poses = truth;
  const PoseGraph3Report r = optimise_pose_graph_3d(poses, edges, planes);
  EXPECT_LT(r.initial_cost, 1e-20);
  EXPECT_LT(r.final_cost, 1e-20);
  for (std::size_t i = 0; i < truth.size(); ++i) EXPECT_LT(pg3_pose_difference(poses[i], truth[i]), 1e-12) << i;
}

TEST(PoseGraph3d, RecoversConsistentMeasurementsFromAPerturbedStart) {
  const std::vector<Rigid3> truth = pg3_helix();
  std::vector<PoseGraph3Edge> edges;
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) edges.push_back(pg3_true_edge(truth, i, i + 1));
  edges.push_back(pg3_true_edge(truth, truth.size() - 1, 0));
  edges.push_back(pg3_true_edge(truth, 7, 25));
  std::vector<PlaneEdge3> planes;
  for (std::size_t i = 0; i < truth.size(); i += 4) planes.push_back({i, pg3_floor_in_frame(truth[i])});
  Rng rng(5);
  std::vector<Rigid3> poses = truth;
  for (std::size_t i = 1; i < poses.size(); ++i) poses[i] = pg3_random_motion(rng, 0.1, 0.3) * poses[i];
  const PoseGraph3Report r = optimise_pose_graph_3d(poses, edges, planes, {.max_iterations = 100});
  EXPECT_GT(r.initial_cost, 100.0);
  EXPECT_LT(r.final_cost, 1e-12);
  for (std::size_t i = 0; i < truth.size(); ++i) EXPECT_LT(pg3_pose_difference(poses[i], truth[i]), 1e-6) << i;
  // Rotations stay rotations.
  for (const Rigid3& p : poses)
    EXPECT_LT((p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(PoseGraph3d, ALoopClosureBringsANoisyHelixCloserToTheTruthThanDeadReckoning) {
  const std::vector<Rigid3> truth = pg3_helix();
  Rng rng(2024);
  std::vector<PoseGraph3Edge> edges;
  std::vector<Rigid3> dead_reckoning{truth[0]};
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) {
    PoseGraph3Edge e = pg3_true_edge(truth, i, i + 1);
    e.measurement = e.measurement * pg3_random_motion(rng, 0.01, 0.02);
    edges.push_back(e);
    dead_reckoning.push_back(dead_reckoning.back() * e.measurement);
  }
  edges.push_back(pg3_true_edge(truth, truth.size() - 1, 0));
  edges.back().information *= 10.0;  // a registered loop closure, more precise than odometry
  std::vector<Rigid3> poses = dead_reckoning;
  const PoseGraph3Report r = optimise_pose_graph_3d(poses, edges, {});
  const double ate_dead = pg3_ate(dead_reckoning, truth), ate_opt = pg3_ate(poses, truth);
  EXPECT_GT(ate_dead, 0.1);
  EXPECT_LT(ate_opt, 0.5 * ate_dead) << "dead reckoning " << ate_dead;
  EXPECT_LT(r.final_cost, 0.1 * r.initial_cost);
  EXPECT_GT(r.iterations, 0);
  // The optimum leaves each edge about its noise: the cost per residual dimension is near 1.
  EXPECT_LT(r.final_cost, 6.0 * static_cast<double>(edges.size()));
}

// A straight 100-pose run on the floor whose odometry believes every 0.5 m step also climbs 1 cm
// and pitches 0.1 degree: the drift the floor constraint exists to remove. The odometry's
// information (5 cm, 0.01 rad) decides how the optimum explains the climb between two floor
// observations: trusted more in translation (2 cm), it is partly explained by pitching the nodes
// nose down, by up to 0.75 degree mid-segment.
struct Pg3FloorRun {
  std::vector<Rigid3> truth, poses;
  std::vector<PoseGraph3Edge> edges;
};

Pg3FloorRun pg3_biased_floor_run() {
  Pg3FloorRun run;
  Rigid3 bias = Rigid3::Identity();
  bias.linear() = Eigen::AngleAxisd(0.1 * kPi / 180.0, Vec3::UnitY()).toRotationMatrix();
  bias.translation() = Vec3(0, 0, 0.01);
  for (int i = 0; i < 100; ++i) run.truth.push_back(pg3_pose(0.5 * i, 0, 0, 0, 0, 0));
  run.poses = {run.truth[0]};
  for (std::size_t i = 0; i + 1 < run.truth.size(); ++i) {
    PoseGraph3Edge e = pg3_true_edge(run.truth, i, i + 1);
    e.measurement = e.measurement * bias;
    e.information = pg3_information(0.05, 0.01);
    run.edges.push_back(e);
    run.poses.push_back(run.poses.back() * e.measurement);
  }
  return run;
}

TEST(PoseGraph3d, TheFloorConstraintPullsADriftingRunBack) {
  Pg3FloorRun free_run = pg3_biased_floor_run(), floor_run = pg3_biased_floor_run();
  optimise_pose_graph_3d(free_run.poses, free_run.edges, {});
  EXPECT_GT(std::abs(free_run.poses.back().translation().z()), 1.0);
  // A plane edge at every 10th node and at the last (a chain's free end would drift unchecked):
  // the true floor in that node's frame, as RANSAC would fit it.
  std::vector<PlaneEdge3> planes;
  const std::size_t last = floor_run.truth.size() - 1;
  for (std::size_t i = 0; i <= last; ++i)
    if (i % 10 == 0 || i == last)
      planes.push_back({i, Plane3{Vec3::UnitZ(), 0.0}, Eigen::Vector3d(1e4, 1e4, 1e4).asDiagonal()});
  const PoseGraph3Report r = optimise_pose_graph_3d(floor_run.poses, floor_run.edges, planes);
  EXPECT_LT(r.final_cost, r.initial_cost);
  for (std::size_t i = 0; i <= last; ++i) {
    const double z = std::abs(floor_run.poses[i].translation().z());
    const double pitch = std::abs(pg3_pitch(floor_run.poses[i]));
    EXPECT_LT(z, 0.05) << i;
    EXPECT_LT(pitch, 0.5 * kPi / 180.0) << i;
    EXPECT_LE(z, std::abs(free_run.poses[i].translation().z()) + 1e-3) << i;
    EXPECT_LE(pitch, std::abs(pg3_pitch(free_run.poses[i])) + 1e-4) << i;
  }
}

TEST(PoseGraph3d, ARobustLossKeepsOneFalseClosureFromBendingTheGraph) {
  const std::vector<Rigid3> truth = pg3_helix();
  const auto worst_error = [&](RobustLoss loss) {
    std::vector<PoseGraph3Edge> edges;
    for (std::size_t i = 0; i + 1 < truth.size(); ++i) edges.push_back(pg3_true_edge(truth, i, i + 1));
    for (auto [i, j] : {std::pair<std::size_t, std::size_t>{0, 39}, {5, 33}, {12, 28}}) {
      edges.push_back(pg3_true_edge(truth, i, j));
      edges.back().loss = loss;
    }
    // The false one: node 30 sits on node 10.
    PoseGraph3Edge wrong = pg3_true_edge(truth, 10, 30);
    wrong.measurement = Rigid3::Identity();
    wrong.loss = loss;
    edges.push_back(wrong);
    std::vector<Rigid3> poses = truth;
    optimise_pose_graph_3d(poses, edges, {}, {.max_iterations = 200});
    double worst = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i)
      worst = std::max(worst, (poses[i].translation() - truth[i].translation()).norm());
    return worst;
  };
  const double plain = worst_error(RobustLoss::None), cauchy = worst_error(RobustLoss::Cauchy),
               huber = worst_error(RobustLoss::Huber);
  EXPECT_GT(plain, 0.5);
  EXPECT_LT(cauchy, 0.05) << "plain " << plain;
  EXPECT_LT(huber, plain / 2) << "plain " << plain;
}

TEST(PoseGraph3d, FixedNodesStayExactlyWhereTheyWere) {
  const std::vector<Rigid3> truth = pg3_helix();
  std::vector<PoseGraph3Edge> edges;
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) edges.push_back(pg3_true_edge(truth, i, i + 1));
  edges.push_back(pg3_true_edge(truth, truth.size() - 1, 0));
  Rng rng(9);
  std::vector<Rigid3> start = truth;
  for (std::size_t i = 1; i < start.size(); ++i) start[i] = pg3_random_motion(rng, 0.05, 0.2) * start[i];

  // Node 20 held off the truth: it stays, bit for bit, and the rest settles around it.
  std::vector<Rigid3> poses = start;
  const PoseGraph3Report r = optimise_pose_graph_3d(poses, edges, {}, {.fixed_nodes = {0, 20}});
  EXPECT_TRUE(poses[0].matrix() == start[0].matrix());
  EXPECT_TRUE(poses[20].matrix() == start[20].matrix());
  EXPECT_LT(r.final_cost, 0.1 * r.initial_cost);
  EXPECT_GT(pg3_pose_difference(poses[10], start[10]), 1e-3);

  // Node 0 is not special: fixing only node 20 lets node 0 move.
  poses = start;
  optimise_pose_graph_3d(poses, edges, {}, {.fixed_nodes = {20}});
  EXPECT_TRUE(poses[20].matrix() == start[20].matrix());
  EXPECT_GT(pg3_pose_difference(poses[0], start[0]), 1e-3);

  // Every node fixed: nothing to do, and nothing moves.
  poses = start;
  std::vector<std::size_t> all(poses.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const PoseGraph3Report none = optimise_pose_graph_3d(poses, edges, {}, {.fixed_nodes = all});
  EXPECT_EQ(none.iterations, 0);
  EXPECT_GT(none.initial_cost, 0.0);
  EXPECT_EQ(none.final_cost, none.initial_cost);
  for (std::size_t i = 0; i < poses.size(); ++i) EXPECT_TRUE(poses[i].matrix() == start[i].matrix()) << i;
}

TEST(PoseGraph3d, BadInputIsRefusedNamingTheField) {
  std::vector<Rigid3> poses(3, Rigid3::Identity());
  const PoseGraph3Edge good{0, 1};
  const auto field_of = [&](std::vector<PoseGraph3Edge> edges, std::vector<PlaneEdge3> planes,
                            PoseGraph3Options options = {}) {
    return pg3_error_field([&] { optimise_pose_graph_3d(poses, edges, planes, options); });
  };
  EXPECT_EQ(field_of({{0, 3}}, {}), "edges[0]");
  EXPECT_EQ(field_of({good, {2, 2}}, {}), "edges[1]");
  PoseGraph3Edge indefinite = good;
  indefinite.information(4, 4) = -1.0;
  EXPECT_EQ(field_of({good, indefinite}, {}), "edges[1]");
  PoseGraph3Edge singular = good;
  singular.information(5, 5) = 0.0;
  EXPECT_EQ(field_of({singular}, {}), "edges[0]");
  PoseGraph3Edge not_finite = good;
  not_finite.information(0, 0) = std::nan("");
  EXPECT_EQ(field_of({not_finite}, {}), "edges[0]");
  PoseGraph3Edge bad_measurement = good;
  bad_measurement.measurement.translation().x() = std::nan("");
  EXPECT_EQ(field_of({bad_measurement}, {}), "edges[0]");
  PoseGraph3Edge bad_scale = good;
  bad_scale.loss = RobustLoss::Cauchy;
  bad_scale.loss_scale = 0.0;
  EXPECT_EQ(field_of({bad_scale}, {}), "edges[0]");

  EXPECT_EQ(field_of({good}, {{3, Plane3{}}}), "plane_edges[0]");
  EXPECT_EQ(field_of({}, {{1, Plane3{}}, {1, Plane3{Vec3(0, 0, 2), 0.0}}}), "plane_edges[1]");
  EXPECT_EQ(field_of({}, {{1, Plane3{Vec3(std::nan(""), 0, 1), 0.0}}}), "plane_edges[0]");
  EXPECT_EQ(field_of({}, {{1, Plane3{Vec3::UnitZ(), std::nan("")}}}), "plane_edges[0]");
  EXPECT_EQ(field_of({}, {{1, Plane3{}, Eigen::Vector3d(1, 1, -1).asDiagonal()}}), "plane_edges[0]");
  EXPECT_EQ(field_of({}, {{1, Plane3{}, Eigen::Matrix3d::Constant(std::nan(""))}}), "plane_edges[0]");

  EXPECT_EQ(field_of({good}, {}, {.fixed_nodes = {3}}), "fixed_nodes");
  EXPECT_EQ(field_of({good}, {}, {.floor = Plane3{Vec3(0, 1, 1), 0.0}}), "floor");
  poses[2].linear()(0, 1) = 0.5;
  EXPECT_EQ(field_of({good}, {}), "poses[2]");
  poses[2] = Rigid3::Identity();
  EXPECT_EQ(field_of({good}, {{1, Plane3{}}}), "(no error)");

  std::vector<Rigid3> empty;
  EXPECT_NO_THROW(optimise_pose_graph_3d(empty, {}, {}));
}

TEST(PoseGraph3d, AThousandNodeGraphOptimisesQuickly) {
  // Four laps of a 250-pose circle on the floor (radius 10 m): 999 noisy odometry edges, 20 loop
  // closures between laps, a floor plane edge at every 10th node.
  const std::size_t count = 1000, lap = 250;
  std::vector<Rigid3> truth;
  for (std::size_t k = 0; k < count; ++k) {
    const double a = 2.0 * kPi * static_cast<double>(k) / static_cast<double>(lap);
    truth.push_back(pg3_pose(10.0 * std::sin(a), 10.0 - 10.0 * std::cos(a), 0.0, 0.0, 0.0, a));
  }
  Rng rng(77);
  std::vector<PoseGraph3Edge> edges;
  std::vector<Rigid3> poses{truth[0]};
  for (std::size_t i = 0; i + 1 < count; ++i) {
    PoseGraph3Edge e = pg3_true_edge(truth, i, i + 1);
    e.measurement = e.measurement * pg3_random_motion(rng, 0.005, 0.01);
    e.information = pg3_information(0.01, 0.005);
    edges.push_back(e);
    poses.push_back(poses.back() * e.measurement);
  }
  for (std::size_t k = 0; k < 20; ++k) {
    const std::size_t i = 12 * k + 3, j = i + lap * (1 + k % 3);
    edges.push_back(pg3_true_edge(truth, i, j));
    edges.back().loss = RobustLoss::Huber;
  }
  std::vector<PlaneEdge3> planes;
  for (std::size_t i = 0; i < count; i += 10)
    planes.push_back({i, Plane3{}, Eigen::Vector3d(1e4, 1e4, 1e4).asDiagonal()});
  ASSERT_EQ(edges.size(), 1019u);
  ASSERT_EQ(planes.size(), 100u);
  const double ate_dead = pg3_ate(poses, truth);
  const double start = thread_cpu_s();
  const PoseGraph3Report r = optimise_pose_graph_3d(poses, edges, planes);
  const double seconds = thread_cpu_s() - start;
  std::cout << "[ PoseGraph3d ] 1000 nodes, 1019 edges, 100 plane edges: " << r.iterations << " iterations, "
            << seconds << " s CPU, ATE " << ate_dead << " -> " << pg3_ate(poses, truth) << " m\n";
  EXPECT_LT(r.final_cost, 0.01 * r.initial_cost);
  EXPECT_LT(pg3_ate(poses, truth), 0.5 * ate_dead);
  // Loose enough for the sanitizer build; a dense solve of the 6,000 unknowns would take far longer.
  EXPECT_LT(seconds, 5.0);
}

}  // namespace
}  // namespace starnav
