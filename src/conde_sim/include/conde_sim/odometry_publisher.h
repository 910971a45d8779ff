// What the drive plugins (diff drive, Ackermann drive) publish of their odometry, with the
// messages, frames and keys of gazebo_ros_diff_drive: nav_msgs/Odometry of the base frame in the
// odom frame (twist in the base frame, a planar covariance), TF odom -> base with each message
// (<publishOdomTF>), and the static world -> odom (<publishWorldToOdomTF>, an extension) so rviz
// can show odometry over the track.
//
//   OdometryPublisher odometry(ctx, options);
//   odometry.advertise(nh, "odom");
//   odometry.publishWorldToOdom(drive.encoderOdometry(), drive.startPose());  // at load and reset
//   odometry.publish(drive.odomPose(), drive.odomTwist());                     // at the update rate
#pragma once

#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>

#include <string>
#include <utility>

#include "conde_physics/math.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"

namespace conde_sim {

// <odometrySource>: true for "encoder" (dead reckoning), false for "world" (ground truth, the
// default); any other value is a PluginError naming the key.
bool readEncoderOdometry(PluginParams& params);

class OdometryPublisher {
 public:
  struct Options {
    std::string odom_frame, base_frame;    // with the robot's frame prefix
    bool publish_odom_tf = true;           // <publishOdomTF>
    bool publish_world_to_odom_tf = true;  // <publishWorldToOdomTF>; only with publish_odom_tf
    // Diagonal of the pose and twist covariances (x, y, yaw; z, roll and pitch get 1e12), those
    // of gazebo_ros_diff_drive and planar_move; skid steer reads <covariance_x> and friends.
    double covariance_x = 1e-5, covariance_y = 1e-5, covariance_yaw = 1e-3;
  };

  OdometryPublisher() = default;
  OdometryPublisher(const PluginContext& ctx, Options options) : ctx_(ctx), options_(std::move(options)) {}

  // nav_msgs/Odometry on `topic`; publish() needs it.
  void advertise(ros::NodeHandle& nh, const std::string& topic);
  std::string topic() const { return pub_.getTopic(); }

  // The static world -> odom transform: encoder odometry starts at zero where the robot started
  // (`start_pose` in the world); world odometry is the world frame.
  void publishWorldToOdom(bool encoder_odometry, const conde_physics::Pose& start_pose) const;
  // The odometry message and, with publish_odom_tf, odom -> base, stamped with simulated time.
  void publish(const conde_physics::Pose& base_in_odom, const conde_physics::Twist& twist_in_base) const;

 private:
  PluginContext ctx_;
  Options options_;
  ros::Publisher pub_;
};

}  // namespace conde_sim
