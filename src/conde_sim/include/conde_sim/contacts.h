// The last physics step's contacts as gazebo_msgs/ContactsState, named as Gazebo names them:
// a robot's body "robot::link" (the body's root link; links fixed to it are merged into it), a
// world object by its name, the ground "ground_plane".
//
// Used by the /conde_sim/contacts topic (ContactsPublisher: robots against world objects and
// other robots, never the ground) and by libgazebo_ros_bumper.so (one link's contacts).
#pragma once

#include <gazebo_msgs/ContactsState.h>
#include <ros/ros.h>

#include <functional>
#include <string>

#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {

std::string contactName(const Simulation& sim, const Simulation::ContactOwner& owner);

using ContactFilter = std::function<bool(const Simulation::ContactOwner&)>;

// One ContactState per pair of bodies/objects in contact in the last step, with collision1 the
// side `first` accepts and collision2 the side `second` accepts (pairs matching neither way are
// left out; pairs matching both ways put the smaller name first). Normals point from collision2
// towards collision1; wrenches[i] is the contact force on collision1 at point i (torques are 0),
// total_wrench their sum. Positions, normals and forces in the frame `frame_in_world` (the world
// frame: identity). Contacts are per body: a link fixed to another one shares its body's.
void lastStepContacts(const Simulation& sim, const ContactFilter& first, const ContactFilter& second,
                      const conde_physics::Pose& frame_in_world, gazebo_msgs::ContactsState& out);

// Publishes `topic` (gazebo_msgs/ContactsState, frame "world"): every contact between a robot
// and a world object or another robot, at `rate_hz` in simulated time (0: every step), only
// while someone subscribes.
class ContactsPublisher : public StepHooks {
 public:
  ContactsPublisher(ros::NodeHandle& nh, const std::string& topic, Simulation& sim, double rate_hz);
  void afterStep() override;

 private:
  Simulation& sim_;
  UpdateTimer timer_;
  ros::Publisher pub_;
};

}  // namespace conde_sim
