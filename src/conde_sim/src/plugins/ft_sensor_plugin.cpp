// libgazebo_ros_ft_sensor.so: the force and torque a joint passes to its child link, as
// geometry_msgs/WrenchStamped, with the keys of gazebo_ros_ft_sensor (ROS 1).
//
//   <gazebo><plugin name="ft_sensor" filename="libgazebo_ros_ft_sensor.so">
//     <jointName>wrist_joint</jointName> <topicName>ft_sensor_topic</topicName>
//     <updateRate>100</updateRate> <gaussianNoise>0.0</gaussianNoise>
//   </plugin></gazebo>
//
// As Gazebo: frame_id = the child link; force [N] on the child, torque [N m] about the joint's
// origin, both in the child link's frame (Gazebo's body2Force / body2Torque, "child_to_parent");
// published only while someone subscribes; gaussianNoise is the stddev added to each of the six
// values. The wrench is the joint constraint's (limits and motor included) measured by the engine
// in the last step. Fixed joints are merged into one body here (as Gazebo lumps them), so the
// sensed joint must be a movable one (jointName is an error otherwise).
#include <geometry_msgs/WrenchStamped.h>

#include "conde_sim/gaussian_noise.h"
#include "conde_sim/joint_wrench.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class FtSensorPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    if (!params.has("jointName")) throw params.error("jointName", "required parameter is missing");
    if (!params.has("topicName")) throw params.error("topicName", "required parameter is missing");
    const std::string joint_name = params.getString("jointName", "");
    joint_ = requireJoint(ctx_, params, "jointName", joint_name);
    const std::string topic = params.getString("topicName", "");
    const double noise = params.getDouble("gaussianNoise", 0.0);
    if (noise < 0) throw params.error("gaussianNoise", "must not be negative");
    noise_ = GaussianNoise(noise, ctx_.noiseSeed(joint_name + "/ft_sensor"));
    const double rate_hz = params.getDouble("updateRate", 0.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    params.ignore({"alwaysOn"});
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    msg_.header.frame_id = ctx_.frame(robot.model.bodies.at(robot.model.joints.at(joint_).child_body).name);
    pub_ = nh.advertise<geometry_msgs::WrenchStamped>(topic, 10);
    ROS_INFO("%s: force/torque of joint %s in %s on %s, %.1f Hz, noise %.4g", robot.spec.name.c_str(),
             joint_name.c_str(), msg_.header.frame_id.c_str(), pub_.getTopic().c_str(), rate_hz, noise);
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    const conde_physics::JointWrench w = jointWrenchOnChild(*ctx_.sim, ctx_.robot, joint_);
    msg_.header.stamp = ctx_.now();
    msg_.wrench.force = toVector3Msg(w.force_N + noiseVector());
    msg_.wrench.torque = toVector3Msg(w.torque_Nm + noiseVector());
    pub_.publish(msg_);
  }

 private:
  conde_physics::Vec3 noiseVector() {  // draws in x, y, z order (the same in every run)
    const double x = noise_();
    const double y = noise_();
    return conde_physics::Vec3(x, y, noise_());
  }

  int joint_ = -1;
  GaussianNoise noise_;
  UpdateTimer timer_;
  ros::Publisher pub_;
  geometry_msgs::WrenchStamped msg_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeFtSensorPlugin() { return std::make_unique<FtSensorPlugin>(); }

}  // namespace conde_sim
