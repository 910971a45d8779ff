// JointTrajectory (joint_trajectory.h): linear and cubic segments, holding before and after, and
// the rejected inputs.
#include "conde_sim/joint_trajectory.h"

#include <gtest/gtest.h>

using conde_sim::JointTrajectory;
using conde_sim::TrajectoryPoint;

TEST(JointTrajectory, LinearBetweenPointsWithoutVelocities) {
  const JointTrajectory t({0.0, 1.0}, {{1.0, {0.5, 0.0}, {}}, {2.0, {1.0, 2.0}, {}}});
  EXPECT_DOUBLE_EQ(t.durationS(), 2.0);
  EXPECT_EQ(t.sample(-1.0), (std::vector<double>{0.0, 1.0}));
  EXPECT_NEAR(t.sample(0.5)[0], 0.25, 1e-12);
  EXPECT_NEAR(t.sample(0.5)[1], 0.5, 1e-12);
  EXPECT_NEAR(t.sample(1.5)[0], 0.75, 1e-12);
  EXPECT_NEAR(t.sample(1.5)[1], 1.0, 1e-12);
  EXPECT_EQ(t.sample(5.0), (std::vector<double>{1.0, 2.0}));
}

TEST(JointTrajectory, CubicWithVelocitiesStartsAndEndsAtRest) {
  const JointTrajectory t({0.0}, {{2.0, {1.0}, {0.0}}});
  EXPECT_NEAR(t.sample(1.0)[0], 0.5, 1e-12);                   // symmetric
  EXPECT_NEAR(t.sample(0.2)[0], 3 * 0.01 - 2 * 0.001, 1e-12);  // 3 s^2 - 2 s^3 at s = 0.1
  // Slope near the ends is ~0 (starts and ends at rest).
  EXPECT_NEAR((t.sample(1e-4)[0] - t.sample(0.0)[0]) / 1e-4, 0.0, 1e-3);
  EXPECT_NEAR((t.sample(2.0)[0] - t.sample(2.0 - 1e-4)[0]) / 1e-4, 0.0, 1e-3);
}

TEST(JointTrajectory, FirstPointAtTimeZeroReplacesTheStart) {
  const JointTrajectory t({5.0}, {{0.0, {1.0}, {}}, {1.0, {2.0}, {}}});
  EXPECT_NEAR(t.sample(0.0)[0], 1.0, 1e-12);
  EXPECT_NEAR(t.sample(0.5)[0], 1.5, 1e-12);
}

TEST(JointTrajectory, RejectsBadPoints) {
  EXPECT_THROW(JointTrajectory({0.0}, {{1.0, {1.0, 2.0}, {}}}), std::invalid_argument);
  EXPECT_THROW(JointTrajectory({0.0}, {{1.0, {1.0}, {1.0, 2.0}}}), std::invalid_argument);
  EXPECT_THROW(JointTrajectory({0.0}, {{1.0, {1.0}, {}}, {1.0, {2.0}, {}}}), std::invalid_argument);
  EXPECT_THROW(JointTrajectory({0.0}, {{-1.0, {1.0}, {}}}), std::invalid_argument);
}
