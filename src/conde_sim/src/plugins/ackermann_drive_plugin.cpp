// libconde_ackermann_drive.so: Ackermann steering with PID control of the wheel speeds and the
// steering hinges (gazebo_ros for ROS 1 has no such plugin; gazebo_ros_pkgs #900).
//
//   <gazebo><plugin name="ackermann_drive" filename="libconde_ackermann_drive.so">
//     <leftSteeringJoint>left_steering_joint</leftSteeringJoint>
//     <rightSteeringJoint>right_steering_joint</rightSteeringJoint>
//     <leftRearWheelJoint>left_rear_wheel_joint</leftRearWheelJoint>
//     <rightRearWheelJoint>right_rear_wheel_joint</rightRearWheelJoint>
//     <leftFrontWheelJoint>left_front_wheel_joint</leftFrontWheelJoint>     <!-- optional -->
//     <rightFrontWheelJoint>right_front_wheel_joint</rightFrontWheelJoint>  <!-- optional -->
//     <driveWheels>all</driveWheels>                  <!-- rear (default) | front | all -->
//     <commandTopic>ackermann_cmd</commandTopic>      <!-- conde_msgs/AckermannDriveStamped -->
//     <twistTopic>cmd_vel</twistTopic>                <!-- geometry_msgs/Twist, angular.z a yaw rate -->
//     <wheelPidGains>0.1 2.0 0.0</wheelPidGains>      <!-- p [N m s/rad], i [N m/rad], d [N m s^2/rad] -->
//     <wheelPidIClamp>1.0</wheelPidIClamp> <wheelTorque>1.0</wheelTorque>               <!-- [N m] -->
//     <steeringPidGains>100 100 0.2</steeringPidGains> <!-- p [N m/rad], i [N m/(rad s)], d [N m s/rad] -->
//     <steeringPidIClamp>0.1</steeringPidIClamp> <steeringTorque>5.0</steeringTorque>   <!-- [N m] -->
//     <cmdTimeout>0.5</cmdTimeout> <updateRate>50</updateRate>
//     <odometrySource>encoder</odometrySource>        <!-- or world (ground truth, the default) -->
//     <odometryTopic>odom</odometryTopic> <odometryFrame>odom</odometryFrame>
//     <robotBaseFrame>base_footprint</robotBaseFrame>
//   </plugin></gazebo>
//
// Geometry comes from the URDF unless given: <wheelbase> [m] (steering hinges to rear wheel
// joints along x of robotBaseFrame), <frontTrack> / <rearTrack> [m] (between the steering hinges /
// rear wheel joints), <wheelRadius> [m] (the rear wheels' cylinders), <maxSteeringAngle> [rad] of
// the centre steering angle (what the hinges' position limits allow). Other keys:
// <publishOdomTF> (true), <publishWorldToOdomTF> (true: static world -> odom, as the diff drive),
// <publishJointStates> (true: `joint_states` with the six joints at the update rate), <robotNamespace>.
// The PIDs run at every physics step; the update rate paces odometry and joint states. After
// <cmdTimeout> s [0 = never] without a command the wheels brake to 0 and the steering holds.
#include <conde_msgs/AckermannDriveStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/JointState.h>

#include <cmath>

#include "conde_sim/ackermann_drive.h"
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

PidController::Gains readGains(PluginParams& params, const std::string& prefix, const PidController::Gains& fallback) {
  const std::string gains_key = prefix + "PidGains", clamp_key = prefix + "PidIClamp", torque_key = prefix + "Torque";
  const cp::Vec3 pid = params.getVec3(gains_key, cp::Vec3(fallback.p, fallback.i, fallback.d));
  PidController::Gains g;
  g.p = pid.x;
  g.i = pid.y;
  g.d = pid.z;
  if (g.p < 0 || g.i < 0 || g.d < 0) throw params.error(gains_key, "gains must not be negative");
  g.i_clamp = params.getDouble(clamp_key, fallback.i_clamp);
  if (g.i_clamp < 0) throw params.error(clamp_key, "must not be negative");
  g.output_limit = params.getDouble(torque_key, fallback.output_limit);
  if (g.output_limit <= 0) throw params.error(torque_key, "must be positive");
  return g;
}

double nonNegative(PluginParams& params, const std::string& key, double fallback) {
  const double v = params.getDouble(key, fallback);
  if (v < 0) throw params.error(key, "must not be negative");
  return v;
}

class AckermannDrivePlugin : public SimPlugin {
 public:
  void load(PluginContext& ctx, PluginParams& params) override {
    ctx_ = ctx;
    ros::NodeHandle nh = ctx.nodeHandle(params);
    AckermannDrive::Config c;
    c.left_steering_joint = params.requireString("leftSteeringJoint");
    c.right_steering_joint = params.requireString("rightSteeringJoint");
    c.left_rear_wheel_joint = params.requireString("leftRearWheelJoint");
    c.right_rear_wheel_joint = params.requireString("rightRearWheelJoint");
    c.left_front_wheel_joint = params.getString("leftFrontWheelJoint", "");
    c.right_front_wheel_joint = params.getString("rightFrontWheelJoint", "");
    for (const char* key : {"leftSteeringJoint", "rightSteeringJoint", "leftRearWheelJoint", "rightRearWheelJoint",
                            "leftFrontWheelJoint", "rightFrontWheelJoint"}) {
      const std::string name = params.getString(key, "");
      if (!name.empty()) requireJoint(ctx, params, key, name);
    }
    const std::string drive_wheels = params.getString("driveWheels", "rear");
    if (drive_wheels != "rear" && drive_wheels != "front" && drive_wheels != "all") {
      throw params.error("driveWheels", "expected 'rear', 'front' or 'all', got '" + drive_wheels + "'");
    }
    c.drive_rear = drive_wheels != "front";
    c.drive_front = drive_wheels != "rear";
    c.geometry.wheelbase_m = nonNegative(params, "wheelbase", 0.0);
    c.geometry.front_half_track_m = nonNegative(params, "frontTrack", 0.0) / 2.0;
    c.geometry.rear_half_track_m = nonNegative(params, "rearTrack", 0.0) / 2.0;
    c.geometry.wheel_radius_m = nonNegative(params, "wheelRadius", 0.0);
    c.max_steering_angle_rad = params.getDouble("maxSteeringAngle", 0.0);
    if (params.has("maxSteeringAngle") && !(c.max_steering_angle_rad > 0 && c.max_steering_angle_rad < M_PI / 2)) {
      throw params.error("maxSteeringAngle", "must lie in (0, pi/2) rad");
    }
    c.wheel_pid = readGains(params, "wheel", c.wheel_pid);
    c.steering_pid = readGains(params, "steering", c.steering_pid);
    c.command_timeout_s = nonNegative(params, "cmdTimeout", c.command_timeout_s);
    c.update_rate_hz = nonNegative(params, "updateRate", c.update_rate_hz);
    c.base_link = params.getString("robotBaseFrame", "base_footprint");
    const std::string source = params.getString("odometrySource", "world");
    if (source != "world" && source != "encoder") {
      throw params.error("odometrySource", "expected 'world' or 'encoder', got '" + source + "'");
    }
    c.encoder_odometry = source == "encoder";
    const std::string command_topic = params.getString("commandTopic", "ackermann_cmd");
    const std::string twist_topic = params.getString("twistTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    odom_frame_ = ctx.frame(params.getString("odometryFrame", "odom"));
    base_frame_ = ctx.frame(c.base_link);
    publish_odom_tf_ = params.getBool("publishOdomTF", true);
    publish_world_odom_tf_ = params.getBool("publishWorldToOdomTF", true);
    const bool publish_joint_states = params.getBool("publishJointStates", true);
    try {
      drive_ = std::make_unique<AckermannDrive>(*ctx.sim, ctx.robot, c);
    } catch (const AckermannConfigError& e) {
      throw params.error(e.key, e.what());
    }

    robot_name_ = ctx.sim->robot(ctx.robot).spec.name;
    if (!command_topic.empty()) drive_sub_ = nh.subscribe(command_topic, 1, &AckermannDrivePlugin::onDrive, this);
    if (!twist_topic.empty()) twist_sub_ = nh.subscribe(twist_topic, 1, &AckermannDrivePlugin::onTwist, this);
    odom_pub_ = nh.advertise<nav_msgs::Odometry>(odometry_topic, 10);
    if (publish_joint_states) {
      joint_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
      const cp::ArticulatedModel& model = ctx.sim->robot(ctx.robot).model;
      for (int j = 0; j < AckermannDrive::kJointCount; ++j) {
        if (drive_->joint(j) < 0) continue;
        joint_state_.name.push_back(model.joints[drive_->joint(j)].name);
        joint_indices_.push_back(drive_->joint(j));
      }
      joint_state_.position.resize(joint_indices_.size());
      joint_state_.velocity.resize(joint_indices_.size());
    }
    publishWorldToOdom();
    const AckermannGeometry& g = drive_->geometry();
    ROS_INFO("%s: Ackermann drive, wheelbase %.4f m, tracks %.4f/%.4f m, wheel radius %.4f m, max steering %.3f rad, "
             "%s-wheel drive, command %s, twist %s, odometry %s (%s) in %s -> %s, command timeout %.2f s",
             robot_name_.c_str(), g.wheelbase_m, 2 * g.front_half_track_m, 2 * g.rear_half_track_m, g.wheel_radius_m,
             drive_->maxSteeringAngle(), drive_wheels.c_str(),
             command_topic.empty() ? "(off)" : drive_sub_.getTopic().c_str(),
             twist_topic.empty() ? "(off)" : twist_sub_.getTopic().c_str(), odom_pub_.getTopic().c_str(),
             source.c_str(), odom_frame_.c_str(), base_frame_.c_str(), c.command_timeout_s);
  }

  void reset() override {
    drive_->reset();
    publishWorldToOdom();
  }

  void beforeStep() override {
    if (drive_->timedOut() && !timeout_reported_) {
      ROS_WARN("%s: no Ackermann or Twist command for longer than the timeout: braking", robot_name_.c_str());
      timeout_reported_ = true;
    }
    drive_->beforeStep();
  }

  void afterStep() override {
    if (!drive_->afterStep()) return;
    publishOdometry();
    if (joint_pub_ && joint_pub_.getNumSubscribers() > 0) publishJointStates();
  }

 private:
  void onDrive(const conde_msgs::AckermannDriveStamped::ConstPtr& msg) {
    const conde_msgs::AckermannDrive& d = msg->drive;
    if (!drive_->commandDrive(d.speed, d.steering_angle, d.steering_angle_velocity, d.acceleration)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s (speed %f, steering_angle %f, "
                        "steering_angle_velocity %f, acceleration %f)", robot_name_.c_str(), drive_sub_.getTopic().c_str(),
                        d.speed, d.steering_angle, d.steering_angle_velocity, d.acceleration);
      return;
    }
    timeout_reported_ = false;
  }

  void onTwist(const geometry_msgs::Twist::ConstPtr& msg) {
    if (!drive_->commandTwist(msg->linear.x, msg->angular.z)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s (linear.x %f, angular.z %f)", robot_name_.c_str(),
                        twist_sub_.getTopic().c_str(), msg->linear.x, msg->angular.z);
      return;
    }
    timeout_reported_ = false;
  }

  // Encoder odometry starts at zero where the car starts; world odometry is the world frame.
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
    const double cov[6] = {1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3};  // planar motion, as the diff drive
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
    const cp::ModelId id = ctx_.sim->robot(ctx_.robot).id;
    joint_state_.header.stamp = ctx_.now();
    for (size_t i = 0; i < joint_indices_.size(); ++i) {
      joint_state_.position[i] = e.jointPosition(id, joint_indices_[i]);
      joint_state_.velocity[i] = e.jointVelocity(id, joint_indices_[i]);
    }
    joint_pub_.publish(joint_state_);
  }

  PluginContext ctx_;
  std::unique_ptr<AckermannDrive> drive_;
  std::string robot_name_, odom_frame_, base_frame_;
  bool publish_odom_tf_ = true, publish_world_odom_tf_ = true, timeout_reported_ = false;
  ros::Subscriber drive_sub_, twist_sub_;
  ros::Publisher odom_pub_, joint_pub_;
  sensor_msgs::JointState joint_state_;
  std::vector<int> joint_indices_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeAckermannDrivePlugin() { return std::make_unique<AckermannDrivePlugin>(); }

}  // namespace conde_sim
