#include "conde_sim/laser_scanner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

LaserScanner::LaserScanner(Simulation& sim, int robot, const LaserScanConfig& config)
    : sim_(sim), robot_(robot), config_(config), rng_(config.noise_seed) {
  if (config.beam_count < 1) throw std::invalid_argument("a laser scanner needs at least one beam");
  if (config.beam_count > 1 && !(config.min_angle_rad < config.max_angle_rad)) {
    throw std::invalid_argument("the laser's min angle must be below its max angle");
  }
  if (!(config.min_range_m >= 0.0 && config.min_range_m < config.max_range_m)) {
    throw std::invalid_argument("the laser's ranges need 0 <= min < max");
  }
  if (!(config.noise_stddev_m >= 0.0)) throw std::invalid_argument("the laser's noise stddev must not be negative");
  if (config.vertical_count < 1) throw std::invalid_argument("a ray grid needs at least one row");
  if (config.vertical_count > 1 && !(config.min_vertical_angle_rad < config.max_vertical_angle_rad)) {
    throw std::invalid_argument("the ray grid's min vertical angle must be below its max vertical angle");
  }
  sim.linkPose(robot, config.link);  // throws std::out_of_range for an unknown link
  const int columns = config.beam_count, rows = config.vertical_count;
  increment_rad_ = columns > 1 ? (config.max_angle_rad - config.min_angle_rad) / (columns - 1) : 0.0;
  vertical_increment_rad_ =
      rows > 1 ? (config.max_vertical_angle_rad - config.min_vertical_angle_rad) / (rows - 1) : 0.0;
  const int n = columns * rows;
  directions_in_sensor_.resize(n);
  for (int j = 0; j < rows; ++j) {
    const double pitch = config.min_vertical_angle_rad + j * vertical_increment_rad_;
    for (int i = 0; i < columns; ++i) {
      const double yaw = config.min_angle_rad + i * increment_rad_;
      directions_in_sensor_[i + j * columns] =
          cp::Vec3(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
    }
  }
  origins_.resize(n);
  directions_.resize(n);
  hits_.resize(n);
  ranges_.resize(n);
}

const std::vector<float>& LaserScanner::scan() {
  const cp::Pose sensor = sim_.linkPose(robot_, config_.link) * config_.sensor_in_link;
  const double min_m = config_.min_range_m;
  const int n = static_cast<int>(directions_in_sensor_.size());
  for (int i = 0; i < n; ++i) {
    directions_[i] = sensor.orientation.rotate(directions_in_sensor_[i]);
    origins_[i] = sensor.position + directions_[i] * min_m;
  }
  sim_.engine().castRays(origins_, directions_, config_.max_range_m - min_m, sim_.robot(robot_).id, hits_);
  const bool noisy = config_.noise_stddev_m > 0.0 || config_.noise_mean_m != 0.0;
  for (int i = 0; i < n; ++i) {
    if (!hits_[i].hit) {
      ranges_[i] = std::numeric_limits<float>::infinity();
      continue;
    }
    double range_m = min_m + hits_[i].distance_m;
    if (noisy) {
      range_m += config_.noise_mean_m + config_.noise_stddev_m * gauss_(rng_);
      range_m = std::clamp(range_m, min_m, config_.max_range_m);
    }
    ranges_[i] = static_cast<float>(range_m);
  }
  return ranges_;
}

}  // namespace conde_sim
