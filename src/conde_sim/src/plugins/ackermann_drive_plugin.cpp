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
#include <sensor_msgs/JointState.h>

#include <cmath>

#include "conde_sim/ackermann_drive.h"
#include "conde_sim/odometry_publisher.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

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
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
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
      if (!name.empty()) requireJoint(ctx_, params, key, name);
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
    c.encoder_odometry = readEncoderOdometry(params);
    const std::string command_topic = params.getString("commandTopic", "ackermann_cmd");
    const std::string twist_topic = params.getString("twistTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    OdometryPublisher::Options odom;
    odom.odom_frame = ctx_.frame(params.getString("odometryFrame", "odom"));
    odom.base_frame = ctx_.frame(c.base_link);
    odom.publish_odom_tf = params.getBool("publishOdomTF", true);
    odom.publish_world_to_odom_tf = params.getBool("publishWorldToOdomTF", true);
    const bool publish_joint_states = params.getBool("publishJointStates", true);
    try {
      drive_ = std::make_unique<AckermannDrive>(*ctx_.sim, ctx_.robot, c);
    } catch (const AckermannConfigError& e) {
      throw params.error(e.key, e.what());
    }

    robot_name_ = ctx_.sim->robot(ctx_.robot).spec.name;
    if (!command_topic.empty()) drive_sub_ = nh.subscribe(command_topic, 1, &AckermannDrivePlugin::onDrive, this);
    if (!twist_topic.empty()) twist_sub_ = nh.subscribe(twist_topic, 1, &AckermannDrivePlugin::onTwist, this);
    odometry_ = OdometryPublisher(ctx_, odom);
    odometry_.advertise(nh, odometry_topic);
    if (publish_joint_states) {
      joint_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
      const cp::ArticulatedModel& model = ctx_.sim->robot(ctx_.robot).model;
      for (int j = 0; j < AckermannDrive::kJointCount; ++j) {
        if (drive_->joint(j) < 0) continue;
        joint_state_.name.push_back(model.joints[drive_->joint(j)].name);
        joint_indices_.push_back(drive_->joint(j));
      }
      joint_state_.position.resize(joint_indices_.size());
      joint_state_.velocity.resize(joint_indices_.size());
    }
    odometry_.publishWorldToOdom(drive_->encoderOdometry(), drive_->startPose());
    const AckermannGeometry& g = drive_->geometry();
    ROS_INFO(
        "%s: Ackermann drive, wheelbase %.4f m, tracks %.4f/%.4f m, wheel radius %.4f m, max steering %.3f rad, "
        "%s-wheel drive, command %s, twist %s, odometry %s (%s) in %s -> %s, command timeout %.2f s",
        robot_name_.c_str(), g.wheelbase_m, 2 * g.front_half_track_m, 2 * g.rear_half_track_m, g.wheel_radius_m,
        drive_->maxSteeringAngle(), drive_wheels.c_str(),
        command_topic.empty() ? "(off)" : drive_sub_.getTopic().c_str(),
        twist_topic.empty() ? "(off)" : twist_sub_.getTopic().c_str(), odometry_.topic().c_str(),
        c.encoder_odometry ? "encoder" : "world", odom.odom_frame.c_str(), odom.base_frame.c_str(),
        c.command_timeout_s);
  }

  void reset() override {
    drive_->reset();
    odometry_.publishWorldToOdom(drive_->encoderOdometry(), drive_->startPose());
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
    odometry_.publish(drive_->odomPose(), drive_->odomTwist());
    if (joint_pub_ && joint_pub_.getNumSubscribers() > 0) publishJointStates();
  }

 private:
  void onDrive(const conde_msgs::AckermannDriveStamped::ConstPtr& msg) {
    const conde_msgs::AckermannDrive& d = msg->drive;
    if (!drive_->commandDrive(d.speed, d.steering_angle, d.steering_angle_velocity, d.acceleration)) {
      ROS_WARN_THROTTLE(1.0,
                        "%s: ignoring a non-finite command on %s (speed %f, steering_angle %f, "
                        "steering_angle_velocity %f, acceleration %f)",
                        robot_name_.c_str(), drive_sub_.getTopic().c_str(), d.speed, d.steering_angle,
                        d.steering_angle_velocity, d.acceleration);
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

  std::unique_ptr<AckermannDrive> drive_;
  std::string robot_name_;
  bool timeout_reported_ = false;
  ros::Subscriber drive_sub_, twist_sub_;
  OdometryPublisher odometry_;
  ros::Publisher joint_pub_;
  sensor_msgs::JointState joint_state_;
  std::vector<int> joint_indices_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeAckermannDrivePlugin() { return std::make_unique<AckermannDrivePlugin>(); }

}  // namespace conde_sim
