// Drives joints to positions with velocity motors whose effort and speed are limited, free of
// ROS (the joint pose trajectory plugin sets poses with it).
//
// A motor asked for (target - position) / step reaches the target in one step only if its effort
// can stop the joint within that step; otherwise it swings past and never settles. The speed
// asked for is therefore also held to sqrt(2 a |error|), the speed from which the motor's
// deceleration a = effort / inertia stops the joint at the target, and to the joint's URDF
// velocity limit.
//
// Usage:
//   JointPoseServo servo(sim, robot, {sim.robot(robot).model.jointIndex("elbow_joint")});
//   every step: servo.drive(sim, {0.5}); sim step
#pragma once

#include <vector>

namespace conde_physics {
struct ArticulatedModel;
}

namespace conde_sim {

class Simulation;

// Bodies a joint moves: its child and, repeatedly, the children of joints on them.
std::vector<int> bodiesMovedBy(const conde_physics::ArticulatedModel& model, int joint);

// Inertia [kg m^2] about a revolute joint's axis (mass [kg] for a prismatic joint) of
// `moved_bodies` (bodiesMovedBy) at their current poses. Coupling through the joints beyond is
// ignored.
double jointLoadInertia(const Simulation& sim, int robot, int joint, const std::vector<int>& moved_bodies);

// Joint speed [rad/s or m/s] to ask of the motor for `error` [rad or m] = target - position, with
// steps of `step_s` [s], a deceleration of at most `max_deceleration` [rad/s^2 or m/s^2] (0 = no
// limit) and a speed of at most `max_speed` [rad/s or m/s] (0 = no limit).
double poseServoSpeed(double error, double step_s, double max_deceleration, double max_speed = 0.0);

class JointPoseServo {
 public:
  // Motor effort [N m or N] of a joint without an effort limit in the URDF.
  static constexpr double kUnlimitedEffort = 1e3;

  // `joints`: indices into the robot model's joints. What each joint moves is found here, once.
  JointPoseServo(const Simulation& sim, int robot, std::vector<int> joints);

  // Sets, for the next step, each joint's motor towards its target [rad or m] (same order as
  // the joints given), within the joint's URDF effort and velocity limits.
  void drive(Simulation& sim, const std::vector<double>& targets) const;

  const std::vector<int>& joints() const { return joints_; }

 private:
  int robot_;
  std::vector<int> joints_;
  std::vector<std::vector<int>> moved_bodies_;  // per joint
};

}  // namespace conde_sim
