// The diff drive on the real Conde robot (urdf/robots/conde.urdf.xacro), in-process, stepped,
// once per physics engine. Distances and angles are checked against ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/simulation.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;
using conde_sim::DiffDrive;
using conde_sim_test::condeUrdf;

namespace {

// A flat plane with the competition world's physics settings and ground friction (the track's
// own objects would be in the way of the test manoeuvres).
cp::WorldDescription flatWorld() {
  const cp::WorldDescription competition =
      cp::loadWorldFile(std::string(CONDE_REPO_ROOT) + "/worlds/worlds/competition.world.yaml", nullptr);
  cp::WorldDescription w = conde_sim_test::flatGround("flat");
  w.physics = competition.physics;
  w.ground.friction = competition.ground.friction;
  return w;
}

class ConDiffDrive : public conde_sim_test::SteppedRobotTest {
 protected:
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(buildWorld(flatWorld(), "conde", "conde.urdf.xacro", condeUrdf()));
    DiffDrive::Config c;
    c.left_joint = "left_wheel_joint";
    c.right_joint = "right_wheel_joint";
    c.params.wheel_separation_m = 0.33;
    c.params.wheel_diameter_m = 0.064;
    c.params.wheel_acceleration_mps2 = 5.0;  // as the URDF's <wheelAcceleration>
    c.wheel_torque_nm = 7.5;
    c.update_rate_hz = 50;
    c.encoder_odometry = true;
    drive_ = std::make_unique<DiffDrive>(*sim_, 0, c);
    settle();
  }

  // Lets the robot settle on its wheels and caster before a test measures anything.
  void settle() {
    run(0.5, 0.0, 0.0);
    drive_->reset();
  }

  // Drives with (v, w) for `seconds`, re-sending the command at 20 Hz like a teleop node.
  void run(double seconds, double linear_mps, double angular_radps) {
    const int steps = static_cast<int>(std::lround(seconds / sim_->stepS()));
    for (int i = 0; i < steps; ++i) {
      if (i % 50 == 0) drive_->command(linear_mps, angular_radps);
      step();
    }
  }

  void step() { conde_sim_test::stepWithDrive(*sim_, *drive_); }

  cp::Pose truth() const { return sim_->linkPose(0, "base_footprint"); }

  std::unique_ptr<DiffDrive> drive_;
};

TEST_P(ConDiffDrive, HalfAMetrePerSecondForFourSecondsIsTwoMetres) {
  const cp::Pose start = truth();
  run(4.0, 0.5, 0.0);
  const double travelled_m = (truth().position - start.position).norm();
  EXPECT_NEAR(travelled_m, 2.0, 0.02 * 2.0);
  EXPECT_NEAR(cp::wrapAngle(truth().orientation.yaw() - start.orientation.yaw()), 0.0, 0.01);
}

TEST_P(ConDiffDrive, OneRadianPerSecondForHalfPiSecondsIsNinetyDegrees) {
  const double yaw0 = truth().orientation.yaw();
  run(M_PI / 2, 0.0, 1.0);
  run(0.3, 0.0, 0.0);  // stop (and let any overshoot show)
  const double turned_deg = cp::wrapAngle(truth().orientation.yaw() - yaw0) * 180.0 / M_PI;
  EXPECT_NEAR(turned_deg, 90.0, 3.0);
}

// The seed paper's square: 1 m sides at `speed`, 90 degree turns at 1 rad/s, back to the start.
TEST_P(ConDiffDrive, EncoderOdometryTracksGroundTruthOnTheSquare) {
  for (double speed : {0.3, 0.5}) {
    settle();
    const cp::Pose start = truth();
    double path_m = 0.0;
    for (int side = 0; side < 4; ++side) {
      run(1.0 / speed, speed, 0.0);
      run(M_PI / 2, 0.0, 1.0);
      path_m += 1.0;
    }
    run(0.3, 0.0, 0.0);
    // Ground truth relative to the start, in the start frame (= the odom frame).
    const cp::Pose relative = start.inverse() * truth();
    const cp::Pose& odom = drive_->odomPose();
    const double error_m = std::hypot(odom.position.x - relative.position.x, odom.position.y - relative.position.y);
    EXPECT_LT(error_m, 0.02 * path_m) << "speed " << speed;
    // 2 % of what was turned (four quarter turns) for the heading, as for the position.
    EXPECT_NEAR(cp::wrapAngle(odom.orientation.yaw() - relative.orientation.yaw()), 0.0, 0.02 * 2 * M_PI)
        << "speed " << speed;
  }
}

TEST_P(ConDiffDrive, ReversingReportsNegativeSpeed) {
  run(1.0, -0.3, 0.0);
  EXPECT_NEAR(drive_->odomTwist().linear_mps.x, -0.3, 0.01);
  const cp::Pose relative = drive_->startPose().inverse() * truth();
  EXPECT_LT(relative.position.x, -0.2);  // it really went backwards
  EXPECT_LT(drive_->odomPose().position.x, -0.2);
}

TEST_P(ConDiffDrive, CommandTimeoutBrakes) {
  drive_->command(0.5, 0.0);
  for (int i = 0; i < 400; ++i) step();  // 0.4 s: still within the 0.5 s timeout
  EXPECT_FALSE(drive_->timedOut());
  EXPECT_GT(drive_->odomTwist().linear_mps.x, 0.45);
  for (int i = 0; i < 400; ++i) step();  // 0.8 s without a new command
  EXPECT_TRUE(drive_->timedOut());
  EXPECT_NEAR(drive_->odomTwist().linear_mps.x, 0.0, 0.01);
  const cp::Pose stopped = truth();
  for (int i = 0; i < 500; ++i) step();
  EXPECT_NEAR((truth().position - stopped.position).norm(), 0.0, 0.002);
}

TEST_P(ConDiffDrive, NonFiniteCommandsAreIgnored) {
  run(1.0, 0.3, 0.0);
  EXPECT_FALSE(drive_->command(std::nan(""), 0.0));
  EXPECT_FALSE(drive_->command(0.0, INFINITY));
  for (int i = 0; i < 200; ++i) step();
  EXPECT_NEAR(drive_->odomTwist().linear_mps.x, 0.3, 0.01);  // the last good command holds
}

TEST_P(ConDiffDrive, SameCommandsGiveTheSameTrajectory) {
  auto trajectory = [&]() {
    auto sim = conde_sim_test::simulationWithRobot(flatWorld(), GetParam(), "conde", "conde.urdf.xacro", condeUrdf());
    DiffDrive::Config c;
    c.left_joint = "left_wheel_joint";
    c.right_joint = "right_wheel_joint";
    c.params.wheel_separation_m = 0.33;
    c.params.wheel_diameter_m = 0.064;
    DiffDrive drive(*sim, 0, c);
    return conde_sim_test::baseTrajectory(*sim, drive, 3000, [&](int i) { drive.command(0.4, std::sin(i * 0.001)); });
  };
  EXPECT_EQ(trajectory(), trajectory());
}

INSTANTIATE_TEST_SUITE_P(BothEngines, ConDiffDrive, conde_sim_test::bothEngines(), conde_sim_test::engineName);

TEST(DiffDriveController, WheelSpeedsFromTwist) {
  conde_sim::DiffDriveParams p;
  p.wheel_separation_m = 0.4;
  p.wheel_diameter_m = 0.1;
  conde_sim::DiffDriveController c(p);
  double l, r;
  c.update(0.0, 0.02, l, r);
  EXPECT_EQ(l, 0.0);  // no command yet
  ASSERT_TRUE(c.setCommand(1.0, 2.0, 0.0));
  c.update(0.0, 0.02, l, r);
  EXPECT_DOUBLE_EQ(l, (1.0 - 2.0 * 0.2) / 0.05);
  EXPECT_DOUBLE_EQ(r, (1.0 + 2.0 * 0.2) / 0.05);
}

TEST(DiffDriveController, AccelerationRamp) {
  conde_sim::DiffDriveParams p;
  p.wheel_diameter_m = 0.1;
  p.wheel_acceleration_mps2 = 1.0;
  conde_sim::DiffDriveController c(p);
  c.setCommand(1.0, 0.0, 0.0);
  double l, r;
  c.update(0.0, 0.1, l, r);
  EXPECT_NEAR(l * 0.05, 0.1, 1e-12);  // 1 m/s^2 for 0.1 s
  c.update(0.1, 0.1, l, r);
  EXPECT_NEAR(r * 0.05, 0.2, 1e-12);
}

TEST(DiffDriveOdometry, ArcIntegrationIsExact) {
  // Left wheel still, right wheel turning: a circle about the left wheel.
  conde_sim::DiffDriveOdometry odom(0.5, 0.1);
  odom.reset(0.0, 0.0);
  const double right_rad = M_PI / 2 * 0.5 / 0.1;  // quarter circle of radius 0.5 m
  odom.update(0.0, right_rad, 1.0);
  EXPECT_NEAR(odom.yaw_rad(), M_PI / 2, 1e-12);
  EXPECT_NEAR(odom.x_m(), 0.25, 1e-12);  // centre follows a circle of radius 0.25 m
  EXPECT_NEAR(odom.y_m(), 0.25, 1e-12);
}

}  // namespace

// The in-process tests expand this repository's xacro files: a failing xacro stops the test with
// xacro's message instead of handing its error text on as a URDF.
TEST(SteppedRobotSetup, FailingXacroThrowsItsMessage) {
  try {
    conde_sim_test::xacroUrdf("urdf/robots/no_such_robot.urdf.xacro");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("xacro urdf/robots/no_such_robot.urdf.xacro  failed"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
  EXPECT_NE(conde_sim_test::xacroUrdf("urdf/robots/conde.urdf.xacro").find("<robot"), std::string::npos);
}
