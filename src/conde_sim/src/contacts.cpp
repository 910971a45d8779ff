#include "conde_sim/contacts.h"

#include <map>
#include <utility>

namespace conde_sim {

namespace cp = conde_physics;

std::string contactName(const Simulation& sim, const Simulation::ContactOwner& owner) {
  if (owner.robot >= 0) {
    const Robot& robot = sim.robot(owner.robot);
    const auto& bodies = robot.model.bodies;
    const std::string link = owner.body >= 0 && owner.body < static_cast<int>(bodies.size())
                                 ? bodies[owner.body].name
                                 : std::to_string(owner.body);
    return robot.spec.name + "::" + link;
  }
  if (owner.object >= 0) return sim.world().objects.at(owner.object).name;
  return "ground_plane";
}

namespace {

geometry_msgs::Vector3 vec(const cp::Vec3& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x;
  m.y = v.y;
  m.z = v.z;
  return m;
}

}  // namespace

void lastStepContacts(const Simulation& sim, const ContactFilter& first, const ContactFilter& second,
                      const cp::Pose& frame_in_world, gazebo_msgs::ContactsState& out) {
  out.states.clear();
  const cp::Pose to_frame = frame_in_world.inverse();
  std::map<std::pair<std::string, std::string>, size_t> state_of_pair;  // names -> index in out.states
  for (const cp::Contact& c : sim.engine().lastContacts()) {
    const Simulation::ContactOwner a = sim.contactOwner(c.a), b = sim.contactOwner(c.b);
    const bool ab = first(a) && second(b), ba = first(b) && second(a);
    if (!ab && !ba) continue;
    std::string name1 = contactName(sim, a), name2 = contactName(sim, b);
    double sign = 1.0;                   // +1: collision1 is side a
    if (!ab || (ba && name2 < name1)) {  // either way round: the smaller name first, every step
      sign = -1.0;
      std::swap(name1, name2);
    }
    auto it = state_of_pair.find({name1, name2});
    if (it == state_of_pair.end()) {
      it = state_of_pair.emplace(std::make_pair(name1, name2), out.states.size()).first;
      gazebo_msgs::ContactState state;
      state.collision1_name = name1;
      state.collision2_name = name2;
      state.info = "Debug:  i:(0/1)     my geom:" + name1 + "   other geom:" + name2;
      out.states.push_back(state);
    }
    gazebo_msgs::ContactState& state = out.states[it->second];
    const cp::Vec3 position = to_frame * c.position_m;
    const cp::Vec3 normal = to_frame.orientation.rotate(c.normal * sign);
    const cp::Vec3 force = c.has_force ? to_frame.orientation.rotate(c.force_on_a_N * sign) : cp::Vec3();
    geometry_msgs::Vector3 p = vec(position);
    geometry_msgs::Vector3 n = vec(normal);
    state.contact_positions.push_back(p);
    state.contact_normals.push_back(n);
    state.depths.push_back(c.depth_m);
    geometry_msgs::Wrench w;
    w.force = vec(force);
    state.wrenches.push_back(w);
    state.total_wrench.force.x += force.x;
    state.total_wrench.force.y += force.y;
    state.total_wrench.force.z += force.z;
  }
}

ContactsPublisher::ContactsPublisher(ros::NodeHandle& nh, const std::string& topic, Simulation& sim, double rate_hz)
    : sim_(sim), timer_(rate_hz, sim.stepS()) {
  pub_ = nh.advertise<gazebo_msgs::ContactsState>(topic, 10);
}

void ContactsPublisher::afterStep() {
  if (!timer_.due(sim_.stepCount()) || pub_.getNumSubscribers() == 0) return;
  gazebo_msgs::ContactsState msg;
  msg.header.stamp = ros::Time(sim_.timeS());
  msg.header.frame_id = "world";
  lastStepContacts(
      sim_, [](const Simulation::ContactOwner& o) { return o.robot >= 0; },
      [](const Simulation::ContactOwner& o) { return !o.ground(); }, cp::Pose(), msg);
  pub_.publish(msg);
}

}  // namespace conde_sim
