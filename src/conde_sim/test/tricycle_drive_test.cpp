// The tricycle drive's control law and the joint pose servo, without ROS or physics.
#include <gtest/gtest.h>

#include <cmath>

#include "conde_sim/joint_pose_servo.h"
#include "conde_sim/tricycle_drive.h"

namespace conde_sim {
namespace {

TEST(TricycleController, WheelSpeedIsSurfaceSpeedOverRadiusWithoutRamp) {
  TricycleController c{TricycleParams()};  // diameter 0.15 m
  EXPECT_TRUE(c.setCommand(0.3, 0.2, 0.0));
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.1, 0.0, 0.01), 4.0);
  EXPECT_DOUBLE_EQ(c.steeringTarget(), 0.2);
}

TEST(TricycleController, RampsTowardsTheTargetInBothDirections) {
  TricycleParams p;
  p.wheel_acceleration_radps2 = 10.0;
  p.wheel_deceleration_radps2 = 20.0;
  TricycleController c(p);
  c.setCommand(0.3, 0.0, 0.0);                          // 4 rad/s
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.0, 0.0, 0.1), 1.0);   // speeding up at 10 rad/s^2
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.0, 3.95, 0.1), 4.0);  // within the tolerance: the target
  c.setCommand(0.0, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.0, 4.0, 0.1), 2.0);  // slowing down at 20 rad/s^2
  c.setCommand(-0.3, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.0, 1.0, 0.1), -1.0);   // reversing: deceleration first
  EXPECT_DOUBLE_EQ(c.wheelSpeed(0.0, -1.0, 0.1), -2.0);  // then acceleration
}

TEST(TricycleController, SteeringIsHeldWithinQuarterTurnAndTurnsAtSteeringSpeed) {
  TricycleParams p;
  p.steering_speed_radps = 0.5;
  TricycleController c(p);
  c.setCommand(0.0, 2.0, 0.0);
  EXPECT_DOUBLE_EQ(c.steeringTarget(), M_PI / 2.0);
  EXPECT_DOUBLE_EQ(c.steeringSpeed(0.0), 0.5);
  EXPECT_DOUBLE_EQ(c.steeringSpeed(2.0), -0.5);
  EXPECT_DOUBLE_EQ(c.steeringSpeed(M_PI / 2.0 - 0.005), 0.0);  // within steeringAngleTolerance
}

TEST(TricycleController, IgnoresNonFiniteCommandsAndStopsAfterTimeout) {
  TricycleParams p;
  p.command_timeout_s = 0.5;
  TricycleController c(p);
  c.setCommand(0.15, 0.0, 1.0);
  EXPECT_FALSE(c.setCommand(NAN, 0.0, 1.1));
  EXPECT_DOUBLE_EQ(c.wheelSpeed(1.2, 0.0, 0.01), 2.0);
  EXPECT_DOUBLE_EQ(c.wheelSpeed(1.6, 2.0, 0.01), 0.0);
}

TEST(PoseServoSpeed, ReachesInOneStepWhenItCanStopElseBrakesInTime) {
  EXPECT_DOUBLE_EQ(poseServoSpeed(0.01, 0.001, 0.0), 10.0);         // no deceleration limit
  EXPECT_DOUBLE_EQ(poseServoSpeed(-0.5, 0.001, 100.0), -10.0);      // sqrt(2 * 100 * 0.5)
  EXPECT_DOUBLE_EQ(poseServoSpeed(1e-6, 0.001, 100.0), 1e-3);       // one step from the target
  EXPECT_DOUBLE_EQ(poseServoSpeed(-0.5, 0.001, 100.0, 0.5), -0.5);  // the URDF velocity limit
  EXPECT_DOUBLE_EQ(poseServoSpeed(1e-6, 0.001, 100.0, 0.5), 1e-3);  // below it
}

}  // namespace
}  // namespace conde_sim
