// libgazebo_ros_bumper.so: gazebo_msgs/ContactsState of one link's contacts (a contact sensor).
//
//   <gazebo reference="base_link"><sensor name="bumper" type="contact">
//     <always_on>true</always_on> <update_rate>20</update_rate>
//     <contact><collision>base_link_collision</collision></contact>
//     <plugin name="bumper_plugin" filename="libgazebo_ros_bumper.so">
//       <bumperTopicName>bumper</bumperTopicName> <frameName>world</frameName>
//     </plugin></sensor></gazebo>
// Reports the contacts of the last physics step between the link's body and anything else (the
// ground, world objects, other robots), one ContactState per touching pair with the link's body
// as collision1 ("robot::link") and the other side as collision2 (object name, "ground_plane",
// "robot::link"); an empty list when nothing touches. Published at update_rate in simulated time
// (0: every step) whether or not something touches, as Gazebo does. Positions, normals and
// forces are in the frame of the link `frameName` when the robot has it, else in the world.
// Contacts are per body: <contact><collision> is read but every collision of the link's body
// (links fixed to it included) counts.
#include <gazebo_msgs/ContactsState.h>

#include "conde_sim/contacts.h"
#include "conde_sim/plugin.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class BumperPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    link_ = params.requireSensor({"contact"});
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    body_ = -1;
    for (size_t b = 0; b < robot.model.bodies.size() && body_ < 0; ++b) {
      for (const std::string& merged : robot.model.bodies[b].merged_links)
        if (merged == link_) body_ = static_cast<int>(b);
    }
    if (body_ < 0) throw params.error("sensor", "link '" + link_ + "' has no body (it has no mass or collision)");
    const std::string topic = params.getString("bumperTopicName", "bumper_states");
    frame_link_ = params.getString("frameName", "world");
    frame_in_robot_ = ctx_.sim->hasLink(ModelRef{ctx_.robot, -1}, frame_link_);
    const double rate_hz = params.sensorDouble("update_rate", 0.0);
    if (rate_hz < 0) throw params.sensorError("update_rate", "must not be negative");
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    collision_ = params.sensorString("contact/collision", "");
    params.sensorBool("always_on", true);
    params.ignore({"visualize", "pose", "topic", "contact/topic", "robotNamespace", "alwaysOn", "updateRate"});
    pub_ = nh.advertise<gazebo_msgs::ContactsState>(topic, 10);
    ROS_INFO("%s: bumper on link %s (collision '%s') publishing %s in frame %s at %.1f Hz", robot.spec.name.c_str(),
             link_.c_str(), collision_.c_str(), pub_.getTopic().c_str(), frame_link_.c_str(), rate_hz);
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    const int robot = ctx_.robot, body = body_;
    const cp::Pose frame = frame_in_robot_ ? ctx_.sim->linkPose(robot, frame_link_) : cp::Pose();
    gazebo_msgs::ContactsState msg;
    msg.header.stamp = ctx_.now();
    msg.header.frame_id = frame_in_robot_ ? ctx_.frame(frame_link_) : frame_link_;
    lastStepContacts(
        *ctx_.sim, [robot, body](const Simulation::ContactOwner& o) { return o.robot == robot && o.body == body; },
        [robot, body](const Simulation::ContactOwner& o) { return !(o.robot == robot && o.body == body); }, frame, msg);
    pub_.publish(msg);
  }

 private:
  std::string link_, frame_link_, collision_;
  int body_ = -1;
  bool frame_in_robot_ = false;
  UpdateTimer timer_;
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeBumperPlugin() { return std::make_unique<BumperPlugin>(); }

}  // namespace conde_sim
