// The Ackermann drive on a simulated car, minus ROS: commands in (AckermannDrive fields or a
// Twist), PID effort control of the two steering hinges (position) and of the driven wheels
// (speed) at every physics step, odometry (from the rear wheels and the steering angles, or
// ground truth) at the update rate. The plugin (plugins/ackermann_drive_plugin.cpp) reads the
// parameters and adds topics, TF and joint states around it; tests step it directly.
//
// Differences from what Gazebo users had (gazebo_ros and ros_controllers): Twist angular.z is
// a yaw rate (ros_controllers' ackermann_steering_controller uses it as an angle); the four
// wheels get their own speeds (differential) and the front wheels their own angles (Ackermann);
// a command timeout brakes; NaN/inf commands are rejected; encoder odometry keeps the sign of
// the speed when reversing.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "conde_physics/math.h"
#include "conde_sim/ackermann_geometry.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {

class Simulation;
struct Robot;

// A configuration the robot cannot carry out; `key` is the plugin parameter at fault.
class AckermannConfigError : public std::invalid_argument {
 public:
  AckermannConfigError(std::string key, const std::string& what) : std::invalid_argument(what), key(std::move(key)) {}
  std::string key;
};

// Dead reckoning of the rear-axle centre from its travelled distance and the steering angle
// (exact arc integration between updates), reported for the base frame, which sits at a fixed
// offset from the rear-axle centre.
class AckermannOdometry {
 public:
  // `axle_in_base`: the rear-axle centre in the base frame (x, y) [m].
  AckermannOdometry(double wheelbase_m, double axle_x_in_base_m, double axle_y_in_base_m)
      : wheelbase_m_(wheelbase_m), axle_x_m_(axle_x_in_base_m), axle_y_m_(axle_y_in_base_m) {}

  // Puts the base frame at the origin of the odometry frame.
  void reset();
  // `distance_m`: signed distance the rear-axle centre rolled since the last update;
  // `steering_rad`: centre steering angle over that distance.
  void update(double distance_m, double steering_rad, double dt_s);

  // Pose of the base frame in the odometry frame, and its twist in the base frame.
  double x_m() const;
  double y_m() const;
  double yaw_rad() const { return yaw_rad_; }
  double linear_x_mps() const { return speed_mps_ + yaw_rate_radps_ * axle_y_m_; }
  double linear_y_mps() const { return -yaw_rate_radps_ * axle_x_m_; }
  double angular_radps() const { return yaw_rate_radps_; }

 private:
  double wheelbase_m_, axle_x_m_, axle_y_m_;
  double axle_x_odom_m_ = 0.0, axle_y_odom_m_ = 0.0, yaw_rad_ = 0.0;  // rear-axle centre in odom
  double speed_mps_ = 0.0, yaw_rate_radps_ = 0.0;
};

class AckermannDrive {
 public:
  struct Config {
    std::string left_steering_joint, right_steering_joint;
    std::string left_rear_wheel_joint, right_rear_wheel_joint;
    std::string left_front_wheel_joint, right_front_wheel_joint;  // "" = the car has none to drive
    bool drive_front = false, drive_rear = true;
    std::string base_link = "base_footprint";
    // Zeros are taken from the URDF: wheelbase from the steering and rear wheel joints, half
    // tracks from the joints' y, wheel radius from the rear wheel's cylinder collision.
    AckermannGeometry geometry;
    double max_steering_angle_rad = 0.0;  // centre angle; 0 = what the hinges' limits allow
    // Effort PIDs, tuned for a 1/10-scale car (about 4 kg, 0.05 m wheels, steering knuckle +
    // wheel about 1.3e-4 kg m^2 about the hinge) at a 1 ms step. Explicit effort control is
    // stable while p * step < ~2 I (wheel: I = its spin inertia) and d * step < ~2 I (steering).
    PidController::Gains wheel_pid{0.1, 2.0, 0.0, 1.0, 1.0};         // [N m per rad/s]; clamp, limit [N m]
    PidController::Gains steering_pid{100.0, 100.0, 0.2, 0.1, 5.0};  // [N m per rad]; clamp, limit [N m]
    double command_timeout_s = 0.5;                                  // 0 = never
    double update_rate_hz = 50.0;                                    // odometry
    bool encoder_odometry = false;                                   // false: ground truth ("world")

    // The defaults with the six joints named after their place: left_steering_joint,
    // right_steering_joint, {left,right}_{front,rear}_wheel_joint (the F1/10 racecar and the
    // test car of the gtests use these names).
    static Config placeNamedJoints();
  };

  // Throws AckermannConfigError naming the plugin parameter at fault (unknown joint or link,
  // a steering axis that is not vertical, a wheel axis that is not lateral, bad geometry).
  AckermannDrive(Simulation& sim, int robot, const Config& config);

  // AckermannDrive fields: speed [m/s] of the rear-axle centre, centre steering angle [rad],
  // rate limits [rad/s], [m/s^2] (0 = none). False (command ignored) for a NaN or infinity.
  bool commandDrive(double speed_mps, double steering_angle_rad, double steering_angle_velocity_radps = 0.0,
                    double acceleration_mps2 = 0.0);
  // geometry_msgs/Twist: linear.x [m/s], angular.z a yaw rate [rad/s] (see steeringAngleForYawRate).
  bool commandTwist(double linear_mps, double yaw_rate_radps);
  bool timedOut() const;
  void reset();
  void beforeStep();  // every physics step: the PIDs
  bool afterStep();   // true when the odometry was updated (at the update rate)

  const Config& config() const { return config_; }
  const AckermannGeometry& geometry() const { return config_.geometry; }
  double maxSteeringAngle() const { return config_.max_steering_angle_rad; }
  // Current (rate-limited) set points.
  double steeringSetpoint() const { return steering_rad_; }
  double speedSetpoint() const { return speed_mps_; }
  FrontWheelAngles steeringTargets() const { return frontWheelAngles(config_.geometry, steering_rad_); }
  FrontWheelAngles measuredSteering() const;

  const conde_physics::Pose& odomPose() const { return odom_pose_; }     // base frame in odom
  const conde_physics::Twist& odomTwist() const { return odom_twist_; }  // in the base frame
  const conde_physics::Pose& startPose() const { return start_pose_; }
  bool encoderOdometry() const { return config_.encoder_odometry; }
  // Joint indices: steering left/right, then wheels fl, fr, rl, rr (-1 where absent).
  int joint(int which) const { return joints_[which]; }
  enum { kSteerLeft, kSteerRight, kFrontLeft, kFrontRight, kRearLeft, kRearRight, kJointCount };

 private:
  double rearWheelAngle() const;
  double jointPosition(int which) const;  // [rad], + = left / rolling forward
  double jointVelocity(int which) const;

  Simulation& sim_;
  int robot_;
  Config config_;
  int joints_[kJointCount] = {-1, -1, -1, -1, -1, -1};
  double signs_[kJointCount] = {1, 1, 1, 1, 1, 1};  // joint direction -> car convention
  PidController steering_pid_[2], wheel_pid_[4];
  UpdateTimer timer_;
  std::uint64_t last_update_step_ = 0;
  // Command and set points.
  double target_speed_mps_ = 0.0, target_steering_rad_ = 0.0;
  double steering_rate_limit_ = 0.0, acceleration_limit_ = 0.0;
  double speed_mps_ = 0.0, steering_rad_ = 0.0;
  double command_time_s_ = 0.0;
  bool has_command_ = false;
  // Odometry.
  AckermannOdometry odometry_;
  double last_rear_angle_rad_ = 0.0, last_steering_rad_ = 0.0;
  conde_physics::Pose odom_pose_, start_pose_;
  conde_physics::Twist odom_twist_;
};

// Geometry of a car from its URDF: wheelbase (x distance of the steering joints' midpoint from
// the rear wheel joints' midpoint, in `base_link`), half tracks (half the joints' y distances)
// and the rear wheels' radius (their cylinder collision; 0 when they have none). Also the
// rear-axle centre in `base_link`. Throws AckermannConfigError for an unknown joint or link.
struct MeasuredCarGeometry {
  AckermannGeometry geometry;
  double axle_x_in_base_m = 0.0, axle_y_in_base_m = 0.0;
  double steering_lower_rad = 0.0, steering_upper_rad = 0.0;  // tightest of both hinges
  bool steering_has_limits = false;
};
MeasuredCarGeometry measureCarGeometry(const Robot& robot, const std::string& base_link,
                                       const std::string& left_steering_joint, const std::string& right_steering_joint,
                                       const std::string& left_rear_wheel_joint,
                                       const std::string& right_rear_wheel_joint);

}  // namespace conde_sim
