// libgazebo_ros_skid_steer_drive.so: four driven wheels, two per side, with the parameter names
// and defaults of gazebo_ros_skid_steer_drive (ROS 1). The wheels of a side turn at the same
// speed, as a differential drive's (the DiffDrive of diff_drive_controller.h drives them).
//
//   <gazebo><plugin name="skid_steer" filename="libgazebo_ros_skid_steer_drive.so">
//     <leftFrontJoint>front_left_wheel_joint</leftFrontJoint> <rightFrontJoint>...</rightFrontJoint>
//     <leftRearJoint>rear_left_wheel_joint</leftRearJoint>    <rightRearJoint>...</rightRearJoint>
//     <wheelSeparation>0.4</wheelSeparation> <wheelDiameter>0.15</wheelDiameter> <torque>5</torque>
//     <updateRate>100</updateRate> <commandTopic>cmd_vel</commandTopic>
//     <odometryTopic>odom</odometryTopic> <odometryFrame>odom</odometryFrame>
//     <robotBaseFrame>base_footprint</robotBaseFrame> <broadcastTF>false</broadcastTF>
//     <covariance_x>0.0001</covariance_x> <covariance_y>0.0001</covariance_y>
//     <covariance_yaw>0.01</covariance_yaw>
//   </plugin></gazebo>
//
// Odometry is the base frame's ground-truth pose in the world, named odomFrame (as Gazebo's);
// TF odom -> base only with <broadcastTF>. Extension: <cmdTimeout> [s] (default 0.5, 0 = never)
// brakes the wheels when commands stop (Gazebo keeps the last command forever).
#include <geometry_msgs/Twist.h>

#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/odometry_publisher.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

class SkidSteerDrivePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    DiffDrive::Config c;
    c.left_joint = params.getString("leftFrontJoint", "left_front_joint");
    c.right_joint = params.getString("rightFrontJoint", "right_front_joint");
    c.more_left_joints = {params.getString("leftRearJoint", "left_rear_joint")};
    c.more_right_joints = {params.getString("rightRearJoint", "right_rear_joint")};
    requireJoint(ctx_, params, "leftFrontJoint", c.left_joint);
    requireJoint(ctx_, params, "rightFrontJoint", c.right_joint);
    requireJoint(ctx_, params, "leftRearJoint", c.more_left_joints[0]);
    requireJoint(ctx_, params, "rightRearJoint", c.more_right_joints[0]);
    DiffDriveParams& p = c.params;
    p.wheel_separation_m = params.getDouble("wheelSeparation", 0.4);
    p.wheel_diameter_m = params.getDouble("wheelDiameter", 0.15);
    p.command_timeout_s = params.getDouble("cmdTimeout", p.command_timeout_s);
    if (p.wheel_separation_m <= 0) throw params.error("wheelSeparation", "must be positive");
    if (p.wheel_diameter_m <= 0) throw params.error("wheelDiameter", "must be positive");
    if (p.command_timeout_s < 0) throw params.error("cmdTimeout", "must not be negative");
    c.wheel_torque_nm = params.getDouble("torque", 5.0);
    if (c.wheel_torque_nm <= 0) throw params.error("torque", "must be positive");
    c.update_rate_hz = params.getDouble("updateRate", 100.0);
    if (c.update_rate_hz < 0) throw params.error("updateRate", "must not be negative");
    const std::string command_topic = params.getString("commandTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    c.base_link = requireLink(ctx_, params, "robotBaseFrame", params.getString("robotBaseFrame", "base_footprint"));
    OdometryPublisher::Options odom;
    odom.odom_frame = ctx_.frame(params.getString("odometryFrame", "odom"));
    odom.base_frame = ctx_.frame(c.base_link);
    odom.publish_odom_tf = params.getBool("broadcastTF", false);
    odom.publish_world_to_odom_tf = false;  // the odom frame is the world, named odometryFrame
    odom.covariance_x = params.getDouble("covariance_x", 0.0001);
    odom.covariance_y = params.getDouble("covariance_y", 0.0001);
    odom.covariance_yaw = params.getDouble("covariance_yaw", 0.01);
    if (odom.covariance_x < 0) throw params.error("covariance_x", "must not be negative");
    if (odom.covariance_y < 0) throw params.error("covariance_y", "must not be negative");
    if (odom.covariance_yaw < 0) throw params.error("covariance_yaw", "must not be negative");
    // Written by many public robots (copied from the diff drive), read by no skid steer version.
    params.ignore(
        {"alwaysOn", "publishWheelTF", "publishWheelJointState", "publishOdom", "publishTf", "rosDebugLevel"});

    drive_ = std::make_unique<DiffDrive>(*ctx_.sim, ctx_.robot, c);
    cmd_sub_ = nh.subscribe(command_topic, 1, &SkidSteerDrivePlugin::onCommand, this);
    odometry_ = OdometryPublisher(ctx_, odom);
    odometry_.advertise(nh, odometry_topic);
    ROS_INFO(
        "%s: skid steer on joints %s, %s (left) / %s, %s (right), separation %.4f m, diameter %.4f m, "
        "torque %.2f N m, %.1f Hz, command %s, odometry %s in %s -> %s (TF %s), command timeout %.2f s",
        ctx_.sim->robot(ctx_.robot).spec.name.c_str(), c.left_joint.c_str(), c.more_left_joints[0].c_str(),
        c.right_joint.c_str(), c.more_right_joints[0].c_str(), p.wheel_separation_m, p.wheel_diameter_m,
        c.wheel_torque_nm, c.update_rate_hz, cmd_sub_.getTopic().c_str(), odometry_.topic().c_str(),
        odom.odom_frame.c_str(), odom.base_frame.c_str(), odom.publish_odom_tf ? "on" : "off", p.command_timeout_s);
  }

  void reset() override { drive_->reset(); }
  void beforeStep() override { drive_->beforeStep(); }
  void afterStep() override {
    if (drive_->afterStep()) odometry_.publish(drive_->odomPose(), drive_->odomTwist());
  }

 private:
  void onCommand(const geometry_msgs::Twist::ConstPtr& msg) {
    if (!drive_->command(msg->linear.x, msg->angular.z)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
                        cmd_sub_.getTopic().c_str());
    }
  }

  std::unique_ptr<DiffDrive> drive_;
  ros::Subscriber cmd_sub_;
  OdometryPublisher odometry_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeSkidSteerDrivePlugin() { return std::make_unique<SkidSteerDrivePlugin>(); }

}  // namespace conde_sim
