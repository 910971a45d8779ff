// Tricycle drive logic of libgazebo_ros_tricycle_drive.so, free of ROS: a steered and driven front
// wheel (steering joint + actuated wheel joint) and two passive rear wheels whose joints serve as
// encoders. Command: geometry_msgs/Twist linear.x = the actuated wheel's surface speed [m/s],
// angular.z = the steering angle [rad] (not a yaw rate), as gazebo_ros_tricycle_drive reads it.
//
// What each update does (gazebo_ros_tricycle_drive's motorController):
//   wheel: target joint speed = speed / (actuatedWheelDiameter / 2); with wheelAcceleration > 0
//     the applied speed moves from the wheel's current speed towards the target by at most
//     wheelAcceleration * dt when the speed grows, wheelDeceleration * dt when it shrinks (within
//     wheelSpeedTolerance it is the target), in [rad/s^2] as Gazebo applies them to joint speeds.
//   steering: the target is held within +-pi/2; with steeringSpeed > 0 the joint turns at
//     +-steeringSpeed [rad/s] towards it until within steeringAngleTolerance, else it is driven to
//     the target at once (Gazebo sets the joint position; here a velocity motor reaches it).
// Differences from Gazebo, on purpose: its ramp and steering comparisons mix speeds and angles
// (`diff < target_speed`), so a ramp may run the wrong way; here they go towards the target.
// Gazebo's encoder odometry turns the wrong way (yaw += (s_l - s_r) / b); here yaw grows with
// s_r - s_l. A command timeout (<cmdTimeout>, ours, 0 = never as in Gazebo) stops the wheel.
#pragma once

#include "conde_sim/timed_command.h"

namespace conde_sim {

struct TricycleParams {
  double actuated_wheel_diameter_m = 0.15;  // gazebo_ros_tricycle_drive defaults
  double wheel_acceleration_radps2 = 0.0;   // 0 = speed applied at once
  double wheel_deceleration_radps2 = 0.0;   // Gazebo: defaults to the acceleration
  double wheel_speed_tolerance_radps = 0.01;
  double steering_speed_radps = 0.0;  // 0 = steering set at once
  double steering_angle_tolerance_rad = 0.01;
  double command_timeout_s = 0.0;  // 0 = never
};

class TricycleController {
 public:
  explicit TricycleController(const TricycleParams& params) : params_(params) {}

  // Returns false, keeping the previous command, when a value is NaN or infinite.
  bool setCommand(double speed_mps, double steering_angle_rad, double time_s);
  bool timedOut(double time_s) const;
  void reset();

  // Joint speed [rad/s] to apply to the actuated wheel, turning at `current_radps` now.
  double wheelSpeed(double time_s, double current_radps, double dt_s) const;
  // Steering target [rad], held within +-pi/2.
  double steeringTarget() const;
  // With steeringSpeed > 0: the steering joint's speed [rad/s] at `current_rad`.
  double steeringSpeed(double current_rad) const;

 private:
  TricycleParams params_;
  TimedCommand command_;  // speed [m/s], steering angle [rad]
};

}  // namespace conde_sim
