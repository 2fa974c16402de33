// Ren et al. 2022 Tables 1 and 4 as experiments, short versions: A* and Dijkstra agree on every
// cost while A* expands fewer nodes; the whole stack's table over a seed is the arrivals' own
// max / min / mean, and a seed that does not arrive everywhere is not in it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/ren_table1_experiment.hpp"
#include "starnav/experiment/ren_table4_experiment.hpp"

namespace starnav {
namespace {

const std::string kSource = STARNAV_SOURCE_DIR;

TEST(RenTable1, AStarAndDijkstraFindTheSameCostsAndAStarExpandsFewer) {
  RenTable1Config c;
  c.empty_room = kSource + "/scenarios/maps/ren_room_empty.yaml";
  c.obstacle_room = kSource + "/scenarios/maps/ren_room_obstacles.yaml";
  c.indoor_map = kSource + "/scenarios/maps/indoor_rooms.yaml";
  c.repeats = 2;
  c.queries = 40;
  const RenTable1Result r = run_ren_table1(c);
  ASSERT_EQ(r.rows.size(), 6u);
  EXPECT_EQ(r.cost_mismatches, 0);
  for (std::size_t i = 0; i < r.rows.size(); i += 2) {
    const RenTable1Row& dijkstra = r.rows[i];
    const RenTable1Row& astar = r.rows[i + 1];
    EXPECT_EQ(dijkstra.planner, "dijkstra");
    EXPECT_EQ(astar.planner, "astar");
    EXPECT_NEAR(dijkstra.cost_m, astar.cost_m, 1e-9) << dijkstra.map;
    EXPECT_LT(astar.expanded_mean, dijkstra.expanded_mean) << dijkstra.map;
  }
  // The empty room's optimum in closed form: 17 diagonal steps of 0.05 sqrt 2 per 0.05 m.
  EXPECT_NEAR(r.rows[0].cost_m, 17.0 * std::sqrt(2.0), 1e-6);
  EXPECT_GT(r.rows[2].cost_m, r.rows[0].cost_m);  // the obstacles make it longer
  c.repeats = 0;
  EXPECT_THROW(run_ren_table1(c), Error);
}

TEST(RenTable4, TheTableIsTheArrivalsOwnSpread) {
  RenTable4Config c;
  c.scenario_file = kSource + "/scenarios/ren_table4.yaml";
  c.overrides = {parse_scenario_override("navigation.laps=1")};
  c.seeds = 1;
  const RenTable4Result r = run_ren_table4(c);
  ASSERT_EQ(r.trials.size(), 1u);
  const auto& t = r.trials[0];
  ASSERT_TRUE(t.completed) << t.error;
  ASSERT_TRUE(t.record.success) << t.record.outcome;
  EXPECT_EQ(r.seeds_ok, 1);
  ASSERT_EQ(t.record.arrival_list.size(), 2u);
  const double ex0 = std::abs(t.record.arrival_list[0].error_x_m()), ex1 = std::abs(t.record.arrival_list[1].error_x_m());
  EXPECT_DOUBLE_EQ(r.x.max, std::max(ex0, ex1));
  EXPECT_DOUBLE_EQ(r.x.min, std::min(ex0, ex1));
  EXPECT_DOUBLE_EQ(r.x.mean, 0.5 * (ex0 + ex1));
  EXPECT_DOUBLE_EQ(r.worst_x, r.x.max);
  EXPECT_LE(r.x.max, 0.08);
  EXPECT_LE(r.y.max, 0.08);
  EXPECT_LE(rad_to_deg(r.yaw.max), 6.0);
  EXPECT_GT(r.real_time_factor_median, 0.0);
  EXPECT_NE(ren_table4_markdown(r).find("| x (cm) |"), std::string::npos);
  // A run too short to arrive anywhere fails its seed and leaves the table empty.
  c.overrides.push_back(parse_scenario_override("sim.duration_s=5"));
  const RenTable4Result short_run = run_ren_table4(c);
  EXPECT_FALSE(short_run.trials[0].record.success);
  EXPECT_EQ(short_run.seeds_ok, 0);
}

}  // namespace
}  // namespace starnav
