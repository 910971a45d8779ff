// A planar scanning range finder (2D LiDAR) on a robot's link, free of ROS: one batch ray cast
// per scan through the physics engine, ignoring the robot that carries it, into buffers that
// are allocated once (no allocation per beam or per scan).
//
// Beam i (0 <= i < beamCount()) points at angle min_angle + i * angleIncrement() about the
// sensor's z axis, counter-clockwise from its x axis (REP 103), as sensor_msgs/LaserScan
// describes it. With vertical_count > 1 the beams form a grid (Gazebo's ray sensor with
// <vertical> samples): ray i + j * beamCount() has yaw as beam i and pitch (elevation, up
// positive) min_vertical_angle + j * verticalIncrement(), direction
// (cos pitch cos yaw, cos pitch sin yaw, sin pitch). As Gazebo's ray sensor, each ray starts at min_range from the
// sensor (nothing nearer is seen); a range is the distance from the sensor. Ranges follow REP 117: +inf when nothing
// lies within max_range. Gaussian noise (if any) is added to hits only, and the result is kept within [min_range,
// max_range].
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/physics_engine.h"

namespace conde_sim {

class Simulation;

struct LaserScanConfig {
  std::string link;                                                   // link carrying the sensor
  conde_physics::Pose sensor_in_link;                                 // SDF <sensor><pose>
  int beam_count = 640;                                               // >= 1 (Gazebo: samples x resolution)
  double min_angle_rad = 0.0, max_angle_rad = 0.0;                    // min < max, unless beam_count == 1
  int vertical_count = 1;                                             // rows of the grid, >= 1
  double min_vertical_angle_rad = 0.0, max_vertical_angle_rad = 0.0;  // min < max, unless 1 row
  double min_range_m = 0.1, max_range_m = 10.0;                       // 0 <= min < max
  double noise_mean_m = 0.0, noise_stddev_m = 0.0;
  std::uint32_t noise_seed = 0;  // deterministic noise: same seed, same scans
};

class LaserScanner {
 public:
  // Throws std::invalid_argument for a config that breaks the limits above or an unknown link.
  LaserScanner(Simulation& sim, int robot, const LaserScanConfig& config);

  int beamCount() const { return config_.beam_count; }  // rays per row
  int rowCount() const { return config_.vertical_count; }
  // (max - min) / (beams - 1), 0 for a single beam (as Gazebo's gazebo_ros_laser).
  double angleIncrement() const { return increment_rad_; }
  double verticalIncrement() const { return vertical_increment_rad_; }
  // Unit direction of ray `index` (i + j * beamCount()) in the sensor frame.
  const conde_physics::Vec3& directionInSensor(int index) const { return directions_in_sensor_[index]; }
  const LaserScanConfig& config() const { return config_; }

  // Casts every ray from the link's current pose; the result (beamCount() x rowCount() ranges,
  // row by row) lives until the next scan().
  const std::vector<float>& scan();
  const std::vector<float>& ranges() const { return ranges_; }

 private:
  Simulation& sim_;
  int robot_;
  LaserScanConfig config_;
  double increment_rad_ = 0.0, vertical_increment_rad_ = 0.0;
  std::vector<conde_physics::Vec3> directions_in_sensor_;
  std::vector<conde_physics::Vec3> origins_, directions_;
  std::vector<conde_physics::RayHit> hits_;
  std::vector<float> ranges_;
  std::mt19937_64 rng_;  // one draw per uniform double (mt19937 needs two for 53 bits)
  std::normal_distribution<double> gauss_{0.0, 1.0};
};

}  // namespace conde_sim
