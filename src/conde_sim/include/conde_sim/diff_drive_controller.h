// Differential-drive logic of the diff-drive plugin, free of ROS so tests can call it directly.
//
// Kinematics: wheel surface speeds v_l = v - w s / 2 and v_r = v + w s / 2 with s the wheel
// separation; joint targets v / r. Differences from gazebo_ros_diff_drive, on purpose:
// a command timeout brakes the robot (Gazebo keeps the last command forever), NaN or infinite
// commands are rejected, and encoder odometry reports signed speeds in the base frame (Gazebo's
// encoder mode loses the sign when reversing, gazebo_ros_pkgs #1552).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_sim/timed_command.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {

class Simulation;

struct DiffDriveParams {
  double wheel_separation_m = 0.34;  // gazebo_ros_diff_drive defaults
  double wheel_diameter_m = 0.15;
  double wheel_acceleration_mps2 = 0.0;  // ramp on each wheel's surface speed; 0 = none
  double command_timeout_s = 0.5;        // 0 disables the timeout
};

class DiffDriveController {
 public:
  explicit DiffDriveController(const DiffDriveParams& params) : params_(params) {}

  // Returns false, keeping the previous command, when a value is NaN or infinite.
  bool setCommand(double linear_mps, double angular_radps, double time_s);
  // Wheel joint velocity targets [rad/s] at `time_s`, `dt_s` after the previous call.
  void update(double time_s, double dt_s, double& left_radps, double& right_radps);
  bool timedOut(double time_s) const;
  void reset();

 private:
  DiffDriveParams params_;
  TimedCommand command_;                     // linear [m/s], angular [rad/s]
  double left_mps_ = 0.0, right_mps_ = 0.0;  // ramped wheel surface speeds
};

// Dead reckoning from the wheel joint angles (exact arc integration between updates).
class DiffDriveOdometry {
 public:
  DiffDriveOdometry(double wheel_separation_m, double wheel_radius_m)
      : separation_m_(wheel_separation_m), radius_m_(wheel_radius_m) {}

  void reset(double left_rad, double right_rad);
  void update(double left_rad, double right_rad, double dt_s);

  double x_m() const { return x_m_; }
  double y_m() const { return y_m_; }
  double yaw_rad() const { return yaw_rad_; }
  double linear_mps() const { return linear_mps_; }  // signed, base frame x
  double angular_radps() const { return angular_radps_; }

 private:
  double separation_m_, radius_m_;
  double last_left_rad_ = 0.0, last_right_rad_ = 0.0;
  double x_m_ = 0.0, y_m_ = 0.0, yaw_rad_ = 0.0;
  double linear_mps_ = 0.0, angular_radps_ = 0.0;
};

// The whole diff drive on a simulated robot, minus ROS: commands in, wheel motors driven at the
// update rate, odometry (encoder or ground truth) out. The plugin adds topics and TF around it.
class DiffDrive {
 public:
  struct Config {
    DiffDriveParams params;
    std::string left_joint, right_joint;
    // More wheels driven like the left or right one (skid steer's rear wheels); odometry reads
    // only left_joint and right_joint.
    std::vector<std::string> more_left_joints, more_right_joints;
    std::string base_link = "base_footprint";
    double wheel_torque_nm = 5.0;
    double update_rate_hz = 100.0;
    bool encoder_odometry = false;  // false: ground truth ("world")
  };
  // Throws std::invalid_argument naming the joint or link that the robot lacks.
  DiffDrive(Simulation& sim, int robot, const Config& config);

  bool command(double linear_mps, double angular_radps);  // false for NaN/inf (ignored)
  bool timedOut() const;
  void reset();
  void beforeStep();
  // True after a step at which the odometry was updated (at the update rate).
  bool afterStep();

  // Odometry of the base link: pose in the odom frame and twist in the base frame.
  const conde_physics::Pose& odomPose() const { return odom_pose_; }
  const conde_physics::Twist& odomTwist() const { return odom_twist_; }
  // Where the base link started (the odom frame's origin for encoder odometry).
  const conde_physics::Pose& startPose() const { return start_pose_; }
  bool encoderOdometry() const { return config_.encoder_odometry; }
  int leftJoint() const { return left_; }
  int rightJoint() const { return right_; }

 private:
  Simulation& sim_;
  int robot_;
  Config config_;
  int left_ = -1, right_ = -1;
  std::vector<int> more_left_, more_right_;
  UpdateTimer timer_;
  std::uint64_t last_update_step_ = 0;
  DiffDriveController controller_;
  DiffDriveOdometry odometry_;
  conde_physics::Pose odom_pose_, start_pose_;
  conde_physics::Twist odom_twist_;
};

}  // namespace conde_sim
