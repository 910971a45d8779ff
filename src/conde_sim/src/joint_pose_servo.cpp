#include "conde_sim/joint_pose_servo.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

double jointLoadInertia(const Simulation& sim, int robot, int joint) {
  const Robot& r = sim.robot(robot);
  const cp::ArticulatedModel& model = r.model;
  const cp::JointSpec& spec = model.joints.at(joint);
  // Bodies beyond the joint: its child and, repeatedly, the children of joints on them.
  std::vector<bool> moved(model.bodies.size(), false);
  moved.at(spec.child_body) = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (const cp::JointSpec& j : model.joints) {
      if (moved.at(j.parent_body) && !moved.at(j.child_body)) moved[j.child_body] = grew = true;
    }
  }
  const cp::Pose joint_frame = sim.engine().bodyPose(r.id, spec.parent_body) * spec.pose_in_parent;
  const cp::Vec3 axis = joint_frame.orientation.rotate(spec.axis).normalized();
  double load = 0.0;
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (!moved[b]) continue;
    const cp::BodySpec& body = model.bodies[b];
    if (spec.type == cp::JointType::kPrismatic) {
      load += body.mass_kg;
      continue;
    }
    const cp::Pose inertial = sim.engine().bodyPose(r.id, static_cast<int>(b)) * body.inertial_frame;
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

double poseServoSpeed(double error, double step_s, double max_deceleration) {
  double speed = std::abs(error) / step_s;
  if (max_deceleration > 0.0) speed = std::min(speed, std::sqrt(2.0 * max_deceleration * std::abs(error)));
  return std::copysign(speed, error);
}

}  // namespace conde_sim
