// libgazebo_ros_diff_drive.so: differential drive with gazebo_ros parameter names and defaults.
//
//   <gazebo><plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so">
//     <leftJoint>left_wheel_joint</leftJoint> <rightJoint>right_wheel_joint</rightJoint>
//     <wheelSeparation>0.33</wheelSeparation> <wheelDiameter>0.064</wheelDiameter>
//     <wheelTorque>7.5</wheelTorque> <updateRate>50</updateRate>
//     <commandTopic>cmd_vel</commandTopic> <odometryTopic>odom</odometryTopic>
//     <odometryFrame>odom</odometryFrame> <robotBaseFrame>base_footprint</robotBaseFrame>
//     <odometrySource>encoder</odometrySource>   <!-- or world (ground truth, the default) -->
//   </plugin></gazebo>
//
// Extensions (not in Gazebo): <cmdTimeout> [s] brakes the wheels when no command came for that
// long (default 0.5, 0 = never); <publishWorldToOdomTF> (default true) publishes the static
// world -> odom transform so rviz can show odometry over the track.
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/JointState.h>

#include <cmath>

#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

namespace cp = conde_physics;

geometry_msgs::Quaternion toMsg(const cp::Quat& q) {
  geometry_msgs::Quaternion m;
  m.w = q.w;
  m.x = q.x;
  m.y = q.y;
  m.z = q.z;
  return m;
}

class DiffDrivePlugin : public SimPlugin {
 public:
  void load(PluginContext& ctx, PluginParams& params) override {
    ctx_ = ctx;
    ros::NodeHandle nh = ctx.nodeHandle(params);
    DiffDrive::Config c;
    DiffDriveParams& p = c.params;
    c.left_joint = params.requireString("leftJoint");
    c.right_joint = params.requireString("rightJoint");
    requireJoint(ctx, params, "leftJoint", c.left_joint);
    requireJoint(ctx, params, "rightJoint", c.right_joint);
    p.wheel_separation_m = params.getDouble("wheelSeparation", p.wheel_separation_m);
    p.wheel_diameter_m = params.getDouble("wheelDiameter", p.wheel_diameter_m);
    p.wheel_acceleration_mps2 = params.getDouble("wheelAcceleration", p.wheel_acceleration_mps2);
    p.command_timeout_s = params.getDouble("cmdTimeout", p.command_timeout_s);
    if (p.wheel_separation_m <= 0) throw params.error("wheelSeparation", "must be positive");
    if (p.wheel_diameter_m <= 0) throw params.error("wheelDiameter", "must be positive");
    if (p.wheel_acceleration_mps2 < 0) throw params.error("wheelAcceleration", "must not be negative");
    if (p.command_timeout_s < 0) throw params.error("cmdTimeout", "must not be negative");
    c.wheel_torque_nm = params.getDouble("wheelTorque", c.wheel_torque_nm);
    if (c.wheel_torque_nm <= 0) throw params.error("wheelTorque", "must be positive");
    c.update_rate_hz = params.getDouble("updateRate", c.update_rate_hz);
    if (c.update_rate_hz < 0) throw params.error("updateRate", "must not be negative");
    const std::string command_topic = params.getString("commandTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    odom_frame_ = ctx.frame(params.getString("odometryFrame", "odom"));
    c.base_link = params.getString("robotBaseFrame", "base_footprint");
    base_frame_ = ctx.frame(c.base_link);
    int body = -1;
    cp::Pose unused;
    if (!ctx.sim->robot(ctx.robot).model.linkInBody(c.base_link, body, unused)) {
      throw params.error("robotBaseFrame", "robot has no link named '" + c.base_link + "'");
    }
    const std::string source = params.getString("odometrySource", "world");
    if (source != "world" && source != "encoder") {
      throw params.error("odometrySource", "expected 'world' or 'encoder', got '" + source + "'");
    }
    c.encoder_odometry = source == "encoder";
    publish_odom_tf_ = params.getBool("publishOdomTF", true);
    // In gazebo_ros_diff_drive, publishTf=false silences odometry altogether (a quirk we keep).
    publish_odometry_ = params.getBool("publishTf", true);
    publish_wheel_tf_ = params.getBool("publishWheelTF", false);
    publish_wheel_joint_state_ = params.getBool("publishWheelJointState", false);
    publish_world_odom_tf_ = params.getBool("publishWorldToOdomTF", true);
    params.ignore({"alwaysOn", "legacyMode", "rosDebugLevel"});

    drive_ = std::make_unique<DiffDrive>(*ctx.sim, ctx.robot, c);
    cmd_sub_ = nh.subscribe(command_topic, 1, &DiffDrivePlugin::onCommand, this);
    if (publish_odometry_) odom_pub_ = nh.advertise<nav_msgs::Odometry>(odometry_topic, 10);
    if (publish_wheel_joint_state_) joint_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
    command_topic_ = cmd_sub_.getTopic();
    publishWorldToOdom();
    ROS_INFO("%s: diff drive on joints %s/%s, separation %.4f m, diameter %.4f m, torque %.2f N m, %.1f Hz, "
             "command %s, odometry %s (%s) in %s -> %s, command timeout %.2f s",
             ctx.sim->robot(ctx.robot).spec.name.c_str(), c.left_joint.c_str(), c.right_joint.c_str(),
             p.wheel_separation_m, p.wheel_diameter_m, c.wheel_torque_nm, c.update_rate_hz, command_topic_.c_str(),
             publish_odometry_ ? odom_pub_.getTopic().c_str() : "(off)", source.c_str(), odom_frame_.c_str(),
             base_frame_.c_str(), p.command_timeout_s);
  }

  void reset() override {
    drive_->reset();
    publishWorldToOdom();
  }

  void beforeStep() override {
    if (drive_->timedOut() && !timeout_reported_) {
      ROS_WARN("%s: no command on %s for longer than the timeout: braking",
               ctx_.sim->robot(ctx_.robot).spec.name.c_str(), command_topic_.c_str());
      timeout_reported_ = true;
    }
    drive_->beforeStep();
  }

  void afterStep() override {
    if (!drive_->afterStep()) return;
    if (publish_odometry_) publishOdometry();
    if (publish_wheel_joint_state_ && joint_pub_.getNumSubscribers() > 0) publishJointStates();
    if (publish_wheel_tf_) publishWheelTransforms();
  }

 private:
  void onCommand(const geometry_msgs::Twist::ConstPtr& msg) {
    if (!drive_->command(msg->linear.x, msg->angular.z)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s (linear.x %f, angular.z %f)",
                        ctx_.sim->robot(ctx_.robot).spec.name.c_str(), command_topic_.c_str(), msg->linear.x,
                        msg->angular.z);
      return;
    }
    timeout_reported_ = false;
  }

  // Encoder odometry starts at zero where the robot starts; world odometry is the world frame.
  void publishWorldToOdom() {
    if (!publish_world_odom_tf_ || !publish_odom_tf_) return;
    const cp::Pose odom_in_world = drive_->encoderOdometry() ? drive_->startPose() : cp::Pose();
    geometry_msgs::TransformStamped t;
    t.header.stamp = ctx_.now();
    t.header.frame_id = "world";
    t.child_frame_id = odom_frame_;
    t.transform.translation.x = odom_in_world.position.x;
    t.transform.translation.y = odom_in_world.position.y;
    t.transform.translation.z = odom_in_world.position.z;
    t.transform.rotation = toMsg(odom_in_world.orientation);
    ctx_.static_tf->sendTransform(t);
  }

  void publishOdometry() {
    const cp::Pose& pose = drive_->odomPose();
    const cp::Twist& twist = drive_->odomTwist();
    nav_msgs::Odometry odom;
    odom.header.stamp = ctx_.now();
    odom.header.frame_id = odom_frame_;
    odom.child_frame_id = base_frame_;
    odom.pose.pose.position.x = pose.position.x;
    odom.pose.pose.position.y = pose.position.y;
    odom.pose.pose.position.z = pose.position.z;
    odom.pose.pose.orientation = toMsg(pose.orientation);
    odom.twist.twist.linear.x = twist.linear_mps.x;
    odom.twist.twist.linear.y = twist.linear_mps.y;
    odom.twist.twist.linear.z = twist.linear_mps.z;
    odom.twist.twist.angular.x = twist.angular_radps.x;
    odom.twist.twist.angular.y = twist.angular_radps.y;
    odom.twist.twist.angular.z = twist.angular_radps.z;
    // Same diagonal as gazebo_ros_diff_drive: planar motion, z/roll/pitch unknown.
    const double cov[6] = {1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3};
    for (int i = 0; i < 6; ++i) {
      odom.pose.covariance[i * 7] = cov[i];
      odom.twist.covariance[i * 7] = cov[i];
    }
    odom_pub_.publish(odom);
    if (publish_odom_tf_) {
      geometry_msgs::TransformStamped t;
      t.header = odom.header;
      t.child_frame_id = base_frame_;
      t.transform.translation.x = pose.position.x;
      t.transform.translation.y = pose.position.y;
      t.transform.translation.z = pose.position.z;
      t.transform.rotation = odom.pose.pose.orientation;
      ctx_.tf->sendTransform(t);
    }
  }

  void publishJointStates() {
    const cp::PhysicsEngine& e = ctx_.sim->engine();
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    sensor_msgs::JointState js;
    js.header.stamp = ctx_.now();
    for (int j : {drive_->leftJoint(), drive_->rightJoint()}) {
      js.name.push_back(robot.model.joints[j].name);
      js.position.push_back(e.jointPosition(robot.id, j));
      js.velocity.push_back(e.jointVelocity(robot.id, j));
    }
    joint_pub_.publish(js);
  }

  // Wheel link frames relative to the link frame of the body they turn on (for robots without
  // robot_state_publisher; do not combine with it, or the wheel frames get two parents).
  void publishWheelTransforms() {
    const cp::PhysicsEngine& e = ctx_.sim->engine();
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    for (int j : {drive_->leftJoint(), drive_->rightJoint()}) {
      const cp::JointSpec& spec = robot.model.joints[j];
      const cp::Pose wheel =
          spec.pose_in_parent * cp::Pose(cp::Vec3(), cp::Quat::fromAxisAngle(spec.axis, e.jointPosition(robot.id, j)));
      geometry_msgs::TransformStamped t;
      t.header.stamp = ctx_.now();
      t.header.frame_id = ctx_.frame(robot.model.bodies[spec.parent_body].name);
      t.child_frame_id = ctx_.frame(robot.model.bodies[spec.child_body].name);
      t.transform.translation.x = wheel.position.x;
      t.transform.translation.y = wheel.position.y;
      t.transform.translation.z = wheel.position.z;
      t.transform.rotation = toMsg(wheel.orientation);
      ctx_.tf->sendTransform(t);
    }
  }

  PluginContext ctx_;
  std::unique_ptr<DiffDrive> drive_;
  std::string odom_frame_, base_frame_, command_topic_;
  bool publish_odom_tf_ = true, publish_odometry_ = true;
  bool publish_wheel_tf_ = false, publish_wheel_joint_state_ = false, publish_world_odom_tf_ = true;
  bool timeout_reported_ = false;
  ros::Subscriber cmd_sub_;
  ros::Publisher odom_pub_, joint_pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeDiffDrivePlugin() { return std::make_unique<DiffDrivePlugin>(); }

}  // namespace conde_sim
