// ros_control-style joint controllers on a simulated joint, free of ROS (the
// libgazebo_ros_control.so plugin reads their YAML and gives each a `command` topic).
//
// What each type does with its command (as ros_controllers + gazebo_ros_control's
// DefaultRobotHWSim do it):
//   effort_controllers/JointPositionController  command [rad or m]; effort = PID(target - position),
//       derivative from the change of the error; the target is held within the joint's limits.
//   effort_controllers/JointVelocityController  command [rad/s or m/s]; effort = PID(target - velocity).
//   effort_controllers/JointEffortController    command [N m or N], applied as it is.
//   velocity_controllers/JointVelocityController  command [rad/s]: a velocity motor with the
//       joint's effort limit (DefaultRobotHWSim's SetVelocity).
//   position_controllers/JointPositionController  command [rad]: a velocity motor that reaches the
//       target in one step if the joint's effort and velocity limits allow (DefaultRobotHWSim sets
//       the position directly, which a dynamic engine cannot do).
// Efforts are clamped to the URDF effort limit and velocities to the velocity limit, as ros_control's
// joint limits interface does in DefaultRobotHWSim. PID gains follow control_toolbox::Pid (p, i, d,
// i_clamp), with the integral itself held within the clamp (control_toolbox's `antiwindup: true`).
#pragma once

#include <string>

#include "conde_sim/ackermann_geometry.h"

namespace conde_sim {

class Simulation;

enum class JointControllerType {
  kEffortPosition,  // effort_controllers/JointPositionController
  kEffortVelocity,  // effort_controllers/JointVelocityController
  kEffort,          // effort_controllers/JointEffortController
  kVelocity,        // velocity_controllers/JointVelocityController
  kPosition,        // position_controllers/JointPositionController
};

// The ros_control type name of each type, and the reverse (false for an unsupported name).
const char* jointControllerTypeName(JointControllerType type);
bool parseJointControllerType(const std::string& name, JointControllerType& type);
// True for types that need PID gains (`pid:` in the YAML).
bool jointControllerUsesPid(JointControllerType type);

class JointController {
 public:
  // `joint`: index of a movable joint of the robot (checked by the caller).
  JointController(Simulation& sim, int robot, int joint, JointControllerType type, const PidController::Gains& pid);

  // NaN or infinity: false, the command is ignored.
  bool setCommand(double command);
  double command() const { return command_; }
  // Runs the control law over `dt_s` and keeps its output for apply().
  void update(double dt_s);
  // Applies the output for the coming physics step (efforts last one step only).
  void apply();
  // Emergency stop (gazebo_ros_control's eStopTopic): no effort, velocity 0, position held.
  void setStopped(bool stopped);
  void reset();

  JointControllerType type() const { return type_; }
  int joint() const { return joint_; }
  double effort() const { return effort_; }  // last effort output [N m or N] (0 for motor types)

 private:
  Simulation& sim_;
  int robot_, joint_;
  JointControllerType type_;
  PidController pid_;
  double command_ = 0.0, effort_ = 0.0, motor_velocity_ = 0.0;
  double effort_limit_ = 0.0, velocity_limit_ = 0.0, lower_ = 0.0, upper_ = 0.0;
  bool has_limits_ = false, continuous_ = false, stopped_ = false;
  double held_position_ = 0.0;
};

}  // namespace conde_sim
