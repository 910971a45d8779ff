// libgazebo_ros_planar_move.so: geometry_msgs/Twist on cmd_vel moves the whole model in the
// plane (linear.x, linear.y in the base frame, angular.z), with the parameter names and defaults
// of gazebo_ros_planar_move (ROS 1); no wheels are simulated.
//
//   <gazebo><plugin name="planar_move" filename="libgazebo_ros_planar_move.so">
//     <commandTopic>cmd_vel</commandTopic> <odometryTopic>odom</odometryTopic>
//     <odometryFrame>odom</odometryFrame> <odometryRate>20</odometryRate>
//     <robotBaseFrame>base_footprint</robotBaseFrame> <cmdTimeout>0.5</cmdTimeout>
//   </plugin></gazebo>
//
// As in Gazebo, every step sets the model's velocity to the command (vertical velocity 0, no roll
// or pitch rate), and odometry is the base frame's ground-truth pose in the world, named
// odometryFrame, with TF odom -> base. Differences: the odometry twist is the instantaneous
// velocity (Gazebo differentiates poses between messages), and <cmdTimeout> defaults to 0.5 s
// like our other drives (Gazebo: -1, never); a negative value never times out.
#include <geometry_msgs/Twist.h>

#include <cmath>

#include "conde_sim/drive_odometry.h"
#include "conde_sim/odometry_publisher.h"
#include "conde_sim/plugin.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class PlanarMovePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const std::string command_topic = params.getString("commandTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    base_link_ = requireLink(ctx_, params, "robotBaseFrame", params.getString("robotBaseFrame", "base_footprint"));
    const double rate_hz = params.getDouble("odometryRate", 20.0);
    if (rate_hz < 0) throw params.error("odometryRate", "must not be negative");
    publish_odometry_ = rate_hz > 0;  // Gazebo: 0 publishes no odometry
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    timeout_s_ = params.getDouble("cmdTimeout", 0.5);
    OdometryPublisher::Options odom;
    odom.odom_frame = ctx_.frame(params.getString("odometryFrame", "odom"));
    odom.base_frame = ctx_.frame(base_link_);
    odom.publish_world_to_odom_tf = false;  // the odom frame is the world, named odometryFrame
    params.ignore({"alwaysOn"});
    cmd_sub_ = nh.subscribe(command_topic, 1, &PlanarMovePlugin::onCommand, this);
    odometry_ = OdometryPublisher(ctx_, odom);
    odometry_.advertise(nh, odometry_topic);
    ROS_INFO("%s: planar move, command %s, odometry %s in %s -> %s at %.1f Hz, command timeout %.2f s",
             ctx_.sim->robot(ctx_.robot).spec.name.c_str(), cmd_sub_.getTopic().c_str(), odometry_.topic().c_str(),
             odom.odom_frame.c_str(), odom.base_frame.c_str(), rate_hz, timeout_s_);
  }

  void reset() override { command_ = geometry_msgs::Twist(); }

  void beforeStep() override {
    if (timeout_s_ >= 0 && ctx_.sim->timeS() - command_time_s_ > timeout_s_) command_ = geometry_msgs::Twist();
    const ModelRef model{ctx_.robot, -1};
    const cp::Pose root = ctx_.sim->linkPose(model, "");
    // Gazebo's planar_move: the command turned by the model's yaw, nothing vertical.
    const double yaw = root.orientation.yaw();
    const double c = std::cos(yaw), s = std::sin(yaw);
    cp::Twist twist;
    twist.linear_mps =
        cp::Vec3(command_.linear.x * c - command_.linear.y * s, command_.linear.y * c + command_.linear.x * s, 0.0);
    twist.angular_radps = cp::Vec3(0.0, 0.0, command_.angular.z);
    ctx_.sim->setModelState(model, root, twist);
  }

  void afterStep() override {
    if (!publish_odometry_ || !timer_.due(ctx_.sim->stepCount())) return;
    cp::Pose pose;
    cp::Twist twist;
    groundTruthOdometry(*ctx_.sim, ctx_.robot, base_link_, pose, twist);
    odometry_.publish(pose, twist);
  }

 private:
  void onCommand(const geometry_msgs::Twist::ConstPtr& msg) {
    if (!std::isfinite(msg->linear.x) || !std::isfinite(msg->linear.y) || !std::isfinite(msg->angular.z)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
                        cmd_sub_.getTopic().c_str());
      return;
    }
    command_ = *msg;
    command_time_s_ = ctx_.sim->timeS();
  }

  std::string base_link_;
  bool publish_odometry_ = true;
  double timeout_s_ = 0.5, command_time_s_ = 0.0;
  geometry_msgs::Twist command_;
  UpdateTimer timer_;
  ros::Subscriber cmd_sub_;
  OdometryPublisher odometry_;
};

}  // namespace

std::unique_ptr<SimPlugin> makePlanarMovePlugin() { return std::make_unique<PlanarMovePlugin>(); }

}  // namespace conde_sim
