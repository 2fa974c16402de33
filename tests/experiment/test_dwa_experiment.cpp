// DWA's experiments (experiment/dwa_experiment), short versions: the sign-change count against
// hand-made series, the sideways goal of a Mecanum robot reached by translating, and the people
// case classifying contacts (the arrival rate over 100 seeds is a benchmark, not a test).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/experiment/dwa_experiment.hpp"

namespace starnav {
namespace {

const std::string kDwaSource = STARNAV_SOURCE_DIR;

TEST(DwaExperiment, SignChangesAreCountedInTheWorstWindow) {
  const std::vector<double> t{0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 6.0};
  const std::vector<double> vx{0.1, -0.1, 0.1, 0.005, -0.1, 0.1, 0.1, -0.1, 0.1};  // 0.005: inside the deadband
  const std::vector<double> wz{0.0, 0.0, 0.0, 0.3, 0.3, -0.3, 0.0, 0.0, 0.0};
  // vx changes at 0.5, 1.0, 2.0, 2.5, 5.0, 6.0; wz at 2.5: in [0.5, 2.5] five of them.
  EXPECT_EQ(max_sign_changes(t, {vx, wz}, 2.0, 0.01), 5);
  EXPECT_EQ(max_sign_changes(t, {vx}, 2.0, 0.01), 4);
  EXPECT_EQ(max_sign_changes(t, {vx}, 0.4, 0.01), 1);
  EXPECT_EQ(max_sign_changes(t, {}, 2.0, 0.01), 0);
}

TEST(DwaExperiment, TheSidewaysGoalIsReachedByTranslating) {
  DwaExperimentConfig c;
  c.experiment = "sideways";
  c.scenario_file = kDwaSource + "/scenarios/dwa_sideways.yaml";
  c.seeds = 2;
  const DwaExperimentResult r = run_dwa_experiment(c);
  ASSERT_EQ(r.trials.size(), 2u);
  for (const auto& t : r.trials) {
    ASSERT_TRUE(t.completed) << t.error;
    EXPECT_TRUE(t.record.arrived) << t.record.outcome;
    EXPECT_LE(t.record.goal_distance_m, 0.05);
    EXPECT_GT(t.record.max_abs_vy_mps, 0.1);
    EXPECT_LT(t.record.max_turn_deg, 10.0);
  }
  c.experiment = "zigzag";
  EXPECT_THROW(run_dwa_experiment(c), Error);
}

TEST(DwaExperiment, PeopleRunsArriveAndContactsAreClassified) {
  DwaExperimentConfig c;
  c.experiment = "people";
  c.scenario_file = kDwaSource + "/scenarios/dwa_people.yaml";
  c.seeds = 2;
  const DwaExperimentResult r = run_dwa_experiment(c);
  int contacts = 0;
  for (const auto& t : r.trials) {
    ASSERT_TRUE(t.completed) << t.error;
    EXPECT_LE(t.record.robot_caused_contacts, t.record.contacts);
    contacts += t.record.contacts;
  }
  // The people walk into the robot's way (they do not avoid it): contacts happen; most runs
  // still arrive (the rate over 100 seeds is in docs/local_planning.md).
  EXPECT_GT(contacts, 0);
  EXPECT_GE(r.arrived, 1);
  EXPECT_EQ(r.robot_caused, r.trials[0].record.robot_caused_contacts + r.trials[1].record.robot_caused_contacts);
}

}  // namespace
}  // namespace starnav
