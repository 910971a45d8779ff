#include "conde_sim/odometry_publisher.h"

#include <nav_msgs/Odometry.h>

namespace conde_sim {

namespace cp = conde_physics;

bool readEncoderOdometry(PluginParams& params) {
  const std::string source = params.getString("odometrySource", "world");
  if (source != "world" && source != "encoder") {
    throw params.error("odometrySource", "expected 'world' or 'encoder', got '" + source + "'");
  }
  return source == "encoder";
}

void OdometryPublisher::advertise(ros::NodeHandle& nh, const std::string& topic) {
  pub_ = nh.advertise<nav_msgs::Odometry>(topic, 10);
}

void OdometryPublisher::publishWorldToOdom(bool encoder_odometry, const cp::Pose& start_pose) const {
  if (!options_.publish_world_to_odom_tf || !options_.publish_odom_tf) return;
  const cp::Pose odom_in_world = encoder_odometry ? start_pose : cp::Pose();
  ctx_.static_tf->sendTransform(transformMessage(ctx_.now(), "world", options_.odom_frame, odom_in_world));
}

void OdometryPublisher::publish(const cp::Pose& base_in_odom, const cp::Twist& twist_in_base) const {
  nav_msgs::Odometry odom;
  odom.header.stamp = ctx_.now();
  odom.header.frame_id = options_.odom_frame;
  odom.child_frame_id = options_.base_frame;
  odom.pose.pose.position.x = base_in_odom.position.x;
  odom.pose.pose.position.y = base_in_odom.position.y;
  odom.pose.pose.position.z = base_in_odom.position.z;
  odom.pose.pose.orientation = toMsg(base_in_odom.orientation);
  odom.twist.twist.linear.x = twist_in_base.linear_mps.x;
  odom.twist.twist.linear.y = twist_in_base.linear_mps.y;
  odom.twist.twist.linear.z = twist_in_base.linear_mps.z;
  odom.twist.twist.angular.x = twist_in_base.angular_radps.x;
  odom.twist.twist.angular.y = twist_in_base.angular_radps.y;
  odom.twist.twist.angular.z = twist_in_base.angular_radps.z;
  // Planar motion: z, roll and pitch unknown.
  const double cov[6] = {options_.covariance_x, options_.covariance_y, 1e12, 1e12, 1e12, options_.covariance_yaw};
  for (int i = 0; i < 6; ++i) {
    odom.pose.covariance[i * 7] = cov[i];
    odom.twist.covariance[i * 7] = cov[i];
  }
  pub_.publish(odom);
  if (options_.publish_odom_tf) {
    ctx_.tf->sendTransform(transformMessage(odom.header.stamp, options_.odom_frame, options_.base_frame, base_in_odom));
  }
}

}  // namespace conde_sim
