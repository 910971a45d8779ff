// The Ackermann drive on the test car (tests/fixtures/ackermann_car.urdf.xacro), in-process, stepped,
// once per physics engine. Paths, angles and speeds are checked against ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "conde_sim/ackermann_drive.h"
#include "conde_sim/simulation.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;
using conde_sim::AckermannDrive;
using conde_sim_test::testCarUrdf;

namespace {

cp::WorldDescription flatWorld() {
  cp::WorldDescription w = conde_sim_test::flatGround("flat");
  // 10 solver iterations, as the car benchmark and the racetrack world (within 0.2 % of the
  // Ackermann turning radius on both engines; wheels touch as tyres, conde_physics/tyre.h).
  w.physics.solver_iterations = 10;
  return w;  // otherwise default physics: 1 ms step; ground friction 1
}

// Least-squares circle through points (Kasa fit): returns the radius, sets the centre.
double fitCircle(const std::vector<cp::Vec3>& points, double& cx, double& cy) {
  // Solve for (a, b, c) in x^2 + y^2 + a x + b y + c = 0 by normal equations.
  double m[3][4] = {};
  for (const cp::Vec3& p : points) {
    const double row[3] = {p.x, p.y, 1.0};
    const double rhs = -(p.x * p.x + p.y * p.y);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += row[i] * row[j];
      m[i][3] += row[i] * rhs;
    }
  }
  for (int i = 0; i < 3; ++i) {  // Gauss-Jordan (the matrix is symmetric positive definite)
    for (int k = i + 1; k < 3; ++k) {
      const double f = m[k][i] / m[i][i];
      for (int j = i; j < 4; ++j) m[k][j] -= f * m[i][j];
    }
  }
  double x[3];
  for (int i = 2; i >= 0; --i) {
    x[i] = m[i][3];
    for (int j = i + 1; j < 3; ++j) x[i] -= m[i][j] * x[j];
    x[i] /= m[i][i];
  }
  cx = -x[0] / 2.0;
  cy = -x[1] / 2.0;
  return std::sqrt(cx * cx + cy * cy - x[2]);
}

class AckermannCar : public conde_sim_test::SteppedRobotTest {
 protected:
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(buildWorld(flatWorld(), "car", "ackermann_car.urdf", testCarUrdf()));
    makeDrive(defaultConfig());
  }

  static AckermannDrive::Config defaultConfig() {
    AckermannDrive::Config c = AckermannDrive::Config::placeNamedJoints();
    c.base_link = "base_footprint";
    c.encoder_odometry = true;
    return c;
  }

  void makeDrive(const AckermannDrive::Config& c) {
    drive_ = std::make_unique<AckermannDrive>(*sim_, 0, c);
    run(0.3, [] {});  // settle on the wheels
    drive_->reset();
  }

  template <class Command>
  void run(double seconds, Command command) {
    const int steps = static_cast<int>(std::lround(seconds / sim_->stepS()));
    for (int i = 0; i < steps; ++i) {
      if (i % 50 == 0) command();  // 20 Hz, like a driver node
      step();
    }
  }

  void drive(double seconds, double speed, double steering) {
    run(seconds, [&] { drive_->commandDrive(speed, steering); });
  }

  void step() { conde_sim_test::stepWithDrive(*sim_, *drive_); }

  cp::Pose truth() const { return sim_->linkPose(0, "base_footprint"); }
  cp::Twist truthTwist() const { return sim_->linkTwist(0, "base_footprint"); }
  double wheelbase() const { return drive_->geometry().wheelbase_m; }

  // Drives at (speed, steering) and returns the radius of the circle the base_footprint (the
  // rear-axle centre) follows, fitted over one full turn after a second of settling.
  double turningRadius(double speed, double steering) {
    drive(1.0, speed, steering);
    const double radius = wheelbase() / std::tan(std::abs(steering));
    const double turn_s = 2.0 * M_PI * radius / std::abs(speed);
    std::vector<cp::Vec3> path;
    run(turn_s, [&] {
      drive_->commandDrive(speed, steering);
      path.push_back(truth().position);
    });
    double cx, cy;
    const double fitted_m = fitCircle(path, cx, cy);
    std::printf("[ radius   ] %s, %.2f m/s, steering %+.2f rad: %.4f m, L / tan(delta) %.4f m (%+.2f %%)\n",
                GetParam().c_str(), speed, steering, fitted_m, radius, 100.0 * (fitted_m - radius) / radius);
    return fitted_m;
  }

  std::unique_ptr<AckermannDrive> drive_;
};

TEST_P(AckermannCar, GeometryComesFromTheUrdf) {
  EXPECT_NEAR(drive_->geometry().wheelbase_m, 0.33, 1e-9);
  EXPECT_NEAR(drive_->geometry().front_half_track_m, 0.12, 1e-9);
  EXPECT_NEAR(drive_->geometry().rear_half_track_m, 0.12, 1e-9);
  EXPECT_NEAR(drive_->geometry().wheel_radius_m, 0.05, 1e-9);
  // Hinges stop at 0.6 rad: the inner wheel reaches it at the largest centre angle.
  EXPECT_NEAR(conde_sim::frontWheelAngles(drive_->geometry(), drive_->maxSteeringAngle()).left_rad, 0.6, 1e-9);
}

TEST_P(AckermannCar, TurningRadiusIsWheelbaseOverTanDelta) {
  for (double steering : {0.3, -0.2}) {
    const double expected_m = wheelbase() / std::tan(std::abs(steering));
    const double radius_m = turningRadius(0.5, steering);
    EXPECT_NEAR(radius_m, expected_m, 0.03 * expected_m) << "steering " << steering;
  }
}

TEST_P(AckermannCar, FourWheelDriveTurnsOnTheSameCircle) {
  AckermannDrive::Config c = defaultConfig();
  c.drive_front = true;
  makeDrive(c);
  const double expected_m = wheelbase() / std::tan(0.3);
  EXPECT_NEAR(turningRadius(0.5, 0.3), expected_m, 0.03 * expected_m);
}

TEST_P(AckermannCar, SteeringSettlesOnTheAckermannAnglesWithoutOscillation) {
  drive(0.5, 0.3, 0.0);
  const double delta = 0.35;
  const conde_sim::FrontWheelAngles target = conde_sim::frontWheelAngles(drive_->geometry(), delta);
  drive_->commandDrive(0.3, delta);
  // Settling: within 2 % of the step after 0.3 s (the hinges turn at up to 10 rad/s).
  run(0.3, [&] { drive_->commandDrive(0.3, delta); });
  EXPECT_NEAR(drive_->measuredSteering().left_rad, target.left_rad, 0.02 * delta);
  EXPECT_NEAR(drive_->measuredSteering().right_rad, target.right_rad, 0.02 * delta);
  // Then it stays there: no sustained oscillation over the next second.
  double worst_left = 0.0, worst_right = 0.0;
  for (int i = 0; i < 1000; ++i) {
    if (i % 50 == 0) drive_->commandDrive(0.3, delta);
    step();
    worst_left = std::max(worst_left, std::abs(drive_->measuredSteering().left_rad - target.left_rad));
    worst_right = std::max(worst_right, std::abs(drive_->measuredSteering().right_rad - target.right_rad));
  }
  // Contact noise may shake the wheels by a few milliradians; an oscillation of the PID loop
  // would be far larger.
  EXPECT_LT(worst_left, 0.005);
  EXPECT_LT(worst_right, 0.005);
  // Inner (left) wheel turns more than the outer one, as Ackermann geometry wants.
  EXPECT_GT(drive_->measuredSteering().left_rad, drive_->measuredSteering().right_rad + 0.03);
}

TEST_P(AckermannCar, ReversingDrivesBackwardsAndTurnsTheOtherWay) {
  const cp::Pose start = truth();
  drive(2.0, -0.4, 0.25);
  const cp::Pose relative = start.inverse() * truth();
  EXPECT_LT(relative.position.x, -0.5);
  // Backwards with the wheels turned left: the car yaws clockwise (yaw rate v tan(delta) / L < 0).
  EXPECT_NEAR(truthTwist().angular_radps.z, -0.4 * std::tan(0.25) / wheelbase(),
              0.03 * 0.4 * std::tan(0.25) / wheelbase());
  EXPECT_LT(drive_->odomTwist().linear_mps.x, -0.35);  // signed encoder speed
  const double expected_m = wheelbase() / std::tan(0.25);
  EXPECT_NEAR(turningRadius(-0.4, 0.25), expected_m, 0.03 * expected_m);
}

TEST_P(AckermannCar, CommandTimeoutBrakesAndHoldsTheSteering) {
  drive_->commandDrive(0.6, 0.2);
  for (int i = 0; i < 450; ++i) step();  // within the 0.5 s timeout
  EXPECT_FALSE(drive_->timedOut());
  EXPECT_GT(drive_->odomTwist().linear_mps.x, 0.5);
  for (int i = 0; i < 1000; ++i) step();  // 1.45 s after the only command
  EXPECT_TRUE(drive_->timedOut());
  EXPECT_NEAR(std::hypot(truthTwist().linear_mps.x, truthTwist().linear_mps.y), 0.0, 0.01);
  const conde_sim::FrontWheelAngles held = conde_sim::frontWheelAngles(drive_->geometry(), 0.2);
  EXPECT_NEAR(drive_->measuredSteering().left_rad, held.left_rad, 0.01);
  const cp::Pose stopped = truth();
  for (int i = 0; i < 1000; ++i) step();
  EXPECT_LT((truth().position - stopped.position).norm(), 0.002);
}

TEST_P(AckermannCar, TwistAngularZIsAYawRate) {
  const double v = 0.5, omega = 0.6;
  run(2.0, [&] { drive_->commandTwist(v, omega); });
  EXPECT_NEAR(truthTwist().angular_radps.z, omega, 0.03 * omega);
  // Read as an angle (ros_controllers #412), 0.6 rad would give v tan(0.6) / L = 1.04 rad/s.
  EXPECT_NEAR(drive_->steeringSetpoint(), std::atan(omega * wheelbase() / v), 1e-9);
  // Reversing with the same Twist still turns counter-clockwise.
  run(3.0, [&] { drive_->commandTwist(-v, omega); });
  EXPECT_NEAR(truthTwist().angular_radps.z, omega, 0.03 * omega);
}

TEST_P(AckermannCar, RateLimitsOfTheAckermannDriveMessage) {
  drive_->commandDrive(1.0, 0.3, 0.5, 0.5);  // 0.5 rad/s steering, 0.5 m/s^2
  for (int i = 0; i < 200; ++i) step();
  EXPECT_NEAR(drive_->steeringSetpoint(), 0.1, 1e-6);
  EXPECT_NEAR(drive_->speedSetpoint(), 0.1, 1e-6);
}

TEST_P(AckermannCar, NonFiniteCommandsAreIgnored) {
  drive(1.0, 0.4, 0.1);
  EXPECT_FALSE(drive_->commandDrive(std::nan(""), 0.0));
  EXPECT_FALSE(drive_->commandDrive(0.0, INFINITY));
  EXPECT_FALSE(drive_->commandTwist(0.2, std::nan("")));
  EXPECT_DOUBLE_EQ(drive_->steeringSetpoint(), 0.1);
  EXPECT_DOUBLE_EQ(drive_->speedSetpoint(), 0.4);
}

TEST_P(AckermannCar, EncoderOdometryFollowsGroundTruth) {
  const cp::Pose start = truth();
  double path_m = 0.0;
  for (double steering : {0.3, -0.3, 0.0, 0.4}) {
    drive(2.0, 0.5, steering);
    path_m += 1.0;
  }
  drive(0.5, 0.0, 0.0);
  const cp::Pose relative = start.inverse() * truth();
  const cp::Pose& odom = drive_->odomPose();
  EXPECT_LT(std::hypot(odom.position.x - relative.position.x, odom.position.y - relative.position.y), 0.03 * path_m);
  EXPECT_NEAR(cp::wrapAngle(odom.orientation.yaw() - relative.orientation.yaw()), 0.0, 0.05);
}

TEST_P(AckermannCar, SameCommandsGiveTheSameTrajectory) {
  auto trajectory = [&]() {
    auto sim = conde_sim_test::simulationWithRobot(flatWorld(), GetParam(), "car", "ackermann_car.urdf", testCarUrdf());
    AckermannDrive drive(*sim, 0, defaultConfig());
    return conde_sim_test::baseTrajectory(*sim, drive, 2000,
                                          [&](int i) { drive.commandDrive(0.6, 0.3 * std::sin(i * 0.002)); });
  };
  EXPECT_EQ(trajectory(), trajectory());
}

INSTANTIATE_TEST_SUITE_P(BothEngines, AckermannCar, conde_sim_test::bothEngines(), conde_sim_test::engineName);

TEST(AckermannOdometry, ArcOfTheRearAxleCentre) {
  // Base frame 0.1 m ahead of the rear axle; quarter circle of radius R = L / tan(delta).
  const double l = 0.3, delta = 0.4, r = l / std::tan(delta);
  conde_sim::AckermannOdometry odom(l, -0.1, 0.0);
  odom.reset();
  EXPECT_NEAR(odom.x_m(), 0.0, 1e-12);
  odom.update(M_PI / 2 * r, delta, 1.0);
  EXPECT_NEAR(odom.yaw_rad(), M_PI / 2, 1e-12);
  // The axle went from (-0.1, 0) to (-0.1 + R, R); the base is 0.1 m further along +y.
  EXPECT_NEAR(odom.x_m(), -0.1 + r, 1e-12);
  EXPECT_NEAR(odom.y_m(), r + 0.1, 1e-12);
  EXPECT_NEAR(odom.angular_radps(), M_PI / 2, 1e-12);
  EXPECT_NEAR(odom.linear_y_mps(), M_PI / 2 * 0.1, 1e-12);  // the base swings sideways
}

}  // namespace
