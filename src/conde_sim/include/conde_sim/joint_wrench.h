// The force/torque a joint passes to its child link, as Gazebo's Joint::GetForceTorque reports it
// in body2Force / body2Torque (what libgazebo_ros_ft_sensor.so publishes). Free of ROS.
#pragma once

#include "conde_physics/physics_engine.h"

namespace conde_sim {

class Simulation;

// The wrench the joint exerted on its child link in the last step, in the child link's frame:
// force [N], and torque [N m] about the link frame's origin (the joint's origin, URDF convention).
conde_physics::JointWrench jointWrenchOnChild(const Simulation& sim, int robot, int joint);

}  // namespace conde_sim
