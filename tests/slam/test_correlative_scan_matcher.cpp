// The correlative scan matcher: known offsets recovered on synthetic scans of a room (scan to
// scan and scan to a map built by the occupancy mapper), the pruned search equal to an exhaustive
// one over the same lattice, a scan of nothing found as not converged, the registry line.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/slam/correlative_scan_matcher.hpp"
#include "starnav/slam/occupancy_mapping.hpp"
#include "room_fixture.hpp"

namespace starnav {
namespace {

std::vector<Vec2> to_world(const Pose2& pose, const std::vector<Vec2>& pts) {
  std::vector<Vec2> out;
  for (const Vec2& p : pts) out.push_back(pose.transform(p));
  return out;
}

TEST(CorrelativeScanMatcher, RecoversAKnownOffsetScanToScan) {
  CorrelativeScanMatcher m;
  const Pose2 ref(2.0, 2.0, 0.2);
  const std::vector<Vec2> reference = test::scan_from(ref);
  for (const Pose2& offset : {Pose2(0.12, -0.08, deg_to_rad(4)), Pose2(-0.2, 0.17, deg_to_rad(-12)), Pose2(0, 0, 0)}) {
    // The scan is taken at ref * offset; matched in ref's frame starting from the identity.
    const Pose2 truth = ref.compose(offset);
    const std::vector<Vec2> scan = test::scan_from(truth);
    const ScanMatch r = m.match(reference, scan, Pose2());
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.transform.x, offset.x, 0.015) << offset.x;
    EXPECT_NEAR(r.transform.y, offset.y, 0.015);
    EXPECT_NEAR(rad_to_deg(r.transform.yaw), rad_to_deg(offset.yaw), 0.5);
    EXPECT_GT(r.score, 0.8);
    EXPECT_LT(r.rms_m, 0.04);  // the field measures distances between cell centres: under a cell
  }
}

TEST(CorrelativeScanMatcher, MatchesAScanToAMappedRoom) {
  OccupancyMapper mapper;
  for (const Pose2& p : {Pose2(1, 1, 0), Pose2(3, 2.5, 1), Pose2(5.3, 3, 2), Pose2(2.5, 0.6, -1), Pose2(0.7, 3.5, 0.5)}) {
    const std::vector<Vec2> pts = test::scan_from(p, 720);
    // Back to beams for the mapper: beam k of 720 from -pi.
    std::vector<float> all(720, 100.0f);
    for (const Vec2& q : pts) {
      const int k = static_cast<int>(std::lround((std::atan2(q.y(), q.x()) + kPi) / (2 * kPi) * 720)) % 720;
      all[static_cast<std::size_t>(k)] = static_cast<float>(q.norm());
    }
    mapper.add_rays(p, -kPi, 2 * kPi / 720, all, 0.05, 50.0);
  }
  const OccupancyGrid map = mapper.grid();
  CorrelativeScanMatcher m;
  const Pose2 truth(3.3, 1.9, 0.6);
  const ScanMatch r = m.match_to_map(map, test::scan_from(truth), Pose2(3.1, 2.1, 0.6 + deg_to_rad(8)));
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.transform.x, truth.x, 0.02);
  EXPECT_NEAR(r.transform.y, truth.y, 0.02);
  EXPECT_NEAR(r.transform.yaw, truth.yaw, deg_to_rad(0.5));
}

// The score the documented lattice gives a pose: the mean of the fine field at the cells the scan's
// points fall in (0 outside the field).
double lattice_score(const CorrelativeScanMatcher::Field& f, const std::vector<Vec2>& scan, const Pose2& t) {
  double s = 0;
  for (const Vec2& p : scan) {
    const Vec2 q = t.transform(p);
    const int x = static_cast<int>(std::floor((q.x() - f.origin.x()) / f.resolution));
    const int y = static_cast<int>(std::floor((q.y() - f.origin.y()) / f.resolution));
    if (x >= 0 && y >= 0 && x < f.width && y < f.height) s += f.fine[static_cast<std::size_t>(y * f.width + x)];
  }
  return s / static_cast<double>(scan.size());
}

TEST(CorrelativeScanMatcher, PrunedSearchEqualsTheExhaustiveOne) {
  CorrelativeMatcherConfig c;
  c.refine = false;
  c.window_linear_m = 0.2;
  c.window_angular_rad = deg_to_rad(6);
  CorrelativeScanMatcher m(c);
  const Pose2 ref(2.0, 2.0, 0.0);
  const std::vector<Vec2> reference = to_world(ref, test::scan_from(ref));
  const std::vector<Vec2> scan = test::scan_from(Pose2(2.07, 1.95, deg_to_rad(2.5)));
  const CorrelativeScanMatcher::Field f = m.field_of_points(reference, {-1, -1}, {7, 5});
  const ScanMatch r = m.match_to_field(f, scan, ref);
  // Exhaustive over the documented lattice.
  double d_max = c.resolution_m;
  for (const Vec2& p : scan) d_max = std::max(d_max, p.norm());
  const double step = std::acos(1 - c.resolution_m * c.resolution_m / (2 * d_max * d_max));
  const int na = static_cast<int>(std::ceil(c.window_angular_rad / step)), nl = static_cast<int>(std::ceil(c.window_linear_m / c.resolution_m));
  double best = -1;
  for (int a = -na; a <= na; ++a)
    for (int ix = -nl; ix <= nl; ++ix)
      for (int iy = -nl; iy <= nl; ++iy) {
        best = std::max(best, lattice_score(f, scan, Pose2(ref.x + ix * c.resolution_m, ref.y + iy * c.resolution_m, ref.yaw + a * step)));
      }
  EXPECT_NEAR(r.score, best, 1e-6);
}

// A corridor 2 m wide whose walls have a 0.8 m doorway every 3 m (a hall of repeated rooms).
std::vector<test::Segment> doorway_corridor() {
  std::vector<test::Segment> w;
  for (int k = 0; k < 8; ++k) {
    const double x0 = 3.0 * k, x1 = x0 + 2.2;
    w.push_back({{x0, 0}, {x1, 0}});
    w.push_back({{x1, 0}, {x1, -0.5}});  // a jamb, so the doorway has depth
    w.push_back({{x0 + 1.0, 2}, {x0 + 3.0, 2}});
  }
  return w;
}

// The best lattice score (as the matcher scores it) among the poses around `guess`, +- n_l cells and
// angular steps a_lo..a_hi, that lie farther than `exclusion_cells` from (bx, by).
double exhaustive_rival(const CorrelativeScanMatcher::Field& f, const std::vector<Vec2>& scan, const Pose2& guess, double step, int a_lo,
                        int a_hi, int n_l, int bx, int by, double exclusion_cells) {
  double best = 0.0;
  for (int a = a_lo; a <= a_hi; ++a)
    for (int ix = -n_l; ix <= n_l; ++ix)
      for (int iy = -n_l; iy <= n_l; ++iy) {
        if (std::hypot(ix - bx, iy - by) <= exclusion_cells) continue;
        best = std::max(best, lattice_score(f, scan, Pose2(guess.x + ix * f.resolution, guess.y + iy * f.resolution, guess.yaw + a * step)));
      }
  return best;
}

TEST(CorrelativeScanMatcher, RivalSearchFindsTheRepeatedRoomAndEqualsTheExhaustiveOne) {
  CorrelativeMatcherConfig c;
  c.refine = false;
  c.resolution_m = 0.1;
  CorrelativeScanMatcher m(c);
  const std::vector<test::Segment> world = doorway_corridor();
  const Pose2 ref(9.0, 1.0, 0.0);
  std::vector<Vec2> reference;  // the whole corridor, as a submap of a drive along it
  for (double x = 1.0; x <= 22.0; x += 1.0)
    for (const Vec2& p : to_world(Pose2(x, 1.0, 0.0), test::scan_from(Pose2(x, 1.0, 0.0), 360, world, 6.0))) reference.push_back(p);
  const Pose2 truth(9.3, 1.1, deg_to_rad(1.0));
  const std::vector<Vec2> scan = test::scan_from(truth, 360, world, 4.0);
  const CorrelativeScanMatcher::Field f = m.field_of_points(reference, {0, -3}, {20, 5});
  double d_max = c.resolution_m;
  for (const Vec2& p : scan) d_max = std::max(d_max, p.norm());
  const double step = std::acos(1 - c.resolution_m * c.resolution_m / (2 * d_max * d_max));
  MatchWindow w{0.3, deg_to_rad(2), 0.3};
  w.rival_exclusion_m = 1.0;
  const int n_a = static_cast<int>(std::ceil(w.angular_rad / step));
  w.rival_angular_rad = deg_to_rad(1.0);  // rivals' yaw within 1 deg of the match's (the window: 2 deg)
  const int n_rival_a = static_cast<int>(std::ceil(w.rival_angular_rad / step));
  for (const double rival_linear_m : {0.0, 2.0, 3.5}) {
    w.rival_linear_m = rival_linear_m;
    const ScanMatch r = m.match_to_field(f, scan, Pose2(ref.x + 0.2, ref.y, ref.yaw), w);
    ASSERT_TRUE(r.converged);
    EXPECT_NEAR(r.transform.x, truth.x, 0.1);
    const int bx = static_cast<int>(std::lround((r.transform.x - ref.x - 0.2) / c.resolution_m));
    const int by = static_cast<int>(std::lround((r.transform.y - ref.y) / c.resolution_m));
    const int n_l = static_cast<int>(std::ceil(rival_linear_m / c.resolution_m));
    const int ba = static_cast<int>(std::lround(wrap_angle(r.transform.yaw - ref.yaw) / step));
    const double rival = exhaustive_rival(f, scan, Pose2(ref.x + 0.2, ref.y, ref.yaw), step, std::max(-n_a, ba - n_rival_a),
                                          std::min(n_a, ba + n_rival_a), n_l, bx, by, w.rival_exclusion_m / c.resolution_m);
    const double expected = rival >= w.min_score ? std::min(1.0, rival / r.score) : 0.0;  // a rival outside the window may score higher
    EXPECT_NEAR(r.ambiguity, expected, 1e-6) << rival_linear_m;
    // Within 0 m there is no rival; 3.5 m reaches the next doorway,
    // 3 m along, where the scan fits nearly as well; 2 m does not reach it.
    if (rival_linear_m == 0.0) {
      EXPECT_EQ(r.ambiguity, 0.0);
    }
    if (rival_linear_m == 2.0) {
      EXPECT_LT(r.ambiguity, 0.8);
    }
    if (rival_linear_m == 3.5) {
      EXPECT_GT(r.ambiguity, 0.9);
    }
  }
  // Rivals below rival_min_share are not looked for: reported as none.
  w.rival_linear_m = 2.0;
  w.rival_min_share = 0.95;
  EXPECT_EQ(m.match_to_field(f, scan, Pose2(ref.x + 0.2, ref.y, ref.yaw), w).ambiguity, 0.0);
  w.rival_linear_m = 3.5;
  EXPECT_GT(m.match_to_field(f, scan, Pose2(ref.x + 0.2, ref.y, ref.yaw), w).ambiguity, 0.9);
}

TEST(CorrelativeScanMatcher, ReportsNoMatchAndRefusesBadInput) {
  CorrelativeScanMatcher m;
  const std::vector<Vec2> reference = test::scan_from(Pose2(2, 2, 0));
  // A scan of a far-away wall the reference never saw.
  std::vector<Vec2> scan;
  for (int i = 0; i < 50; ++i) scan.push_back({20.0, -2.0 + 0.08 * i});
  EXPECT_FALSE(m.match(reference, scan, Pose2()).converged);
  EXPECT_THROW(m.match(reference, {}, Pose2()), Error);
  EXPECT_THROW(m.match(reference, std::vector<Vec2>{{NAN, 0}}, Pose2()), Error);
  CorrelativeMatcherConfig bad;
  bad.sigma_m = 0;
  EXPECT_THROW(CorrelativeScanMatcher{bad}, Error);
  const ScanMatcherDef& def = find_scan_matcher("correlative", "scan_matcher");
  EXPECT_EQ(def.info.name, "correlative");
  EXPECT_TRUE(def.make({}, {})->supports_map());
}

// A search is judged before anything is built: its top candidates (angles in Olson's steps for the
// farthest point, times the blocks of 2^depth translations a side) against 2^24, and the
// likelihood field of one scan all round (reach, margin, 3 sigma and a cell each side) against
// 2^24 cells; each refusal names the parameters of its product. The counts here are worked out
// apart from the matcher (the same closed forms as the brute-force search above).
TEST(CorrelativeScanMatcher, SearchesAndFieldsThatWouldPassTheirLimitsAreRefusedBeforeTheyAreBuilt) {
  struct Row {
    double resolution_m, linear_m, angular_deg, reach_m, margin_m;
    int depth;
    std::string refused;  // the field of the error; "": accepted
  };
  const std::vector<Row> rows = {
      {0.005, 10, 180, 30, 0, 2, "linear"},  // the attack: 37701 angles x 1001^2 blocks
      {0.05, 0.3, 20, 30, 0.3, 2, ""},       // the local SLAM's defaults
      {0.05, 8, 180, 15, 0, 7, ""},          // graph SLAM's wide search
      {0.05, 100, 180, 15, 0, 0, "linear"},  // 1885 angles x 4001^2
      {0.01, 0.3, 20, 30, 0.3, 2, "reach"},  // a field of 6093^2 cells
      {0.05, 0.3, 20, 103, 0.3, 2, "reach"},  // 4141^2 = 17.1 million cells
      {0.05, 0.3, 20, 100, 0.3, 2, ""},       // 4021^2 = 16.2 million cells
  };
  for (const Row& r : rows) {
    CorrelativeMatcherConfig c;
    c.resolution_m = r.resolution_m;
    const CorrelativeScanMatcher m(c);
    const double step = std::acos(1 - r.resolution_m * r.resolution_m / (2 * r.reach_m * r.reach_m));
    const double angles = 2 * std::ceil(deg_to_rad(r.angular_deg) / step) + 1;
    const double n_l = std::ceil(r.linear_m / r.resolution_m);
    const double blocks = std::floor(2 * n_l / std::pow(2.0, r.depth)) + 1;
    const double side = 2 * std::ceil((r.reach_m + r.margin_m + 3 * c.sigma_m + r.resolution_m) / r.resolution_m) + 1;
    const std::string expected = angles * blocks * blocks > 16777216.0 ? "linear" : side * side > 16777216.0 ? "reach" : "";
    ASSERT_EQ(expected, r.refused);
    SCOPED_TRACE(std::to_string(r.resolution_m) + " m, window " + std::to_string(r.linear_m) + " m, reach " + std::to_string(r.reach_m));
    const SearchNames names{"linear", "angular", "reach", "m."};
    const MatchWindow window{r.linear_m, deg_to_rad(r.angular_deg)};
    if (expected.empty()) {
      EXPECT_NO_THROW(m.check_search(window, r.reach_m, r.margin_m, r.depth, names));
      continue;
    }
    try {
      m.check_search(window, r.reach_m, r.margin_m, r.depth, names);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), expected);
      const std::string what = e.what();
      EXPECT_NE(what.find("m.resolution_m"), std::string::npos) << what;
      if (expected == "linear")
        EXPECT_NE(what.find(format_number(angles) + " angles x " + format_number(2 * n_l + 1) + " x " + format_number(2 * n_l + 1)),
                  std::string::npos)
            << what;
      else
        EXPECT_NE(what.find(format_number(side) + " x " + format_number(side) + " cells"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace starnav
