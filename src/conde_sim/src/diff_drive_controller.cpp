#include "conde_sim/diff_drive_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "conde_sim/drive_odometry.h"
#include "conde_sim/simulation.h"

namespace conde_sim {

bool DiffDriveController::setCommand(double linear_mps, double angular_radps, double time_s) {
  return command_.set(linear_mps, angular_radps, time_s);
}

bool DiffDriveController::timedOut(double time_s) const { return command_.timedOut(time_s, params_.command_timeout_s); }

void DiffDriveController::update(double time_s, double dt_s, double& left_radps, double& right_radps) {
  double v = command_.first, w = command_.second;  // [m/s], [rad/s]
  if (!command_.received || timedOut(time_s)) v = w = 0.0;
  const double left_target = v - w * params_.wheel_separation_m / 2.0;
  const double right_target = v + w * params_.wheel_separation_m / 2.0;
  if (params_.wheel_acceleration_mps2 > 0.0) {
    const double max_change = params_.wheel_acceleration_mps2 * dt_s;
    left_mps_ += std::clamp(left_target - left_mps_, -max_change, max_change);
    right_mps_ += std::clamp(right_target - right_mps_, -max_change, max_change);
  } else {
    left_mps_ = left_target;
    right_mps_ = right_target;
  }
  const double radius_m = params_.wheel_diameter_m / 2.0;
  left_radps = left_mps_ / radius_m;
  right_radps = right_mps_ / radius_m;
}

void DiffDriveController::reset() {
  command_.reset();
  left_mps_ = right_mps_ = 0.0;
}

void DiffDriveOdometry::reset(double left_rad, double right_rad) {
  last_left_rad_ = left_rad;
  last_right_rad_ = right_rad;
  x_m_ = y_m_ = yaw_rad_ = 0.0;
  linear_mps_ = angular_radps_ = 0.0;
}

void DiffDriveOdometry::update(double left_rad, double right_rad, double dt_s) {
  const double dl = (left_rad - last_left_rad_) * radius_m_;
  const double dr = (right_rad - last_right_rad_) * radius_m_;
  last_left_rad_ = left_rad;
  last_right_rad_ = right_rad;
  const double ds = (dl + dr) / 2.0;
  const double dyaw = (dr - dl) / separation_m_;
  integrateArc(ds, dyaw, x_m_, y_m_, yaw_rad_);
  if (dt_s > 0.0) {
    linear_mps_ = ds / dt_s;
    angular_radps_ = dyaw / dt_s;
  }
}

namespace cp = conde_physics;

DiffDrive::DiffDrive(Simulation& sim, int robot, const Config& config)
    : sim_(sim),
      robot_(robot),
      config_(config),
      controller_(config.params),
      odometry_(config.params.wheel_separation_m, config.params.wheel_diameter_m / 2.0) {
  const cp::ArticulatedModel& model = sim.robot(robot).model;
  left_ = model.jointIndex(config.left_joint);
  right_ = model.jointIndex(config.right_joint);
  if (left_ < 0) throw std::invalid_argument("no movable joint named '" + config.left_joint + "'");
  if (right_ < 0) throw std::invalid_argument("no movable joint named '" + config.right_joint + "'");
  for (const auto& [names, indices] : {std::make_pair(&config.more_left_joints, &more_left_),
                                       std::make_pair(&config.more_right_joints, &more_right_)}) {
    for (const std::string& name : *names) {
      indices->push_back(model.jointIndex(name));
      if (indices->back() < 0) throw std::invalid_argument("no movable joint named '" + name + "'");
    }
  }
  int body = -1;
  cp::Pose unused;
  if (!model.linkInBody(config.base_link, body, unused)) {
    throw std::invalid_argument("no link named '" + config.base_link + "'");
  }
  timer_ = UpdateTimer(config.update_rate_hz, sim.stepS());
  reset();
}

bool DiffDrive::command(double linear_mps, double angular_radps) {
  return controller_.setCommand(linear_mps, angular_radps, sim_.timeS());
}

bool DiffDrive::timedOut() const { return controller_.timedOut(sim_.timeS()); }

void DiffDrive::reset() {
  controller_.reset();
  const cp::ModelId id = sim_.robot(robot_).id;
  odometry_.reset(sim_.engine().jointPosition(id, left_), sim_.engine().jointPosition(id, right_));
  start_pose_ = sim_.linkPose(robot_, config_.base_link);
  odom_pose_ = config_.encoder_odometry ? cp::Pose() : start_pose_;
  odom_twist_ = cp::Twist();
  last_update_step_ = sim_.stepCount();
}

void DiffDrive::beforeStep() {
  if (!timer_.due(sim_.stepCount())) return;
  double left_radps = 0, right_radps = 0;
  controller_.update(sim_.timeS(), timer_.stepsPerUpdate() * sim_.stepS(), left_radps, right_radps);
  const cp::ModelId id = sim_.robot(robot_).id;
  sim_.engine().setJointVelocityMotor(id, left_, left_radps, config_.wheel_torque_nm);
  sim_.engine().setJointVelocityMotor(id, right_, right_radps, config_.wheel_torque_nm);
  for (int j : more_left_) sim_.engine().setJointVelocityMotor(id, j, left_radps, config_.wheel_torque_nm);
  for (int j : more_right_) sim_.engine().setJointVelocityMotor(id, j, right_radps, config_.wheel_torque_nm);
}

bool DiffDrive::afterStep() {
  const std::uint64_t step = sim_.stepCount();
  if (!timer_.due(step)) return false;
  const double dt_s = static_cast<double>(step - last_update_step_) * sim_.stepS();
  last_update_step_ = step;
  const cp::ModelId id = sim_.robot(robot_).id;
  if (config_.encoder_odometry) {
    odometry_.update(sim_.engine().jointPosition(id, left_), sim_.engine().jointPosition(id, right_), dt_s);
    odom_pose_ =
        cp::Pose(cp::Vec3(odometry_.x_m(), odometry_.y_m(), 0.0), cp::Quat::fromRpy(0, 0, odometry_.yaw_rad()));
    odom_twist_.linear_mps = cp::Vec3(odometry_.linear_mps(), 0, 0);
    odom_twist_.angular_radps = cp::Vec3(0, 0, odometry_.angular_radps());
  } else {
    groundTruthOdometry(sim_, robot_, config_.base_link, odom_pose_, odom_twist_);
  }
  return true;
}

}  // namespace conde_sim
