// libgazebo_ros_force.so: a geometry_msgs/Wrench on <topicName> is applied to a link at every
// step until the next message replaces it, as gazebo_ros_force (ROS 1) does: force [N] and
// torque [N m] in world coordinates, the force at the centre of mass of the link's body.
//
//   <gazebo><plugin name="push" filename="libgazebo_ros_force.so">
//     <bodyName>base_link</bodyName> <topicName>force</topicName>
//   </plugin></gazebo>
//
// Both keys are required, as in Gazebo. A world reset clears the wrench.
#include <geometry_msgs/Wrench.h>

#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"

namespace conde_sim {
namespace {

class ForcePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    link_ = requireLink(ctx_, params, "bodyName", params.requireString("bodyName"));
    params.ignore({"alwaysOn", "updateRate"});
    sub_ = nh.subscribe(params.requireString("topicName"), 1, &ForcePlugin::onWrench, this);
    ROS_INFO("%s: force on link %s from %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(), link_.c_str(),
             sub_.getTopic().c_str());
  }

  void reset() override { force_N_ = torque_Nm_ = cp::Vec3(); }

  void beforeStep() override {
    if (force_N_.x == 0 && force_N_.y == 0 && force_N_.z == 0 && torque_Nm_.x == 0 && torque_Nm_.y == 0 &&
        torque_Nm_.z == 0) {
      return;
    }
    ctx_.sim->addLinkWrenchAtCentreOfMass({ctx_.robot, -1}, link_, force_N_, torque_Nm_);
  }

 private:
  void onWrench(const geometry_msgs::Wrench::ConstPtr& msg) {
    if (!finite(msg->force) || !finite(msg->torque)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite wrench on %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
                        sub_.getTopic().c_str());
      return;
    }
    force_N_ = fromMsg(msg->force);
    torque_Nm_ = fromMsg(msg->torque);
  }

  std::string link_;
  cp::Vec3 force_N_, torque_Nm_;
  ros::Subscriber sub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeForcePlugin() { return std::make_unique<ForcePlugin>(); }

}  // namespace conde_sim
