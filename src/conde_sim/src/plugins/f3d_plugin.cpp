// libgazebo_ros_f3d.so: the force [N] and torque [N m] applied to a link during the last step
// (by libgazebo_ros_force.so or /gazebo/apply_body_wrench; not gravity or contacts, as Gazebo's
// Link::WorldForce), as geometry_msgs/WrenchStamped in world coordinates at every step while
// someone subscribes, with the parameter names of gazebo_ros_f3d (ROS 1).
//
//   <gazebo><plugin name="f3d" filename="libgazebo_ros_f3d.so">
//     <bodyName>base_link</bodyName> <topicName>force_feedback</topicName>
//     <frameName>world</frameName>   <!-- only the header's frame_id, as in Gazebo -->
//   </plugin></gazebo>
//
// The torque is about the centre of mass of the link's body. <bodyName> and <topicName> are
// required; <frameName> defaults to "world".
#include <geometry_msgs/WrenchStamped.h>

#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"

namespace conde_sim {
namespace {

class F3dPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    link_ = requireLink(ctx_, params, "bodyName", params.requireString("bodyName"));
    const std::string topic = params.requireString("topicName");
    frame_ = params.getString("frameName", "world");
    params.ignore({"alwaysOn", "updateRate"});  // Gazebo publishes at every step whatever they say
    pub_ = nh.advertise<geometry_msgs::WrenchStamped>(topic, 10);
    ROS_INFO("%s: applied wrench of link %s on %s in frame %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
             link_.c_str(), pub_.getTopic().c_str(), frame_.c_str());
  }

  void afterStep() override {
    if (pub_.getNumSubscribers() == 0) return;
    const cp::Twist wrench = ctx_.sim->lastAppliedWrench({ctx_.robot, -1}, link_);
    geometry_msgs::WrenchStamped msg;
    msg.header.stamp = ctx_.now();
    msg.header.frame_id = frame_;
    msg.wrench.force = toVector3Msg(wrench.linear_mps);
    msg.wrench.torque = toVector3Msg(wrench.angular_radps);
    pub_.publish(msg);
  }

 private:
  std::string link_, frame_;
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeF3dPlugin() { return std::make_unique<F3dPlugin>(); }

}  // namespace conde_sim
