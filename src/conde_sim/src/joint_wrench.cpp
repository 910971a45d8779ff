#include "conde_sim/joint_wrench.h"

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

cp::JointWrench jointWrenchOnChild(const Simulation& sim, int robot, int joint) {
  const Robot& r = sim.robot(robot);
  const int child = r.model.joints.at(joint).child_body;
  const cp::JointWrench world = sim.engine().jointWrench(r.id, joint);  // torque about the centre of mass
  const cp::Pose link = sim.engine().bodyPose(r.id, child);
  const cp::Vec3 centre_of_mass = link * r.model.bodies.at(child).inertial_frame.position;
  // Moment about the link origin: the same force acting at the centre of mass.
  const cp::Vec3 torque_about_origin = world.torque_Nm + (centre_of_mass - link.position).cross(world.force_N);
  const cp::Quat to_link = link.orientation.conjugate();
  return cp::JointWrench{to_link.rotate(world.force_N), to_link.rotate(torque_about_origin)};
}

}  // namespace conde_sim
