// conde_physics geometry <-> ROS geometry messages, in one place for every plugin and publisher.
#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Vector3.h>
#include <ros/time.h>

#include <cmath>
#include <string>

#include "conde_physics/math.h"

namespace conde_sim {

inline geometry_msgs::Quaternion toMsg(const conde_physics::Quat& q) {
  geometry_msgs::Quaternion m;
  m.w = q.w;
  m.x = q.x;
  m.y = q.y;
  m.z = q.z;
  return m;
}

// A message with x, y, z fields (Point, Vector3) from a vector.
template <class Msg>
Msg toXyzMsg(const conde_physics::Vec3& v) {
  Msg m;
  m.x = v.x;
  m.y = v.y;
  m.z = v.z;
  return m;
}

inline geometry_msgs::Point toPointMsg(const conde_physics::Vec3& v) { return toXyzMsg<geometry_msgs::Point>(v); }

inline geometry_msgs::Vector3 toVector3Msg(const conde_physics::Vec3& v) { return toXyzMsg<geometry_msgs::Vector3>(v); }

inline conde_physics::Vec3 fromMsg(const geometry_msgs::Vector3& v) { return conde_physics::Vec3(v.x, v.y, v.z); }
inline conde_physics::Vec3 fromMsg(const geometry_msgs::Point& v) { return conde_physics::Vec3(v.x, v.y, v.z); }
inline bool finite(const geometry_msgs::Vector3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline geometry_msgs::Pose toMsg(const conde_physics::Pose& p) {
  geometry_msgs::Pose m;
  m.position = toPointMsg(p.position);
  m.orientation = toMsg(p.orientation);
  return m;
}

// `child` at `child_in_parent` in the frame `parent`, as TF broadcasts it.
inline geometry_msgs::TransformStamped transformMessage(const ros::Time& stamp, const std::string& parent,
                                                        const std::string& child,
                                                        const conde_physics::Pose& child_in_parent) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation = toVector3Msg(child_in_parent.position);
  t.transform.rotation = toMsg(child_in_parent.orientation);
  return t;
}

}  // namespace conde_sim
