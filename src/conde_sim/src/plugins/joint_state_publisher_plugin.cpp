// libgazebo_ros_joint_state_publisher.so: sensor_msgs/JointState of the listed joints.
//
//   <gazebo><plugin name="joint_state_publisher" filename="libgazebo_ros_joint_state_publisher.so">
//     <jointName>left_wheel_joint, right_wheel_joint</jointName> <updateRate>50</updateRate>
//   </plugin></gazebo>
// Publishes on <namespace>/joint_states; effort is not measured and left empty.
#include <sensor_msgs/JointState.h>

#include "conde_sim/plugin.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class JointStatePublisherPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const std::vector<std::string> names = params.getList("jointName");
    if (names.empty()) throw params.error("jointName", "required parameter is missing");
    for (const auto& name : names) joints_.push_back(requireJoint(ctx_, params, "jointName", name));
    const double rate_hz = params.getDouble("updateRate", 100.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    params.ignore({"alwaysOn"});
    pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
    msg_.name = names;
    msg_.position.resize(names.size());
    msg_.velocity.resize(names.size());
    ROS_INFO("%s: joint states of %zu joints on %s at %.1f Hz", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
             names.size(), pub_.getTopic().c_str(), rate_hz);
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount())) return;
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    const conde_physics::PhysicsEngine& e = ctx_.sim->engine();
    msg_.header.stamp = ctx_.now();
    for (size_t i = 0; i < joints_.size(); ++i) {
      msg_.position[i] = e.jointPosition(robot.id, joints_[i]);
      msg_.velocity[i] = e.jointVelocity(robot.id, joints_[i]);
    }
    pub_.publish(msg_);
  }

 private:
  std::vector<int> joints_;
  UpdateTimer timer_;
  ros::Publisher pub_;
  sensor_msgs::JointState msg_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeJointStatePublisherPlugin() { return std::make_unique<JointStatePublisherPlugin>(); }

}  // namespace conde_sim
