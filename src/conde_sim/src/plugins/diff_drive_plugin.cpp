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
#include <sensor_msgs/JointState.h>

#include <cmath>

#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/odometry_publisher.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

class DiffDrivePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    DiffDrive::Config c;
    DiffDriveParams& p = c.params;
    c.left_joint = params.requireString("leftJoint");
    c.right_joint = params.requireString("rightJoint");
    requireJoint(ctx_, params, "leftJoint", c.left_joint);
    requireJoint(ctx_, params, "rightJoint", c.right_joint);
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
    OdometryPublisher::Options odom;
    odom.odom_frame = ctx_.frame(params.getString("odometryFrame", "odom"));
    c.base_link = requireLink(ctx_, params, "robotBaseFrame", params.getString("robotBaseFrame", "base_footprint"));
    odom.base_frame = ctx_.frame(c.base_link);
    c.encoder_odometry = readEncoderOdometry(params);
    odom.publish_odom_tf = params.getBool("publishOdomTF", true);
    // In gazebo_ros_diff_drive, publishTf=false silences odometry altogether (a quirk we keep).
    publish_odometry_ = params.getBool("publishTf", true);
    publish_wheel_tf_ = params.getBool("publishWheelTF", false);
    publish_wheel_joint_state_ = params.getBool("publishWheelJointState", false);
    odom.publish_world_to_odom_tf = params.getBool("publishWorldToOdomTF", true);
    params.ignore({"alwaysOn", "legacyMode", "rosDebugLevel"});

    drive_ = std::make_unique<DiffDrive>(*ctx_.sim, ctx_.robot, c);
    cmd_sub_ = nh.subscribe(command_topic, 1, &DiffDrivePlugin::onCommand, this);
    odometry_ = OdometryPublisher(ctx_, odom);
    if (publish_odometry_) odometry_.advertise(nh, odometry_topic);
    if (publish_wheel_joint_state_) joint_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
    command_topic_ = cmd_sub_.getTopic();
    odometry_.publishWorldToOdom(drive_->encoderOdometry(), drive_->startPose());
    ROS_INFO(
        "%s: diff drive on joints %s/%s, separation %.4f m, diameter %.4f m, torque %.2f N m, %.1f Hz, "
        "command %s, odometry %s (%s) in %s -> %s, command timeout %.2f s",
        ctx_.sim->robot(ctx_.robot).spec.name.c_str(), c.left_joint.c_str(), c.right_joint.c_str(),
        p.wheel_separation_m, p.wheel_diameter_m, c.wheel_torque_nm, c.update_rate_hz, command_topic_.c_str(),
        publish_odometry_ ? odometry_.topic().c_str() : "(off)", c.encoder_odometry ? "encoder" : "world",
        odom.odom_frame.c_str(), odom.base_frame.c_str(), p.command_timeout_s);
  }

  void reset() override {
    drive_->reset();
    odometry_.publishWorldToOdom(drive_->encoderOdometry(), drive_->startPose());
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
    if (publish_odometry_) odometry_.publish(drive_->odomPose(), drive_->odomTwist());
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
      ctx_.tf->sendTransform(transformMessage(ctx_.now(), ctx_.frame(robot.model.bodies[spec.parent_body].name),
                                              ctx_.frame(robot.model.bodies[spec.child_body].name), wheel));
    }
  }

  std::unique_ptr<DiffDrive> drive_;
  std::string command_topic_;
  bool publish_odometry_ = true, publish_wheel_tf_ = false, publish_wheel_joint_state_ = false;
  bool timeout_reported_ = false;
  ros::Subscriber cmd_sub_;
  OdometryPublisher odometry_;
  ros::Publisher joint_pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeDiffDrivePlugin() { return std::make_unique<DiffDrivePlugin>(); }

}  // namespace conde_sim
