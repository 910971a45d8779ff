// libgazebo_ros_p3d.so: ground-truth pose and velocity of one link as nav_msgs/Odometry.
//
//   <gazebo><plugin name="ground_truth" filename="libgazebo_ros_p3d.so">
//     <bodyName>base_footprint</bodyName> <topicName>ground_truth/odom</topicName>
//     <frameName>world</frameName> <updateRate>50</updateRate> <gaussianNoise>0</gaussianNoise>
//   </plugin></gazebo>
// As in gazebo_ros_p3d, the twist is in the reference frame (world), not the body frame, and
// <frameName> may only be "world" or "map" here (a link as reference frame is not supported).
#include <nav_msgs/Odometry.h>

#include <random>

#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class GroundTruthPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    body_ = requireLink(ctx_, params, "bodyName", params.requireString("bodyName"));
    const std::string topic = params.requireString("topicName");
    frame_ = params.getString("frameName", "world");
    if (frame_ != "world" && frame_ != "map" && frame_ != "/world" && frame_ != "/map") {
      throw params.error("frameName", "only 'world' or 'map' are supported, got '" + frame_ + "'");
    }
    const double rate_hz = params.getDouble("updateRate", 0.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    offset_ = cp::Pose(params.getVec3("xyzOffsets", cp::Vec3()), cp::Quat());
    const cp::Vec3 rpy = params.getVec3("rpyOffsets", cp::Vec3());
    offset_.orientation = cp::Quat::fromRpy(rpy.x, rpy.y, rpy.z);
    noise_stddev_ = params.getDouble("gaussianNoise", 0.0);
    if (noise_stddev_ < 0) throw params.error("gaussianNoise", "must not be negative");
    params.ignore({"alwaysOn"});
    pub_ = nh.advertise<nav_msgs::Odometry>(topic, 10);
    ROS_INFO("%s: ground truth of link %s on %s in frame %s at %.1f Hz", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
             body_.c_str(), pub_.getTopic().c_str(), frame_.c_str(), rate_hz);
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    // Offsets as in gazebo_ros_p3d: a pose in the reference frame applied to the body pose.
    const cp::Pose pose = offset_ * ctx_.sim->linkPose(ctx_.robot, body_);
    const cp::Twist twist = ctx_.sim->linkTwist(ctx_.robot, body_);
    nav_msgs::Odometry msg;
    msg.header.stamp = ctx_.now();
    msg.header.frame_id = frame_[0] == '/' ? frame_.substr(1) : frame_;
    msg.child_frame_id = ctx_.frame(body_);
    msg.pose.pose.position.x = pose.position.x + noise();
    msg.pose.pose.position.y = pose.position.y + noise();
    msg.pose.pose.position.z = pose.position.z + noise();
    msg.pose.pose.orientation = toMsg(pose.orientation);
    msg.twist.twist.linear.x = twist.linear_mps.x + noise();
    msg.twist.twist.linear.y = twist.linear_mps.y + noise();
    msg.twist.twist.linear.z = twist.linear_mps.z + noise();
    msg.twist.twist.angular.x = twist.angular_radps.x + noise();
    msg.twist.twist.angular.y = twist.angular_radps.y + noise();
    msg.twist.twist.angular.z = twist.angular_radps.z + noise();
    const double variance = noise_stddev_ * noise_stddev_;
    for (int i = 0; i < 6; ++i) {
      msg.pose.covariance[i * 7] = variance;
      msg.twist.covariance[i * 7] = variance;
    }
    pub_.publish(msg);
  }

 private:
  double noise() { return noise_stddev_ > 0 ? gauss_(rng_) * noise_stddev_ : 0.0; }

  std::string body_, frame_;
  cp::Pose offset_;
  double noise_stddev_ = 0.0;
  UpdateTimer timer_;
  std::mt19937 rng_{0};  // fixed seed: runs are repeatable
  std::normal_distribution<double> gauss_{0.0, 1.0};
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeGroundTruthPlugin() { return std::make_unique<GroundTruthPlugin>(); }

}  // namespace conde_sim
