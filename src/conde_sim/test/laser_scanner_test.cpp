// The 2D LiDAR on the test car facing walls at known distances, once per physics engine.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "conde_sim/laser_scanner.h"
#include "conde_sim/simulation.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;
using conde_sim::LaserScanConfig;
using conde_sim::LaserScanner;
using conde_sim::Simulation;
using conde_sim_test::addRobot;
using conde_sim_test::testCarUrdf;

namespace {

constexpr double kFrontWallFace_m = 2.0;  // world x of the wall ahead of the car
constexpr double kLeftWallFace_m = 1.0;   // world y of the wall on the car's left

cp::WorldObject wall(const std::string& name, double x, double y, double size_x, double size_y) {
  cp::WorldObject o;
  o.name = name;
  o.shape = cp::ObjectShape::kBox;
  o.size_m = cp::Vec3(size_x, size_y, 0.5);
  o.pose = cp::Pose(cp::Vec3(x, y, 0.25), cp::Quat());
  return o;
}

// Empty unless `walls`: a 0.1 m thick wall ahead (face at x = 2 m, 3 m wide) and one on the
// left (face at y = 1 m, from x = -3 m to 1.5 m).
cp::WorldDescription world(bool walls) {
  cp::WorldDescription w = conde_sim_test::flatGround(walls ? "walls" : "empty");
  if (walls) {
    w.objects.push_back(wall("front", kFrontWallFace_m + 0.05, 0.0, 0.1, 3.0));
    w.objects.push_back(wall("left", -0.75, kLeftWallFace_m + 0.05, 4.5, 0.1));
  }
  return w;
}

// The fixture's LiDAR: 1081 beams over 270 degrees, 0.06..10 m.
LaserScanConfig fixtureLidar(double noise_stddev_m) {
  LaserScanConfig c;
  c.link = "laser";
  c.beam_count = 1081;
  c.min_angle_rad = -3.0 * M_PI / 4.0;
  c.max_angle_rad = 3.0 * M_PI / 4.0;
  c.min_range_m = 0.06;
  c.max_range_m = 10.0;
  c.noise_stddev_m = noise_stddev_m;
  return c;
}

class Lidar : public conde_sim_test::SteppedRobotTest {
 protected:
  void build(bool walls) {
    ASSERT_NO_FATAL_FAILURE(buildWorld(world(walls), "car", "ackermann_car.urdf", testCarUrdf()));
    for (int i = 0; i < 300; ++i) sim_->step();  // settle on the wheels
  }

  cp::Pose laserPose() const { return sim_->linkPose(0, "laser"); }
};

TEST_P(Lidar, CentreBeamReadsTheWallDistance) {
  build(true);
  LaserScanner lidar(*sim_, 0, fixtureLidar(0.0));
  ASSERT_EQ(lidar.beamCount(), 1081);
  const std::vector<float>& ranges = lidar.scan();
  const double expected_m = kFrontWallFace_m - laserPose().position.x;
  EXPECT_NEAR(ranges[540], expected_m, 0.01);
}

TEST_P(Lidar, AnglesAndRangesMatchTheHeader) {
  build(true);
  LaserScanner lidar(*sim_, 0, fixtureLidar(0.0));
  EXPECT_NEAR(lidar.angleIncrement(), 1.5 * M_PI / 1080.0, 1e-12);
  const std::vector<float>& ranges = lidar.scan();
  const cp::Pose laser = laserPose();
  const double yaw = laser.orientation.yaw();
  const double to_front_m = kFrontWallFace_m - laser.position.x;
  const double to_left_m = kLeftWallFace_m - laser.position.y;
  int front = 0, left = 0, open = 0;
  for (int i = 0; i < lidar.beamCount(); ++i) {
    const double angle = lidar.config().min_angle_rad + i * lidar.angleIncrement() + yaw;
    const double c = std::cos(angle), s = std::sin(angle);
    // Where the beam would meet each wall's face, along the wall: the front wall spans
    // y in [-1.5, 1.5], the left wall x in [-3, 1.5]. Beams that graze an end are left out.
    const double t_front = c > 1e-9 ? to_front_m / c : INFINITY;
    const double t_left = s > 1e-9 ? to_left_m / s : INFINITY;
    const double front_y = laser.position.y + t_front * s, left_x = laser.position.x + t_left * c;
    const bool near_end = (std::isfinite(t_front) && std::abs(std::abs(front_y) - 1.5) < 0.1) ||
                          (std::isfinite(t_left) && (std::abs(left_x + 3.0) < 0.1 || std::abs(left_x - 1.5) < 0.1));
    if (near_end) continue;
    const bool on_front = std::isfinite(t_front) && std::abs(front_y) < 1.5;
    const bool on_left = std::isfinite(t_left) && left_x > -3.0 && left_x < 1.5;
    const double expected = std::min(on_front ? t_front : INFINITY, on_left ? t_left : INFINITY);
    if (!std::isfinite(expected) || expected > 9.9) {  // nothing within range that way
      EXPECT_TRUE(std::isinf(ranges[i])) << "beam " << i << " reads " << ranges[i];
      ++open;
      continue;
    }
    EXPECT_NEAR(ranges[i], expected, 0.01) << "beam " << i;
    (expected == t_front ? front : left)++;
  }
  // The scan really saw both walls and open space.
  EXPECT_GT(front, 300);
  EXPECT_GT(left, 200);
  EXPECT_GT(open, 100);
  EXPECT_NEAR(ranges[900], to_left_m, 0.01);  // beam 900 points at +90 degrees
}

TEST_P(Lidar, NoiseHasTheConfiguredStandardDeviation) {
  build(true);
  const double stddev_m = 0.02, mean_m = 0.005;
  LaserScanConfig c = fixtureLidar(stddev_m);
  c.noise_mean_m = mean_m;
  LaserScanner lidar(*sim_, 0, c);
  LaserScanner exact(*sim_, 0, fixtureLidar(0.0));
  const std::vector<float> truth = exact.scan();
  double sum = 0.0, sum_sq = 0.0;
  int n = 0;
  for (int scan = 0; scan < 20; ++scan) {
    const std::vector<float>& ranges = lidar.scan();
    for (int i = 440; i <= 640; ++i) {  // the beams that hit the front wall
      const double e = ranges[i] - truth[i];
      sum += e;
      sum_sq += e * e;
      ++n;
    }
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, mean_m, 0.001);  // 4020 samples: standard error 0.0003 m
  EXPECT_NEAR(sd, stddev_m, 0.05 * stddev_m);
}

TEST_P(Lidar, TheCarryingRobotIsInvisible) {
  build(false);
  // Mounted inside the chassis box and low enough to sweep across the car's own wheels.
  LaserScanConfig c = fixtureLidar(0.0);
  c.link = "base_link";
  c.sensor_in_link = cp::Pose(cp::Vec3(0.165, 0.0, 0.0), cp::Quat());
  c.min_range_m = 0.0;
  LaserScanner lidar(*sim_, 0, c);
  for (float r : lidar.scan()) ASSERT_TRUE(std::isinf(r)) << r;
}

TEST_P(Lidar, OtherRobotsAreSeen) {
  build(false);
  // 1.5 m ahead, rear axle first.
  addRobot(*sim_, "other", "ackermann_car.urdf", testCarUrdf(), cp::Pose(cp::Vec3(1.5, 0.0, 0.0), cp::Quat()));
  LaserScanConfig c = fixtureLidar(0.0);
  c.link = "base_link";
  c.sensor_in_link = cp::Pose(cp::Vec3(0.4, 0.0, 0.045), cp::Quat());  // in its own front bumper
  LaserScanner lidar(*sim_, 0, c);
  const double bumper_x = sim_->linkPose(0, "base_link").position.x + 0.4;
  const double other_rear_x = 1.5 + 0.165 - 0.25;  // its chassis box starts 0.085 m behind its axle
  EXPECT_NEAR(lidar.scan()[540], other_rear_x - bumper_x, 0.01);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, Lidar, conde_sim_test::bothEngines(), conde_sim_test::engineName);

TEST(LaserScanner, RejectsBadConfigurations) {
  Simulation sim(world(false), "ode", nullptr);
  addRobot(sim, "car", "ackermann_car.urdf", testCarUrdf());
  LaserScanConfig c = fixtureLidar(0.0);
  c.beam_count = 0;
  EXPECT_THROW(LaserScanner(sim, 0, c), std::invalid_argument);
  c = fixtureLidar(0.0);
  c.max_angle_rad = c.min_angle_rad;
  EXPECT_THROW(LaserScanner(sim, 0, c), std::invalid_argument);
  c = fixtureLidar(0.0);
  c.max_range_m = c.min_range_m;
  EXPECT_THROW(LaserScanner(sim, 0, c), std::invalid_argument);
  c = fixtureLidar(0.0);
  c.link = "no_such_link";
  EXPECT_THROW(LaserScanner(sim, 0, c), std::out_of_range);
}

}  // namespace
