#include "conde_sim/joint_pose_servo.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

std::vector<int> bodiesMovedBy(const cp::ArticulatedModel& model, int joint) {
  std::vector<bool> moved(model.bodies.size(), false);
  moved.at(model.joints.at(joint).child_body) = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (const cp::JointSpec& j : model.joints) {
      if (moved.at(j.parent_body) && !moved.at(j.child_body)) moved[j.child_body] = grew = true;
    }
  }
  std::vector<int> bodies;
  for (size_t b = 0; b < moved.size(); ++b) {
    if (moved[b]) bodies.push_back(static_cast<int>(b));
  }
  return bodies;
}

double jointLoadInertia(const Simulation& sim, int robot, int joint, const std::vector<int>& moved_bodies) {
  const Robot& r = sim.robot(robot);
  const cp::ArticulatedModel& model = r.model;
  const cp::JointSpec& spec = model.joints.at(joint);
  const cp::Pose joint_frame = sim.engine().bodyPose(r.id, spec.parent_body) * spec.pose_in_parent;
  const cp::Vec3 axis = joint_frame.orientation.rotate(spec.axis).normalized();
  double load = 0.0;
  for (int b : moved_bodies) {
    const cp::BodySpec& body = model.bodies.at(b);
    if (spec.type == cp::JointType::kPrismatic) {
      load += body.mass_kg;
      continue;
    }
    const cp::Pose inertial = sim.engine().bodyPose(r.id, b) * body.inertial_frame;
    const cp::Vec3 arm = inertial.position - joint_frame.position;
    const double along = arm.dot(axis);
    load += body.mass_kg * std::max(0.0, arm.dot(arm) - along * along);  // parallel axis
    // The principal inertias projected on the axis.
    const cp::Vec3 local_axis = inertial.orientation.conjugate().rotate(axis);
    const cp::Vec3& i = body.principal_inertia_kgm2;
    load += i.x * local_axis.x * local_axis.x + i.y * local_axis.y * local_axis.y + i.z * local_axis.z * local_axis.z;
  }
  return load;
}

double poseServoSpeed(double error, double step_s, double max_deceleration, double max_speed) {
  double speed = std::abs(error) / step_s;
  if (max_deceleration > 0.0) speed = std::min(speed, std::sqrt(2.0 * max_deceleration * std::abs(error)));
  if (max_speed > 0.0) speed = std::min(speed, max_speed);
  return std::copysign(speed, error);
}

JointPoseServo::JointPoseServo(const Simulation& sim, int robot, std::vector<int> joints)
    : robot_(robot), joints_(std::move(joints)) {
  for (int joint : joints_) moved_bodies_.push_back(bodiesMovedBy(sim.robot(robot_).model, joint));
}

void JointPoseServo::drive(Simulation& sim, const std::vector<double>& targets) const {
  cp::PhysicsEngine& engine = sim.engine();
  const Robot& r = sim.robot(robot_);
  for (size_t j = 0; j < joints_.size() && j < targets.size(); ++j) {
    const cp::JointSpec& spec = r.model.joints[joints_[j]];
    const double max_effort = spec.effort_limit > 0.0 ? spec.effort_limit : kUnlimitedEffort;
    const double inertia = jointLoadInertia(sim, robot_, joints_[j], moved_bodies_[j]);
    // Half the deceleration the motor could give: the joints beyond pull on it too.
    const double deceleration = inertia > 0.0 ? 0.5 * max_effort / inertia : 0.0;
    const double error = targets[j] - engine.jointPosition(r.id, joints_[j]);
    engine.setJointVelocityMotor(r.id, joints_[j],
                                 poseServoSpeed(error, sim.stepS(), deceleration, spec.velocity_limit), max_effort);
  }
}

}  // namespace conde_sim
