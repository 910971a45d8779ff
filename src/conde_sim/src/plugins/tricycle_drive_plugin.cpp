// libgazebo_ros_tricycle_drive.so: a steered, driven front wheel and two encoder rear wheels, with
// the parameter names and defaults of gazebo_ros_tricycle_drive (ROS 1); the control law is in
// tricycle_drive.h (with the differences from Gazebo).
//
//   <gazebo><plugin name="tricycle" filename="libgazebo_ros_tricycle_drive.so">
//     <steeringJoint>front_steering_joint</steeringJoint> <actuatedWheelJoint>front_wheel_joint</actuatedWheelJoint>
//     <encoderWheelLeftJoint>left_wheel_joint</encoderWheelLeftJoint>
//     <encoderWheelRightJoint>right_wheel_joint</encoderWheelRightJoint>
//     <actuatedWheelDiameter>0.15</actuatedWheelDiameter> <encoderWheelDiameter>0.15</encoderWheelDiameter>
//     <encoderWheelSeparation>0.5</encoderWheelSeparation> <wheelTorque>5</wheelTorque>
//     <wheelAcceleration>0</wheelAcceleration> <wheelDeceleration>0</wheelDeceleration>
//     <wheelSpeedTolerance>0.01</wheelSpeedTolerance> <steeringSpeed>0</steeringSpeed>
//     <steeringAngleTolerance>0.01</steeringAngleTolerance> <updateRate>100</updateRate>
//     <commandTopic>cmd_vel</commandTopic> <odometryTopic>odom</odometryTopic>
//     <odometryFrame>odom</odometryFrame> <robotBaseFrame>base_link</robotBaseFrame>
//     <odometrySource>world</odometrySource> <publishWheelTF>false</publishWheelTF>
//     <publishWheelJointState>false</publishWheelJointState>
//   </plugin></gazebo>
//
// cmd_vel: linear.x = wheel surface speed [m/s], angular.z = steering angle [rad]. Odometry
// (world: the base frame's ground truth; encoder: dead reckoning on the rear wheels) with TF
// odometryFrame -> robotBaseFrame at the update rate, as Gazebo always broadcasts it.
#include <geometry_msgs/Twist.h>
#include <sensor_msgs/JointState.h>

#include <utility>

#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/drive_odometry.h"
#include "conde_sim/odometry_publisher.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"
#include "conde_sim/tricycle_drive.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class TricycleDrivePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const char* joint_keys[kJoints] = {"steeringJoint", "actuatedWheelJoint", "encoderWheelLeftJoint",
                                       "encoderWheelRightJoint"};
    const char* joint_defaults[kJoints] = {"front_steering_joint", "front_wheel_joint", "left_wheel_joint",
                                           "right_wheel_joint"};
    for (int i = 0; i < kJoints; ++i) {
      joint_names_[i] = params.getString(joint_keys[i], joint_defaults[i]);
      joints_[i] = requireJoint(ctx_, params, joint_keys[i], joint_names_[i]);
    }
    TricycleParams p;
    p.actuated_wheel_diameter_m = params.getDouble("actuatedWheelDiameter", 0.15);
    const double encoder_diameter_m = params.getDouble("encoderWheelDiameter", 0.15);
    const double encoder_separation_m = params.getDouble("encoderWheelSeparation", 0.5);
    if (p.actuated_wheel_diameter_m <= 0) throw params.error("actuatedWheelDiameter", "must be positive");
    if (encoder_diameter_m <= 0) throw params.error("encoderWheelDiameter", "must be positive");
    if (encoder_separation_m <= 0) throw params.error("encoderWheelSeparation", "must be positive");
    torque_nm_ = params.getDouble("wheelTorque", 5.0);
    if (torque_nm_ <= 0) throw params.error("wheelTorque", "must be positive");
    p.wheel_acceleration_radps2 = params.getDouble("wheelAcceleration", 0.0);
    p.wheel_deceleration_radps2 = params.getDouble("wheelDeceleration", p.wheel_acceleration_radps2);
    p.wheel_speed_tolerance_radps = params.getDouble("wheelSpeedTolerance", 0.01);
    p.steering_speed_radps = params.getDouble("steeringSpeed", 0.0);
    p.steering_angle_tolerance_rad = params.getDouble("steeringAngleTolerance", 0.01);
    p.command_timeout_s = params.getDouble("cmdTimeout", 0.0);
    const std::pair<const char*, double> non_negative[] = {
        {"wheelAcceleration", p.wheel_acceleration_radps2},         {"wheelDeceleration", p.wheel_deceleration_radps2},
        {"wheelSpeedTolerance", p.wheel_speed_tolerance_radps},     {"steeringSpeed", p.steering_speed_radps},
        {"steeringAngleTolerance", p.steering_angle_tolerance_rad}, {"cmdTimeout", p.command_timeout_s}};
    for (const auto& [key, value] : non_negative) {
      if (value < 0) throw params.error(key, "must not be negative");
    }
    const double rate_hz = params.getDouble("updateRate", 100.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    const std::string command_topic = params.getString("commandTopic", "cmd_vel");
    const std::string odometry_topic = params.getString("odometryTopic", "odom");
    base_link_ = requireLink(ctx_, params, "robotBaseFrame", params.getString("robotBaseFrame", "base_link"));
    encoder_odometry_ = readEncoderOdometry(params);
    publish_wheel_tf_ = params.getBool("publishWheelTF", false);
    publish_joint_state_ = params.getBool("publishWheelJointState", false);
    params.ignore({"alwaysOn", "rosDebugLevel"});

    OdometryPublisher::Options odom;
    odom.odom_frame = ctx_.frame(params.getString("odometryFrame", "odom"));
    odom.base_frame = ctx_.frame(base_link_);
    odom.publish_odom_tf = true;
    odom.publish_world_to_odom_tf = false;
    controller_ = std::make_unique<TricycleController>(p);
    encoder_ = std::make_unique<DiffDriveOdometry>(encoder_separation_m, encoder_diameter_m / 2.0);
    cmd_sub_ = nh.subscribe(command_topic, 1, &TricycleDrivePlugin::onCommand, this);
    odometry_ = OdometryPublisher(ctx_, odom);
    odometry_.advertise(nh, odometry_topic);
    if (publish_joint_state_) {
      joint_state_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
      joint_state_.name.assign(joint_names_, joint_names_ + kJoints);
      joint_state_.position.resize(kJoints);
      joint_state_.velocity.resize(kJoints);
      joint_state_.effort.assign(kJoints, torque_nm_);  // Gazebo reports each joint's fmax
    }
    reset();
    ROS_INFO(
        "%s: tricycle steering %s, wheel %s (diameter %.4f m, torque %.2f N m, acceleration %.3f / deceleration "
        "%.3f rad/s^2), encoders %s, %s (diameter %.4f m, separation %.4f m), steering speed %.3f rad/s, %.1f Hz, "
        "command %s, odometry (%s) %s in %s -> %s, wheel TF %s, joint states %s",
        ctx_.sim->robot(ctx_.robot).spec.name.c_str(), joint_names_[kSteering].c_str(), joint_names_[kWheel].c_str(),
        p.actuated_wheel_diameter_m, torque_nm_, p.wheel_acceleration_radps2, p.wheel_deceleration_radps2,
        joint_names_[kLeft].c_str(), joint_names_[kRight].c_str(), encoder_diameter_m, encoder_separation_m,
        p.steering_speed_radps, rate_hz, cmd_sub_.getTopic().c_str(), encoder_odometry_ ? "encoder" : "world",
        odometry_.topic().c_str(), odom.odom_frame.c_str(), odom.base_frame.c_str(), publish_wheel_tf_ ? "on" : "off",
        publish_joint_state_ ? "on" : "off");
    steering_speed_radps_ = p.steering_speed_radps;
  }

  void reset() override {
    controller_->reset();
    encoder_->reset(position(kLeft), position(kRight));
    last_update_step_ = ctx_.sim->stepCount();
  }

  void beforeStep() override {
    cp::PhysicsEngine& engine = ctx_.sim->engine();
    const cp::ModelId id = ctx_.sim->robot(ctx_.robot).id;
    const double step_s = ctx_.sim->stepS();
    if (timer_.due(ctx_.sim->stepCount())) {
      const double wheel_radps =
          controller_->wheelSpeed(ctx_.sim->timeS(), velocity(kWheel), timer_.stepsPerUpdate() * step_s);
      engine.setJointVelocityMotor(id, joints_[kWheel], wheel_radps, torque_nm_);
      if (steering_speed_radps_ > 0.0) {
        engine.setJointVelocityMotor(id, joints_[kSteering], controller_->steeringSpeed(position(kSteering)),
                                     torque_nm_);
      }
    }
    if (steering_speed_radps_ <= 0.0) {
      // Gazebo sets the steering angle; a motor that reaches it within the step does the same.
      const double velocity_radps = (controller_->steeringTarget() - position(kSteering)) / step_s;
      engine.setJointVelocityMotor(id, joints_[kSteering], velocity_radps, torque_nm_);
    }
  }

  void afterStep() override {
    const std::uint64_t step = ctx_.sim->stepCount();
    if (!timer_.due(step)) return;
    const double dt_s = static_cast<double>(step - last_update_step_) * ctx_.sim->stepS();
    last_update_step_ = step;
    cp::Pose pose;
    cp::Twist twist;
    if (encoder_odometry_) {
      encoder_->update(position(kLeft), position(kRight), dt_s);
      pose = cp::Pose(cp::Vec3(encoder_->x_m(), encoder_->y_m(), 0.0), cp::Quat::fromRpy(0, 0, encoder_->yaw_rad()));
      twist.linear_mps = cp::Vec3(encoder_->linear_mps(), 0, 0);
      twist.angular_radps = cp::Vec3(0, 0, encoder_->angular_radps());
    } else {
      groundTruthOdometry(*ctx_.sim, ctx_.robot, base_link_, pose, twist);
    }
    odometry_.publish(pose, twist);
    if (publish_joint_state_) publishJointState();
    if (publish_wheel_tf_) publishWheelTf();
  }

 private:
  enum { kSteering, kWheel, kLeft, kRight, kJoints };

  double position(int i) const { return ctx_.sim->engine().jointPosition(ctx_.sim->robot(ctx_.robot).id, joints_[i]); }
  double velocity(int i) const { return ctx_.sim->engine().jointVelocity(ctx_.sim->robot(ctx_.robot).id, joints_[i]); }

  void onCommand(const geometry_msgs::Twist::ConstPtr& msg) {
    if (!controller_->setCommand(msg->linear.x, msg->angular.z, ctx_.sim->timeS())) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
                        cmd_sub_.getTopic().c_str());
    }
  }

  void publishJointState() {
    joint_state_.header.stamp = ctx_.now();
    for (int i = 0; i < kJoints; ++i) {
      joint_state_.position[i] = position(i);
      joint_state_.velocity[i] = velocity(i);
    }
    joint_state_pub_.publish(joint_state_);
  }

  // As Gazebo: each joint's child link in its parent link, the child frame named after the joint
  // (so it does not clash with robot_state_publisher's link frames). The parent is the link that
  // carries the parent body (links joined by fixed joints are one body, as in Gazebo's SDF).
  void publishWheelTf() const {
    const Robot& robot = ctx_.sim->robot(ctx_.robot);
    for (int i = 0; i < kJoints; ++i) {
      const cp::JointSpec& joint = robot.model.joints.at(joints_[i]);
      const std::string& parent = robot.model.bodies.at(joint.parent_body).name;
      const std::string& child = robot.model.bodies.at(joint.child_body).name;
      const cp::Pose child_in_parent =
          ctx_.sim->linkPose(ctx_.robot, parent).inverse() * ctx_.sim->linkPose(ctx_.robot, child);
      ctx_.tf->sendTransform(
          transformMessage(ctx_.now(), ctx_.frame(parent), ctx_.frame(joint_names_[i]), child_in_parent));
    }
  }

  std::string joint_names_[kJoints];
  int joints_[kJoints] = {-1, -1, -1, -1};
  double torque_nm_ = 5.0, steering_speed_radps_ = 0.0;
  std::string base_link_;
  bool encoder_odometry_ = false, publish_wheel_tf_ = false, publish_joint_state_ = false;
  UpdateTimer timer_;
  std::uint64_t last_update_step_ = 0;
  std::unique_ptr<TricycleController> controller_;
  std::unique_ptr<DiffDriveOdometry> encoder_;
  ros::Subscriber cmd_sub_;
  OdometryPublisher odometry_;
  ros::Publisher joint_state_pub_;
  sensor_msgs::JointState joint_state_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeTricycleDrivePlugin() { return std::make_unique<TricycleDrivePlugin>(); }

}  // namespace conde_sim
