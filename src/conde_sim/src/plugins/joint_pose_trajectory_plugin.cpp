// libgazebo_ros_joint_pose_trajectory.so: trajectory_msgs/JointTrajectory on <topicName> sets the
// robot's joint positions, point after point, with the keys of gazebo_ros_joint_pose_trajectory
// (ROS 1).
//
//   <gazebo><plugin name="joint_trajectory" filename="libgazebo_ros_joint_pose_trajectory.so">
//     <topicName>set_joint_trajectory</topicName> <updateRate>100</updateRate>
//   </plugin></gazebo>
//
// Each point is reached at header.stamp (or now, when the stamp is older) + its time_from_start
// and held until the next one; the last one is held. header.frame_id: "", "world", "map" or a link
// of the robot (Gazebo's reference link; anything else is refused with an error, as Gazebo does).
// Differences from Gazebo, on purpose: Gazebo freezes physics while it plays the trajectory and
// teleports the joints, and it takes each time_from_start as the time to the *next* point (point 0
// at once, point 1 after point 0's time_from_start, ...), against the message's definition; here
// a velocity motor per joint, within the joint's URDF effort and velocity limits (joint_pose_servo.h),
// drives it to each position, with physics running, at the times the message gives: a pose is
// reached as fast as the limits allow, not at once.
// <serviceName> is accepted without effect: Gazebo builds its service only with ENABLE_SERVICE,
// which its ROS 1 packages do not define.
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "conde_sim/joint_pose_servo.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

class JointPoseTrajectoryPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const std::string topic = params.getString("topicName", "set_joint_trajectory");
    // Read as Gazebo reads it; Gazebo plays the points at every world update whatever it says.
    const double rate_hz = params.getDouble("updateRate", 0.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    params.ignore({"serviceName", "alwaysOn"});
    sub_ = nh.subscribe(topic, 100, &JointPoseTrajectoryPlugin::onTrajectory, this);
    ROS_INFO("%s: joint pose trajectories on %s", robotName().c_str(), sub_.getTopic().c_str());
  }

  void reset() override {
    points_.clear();
    servo_.reset();
    targets_.clear();
  }

  void beforeStep() override {
    if (!servo_) return;
    const double now_s = ctx_.sim->timeS();
    while (next_ < points_.size() && points_[next_].time_s <= now_s + 0.5 * ctx_.sim->stepS()) {
      targets_ = points_[next_].positions;
      ++next_;
    }
    servo_->drive(*ctx_.sim, targets_);
  }

 private:
  struct Point {
    double time_s;                  // simulated time at which it is reached
    std::vector<double> positions;  // [rad or m], in the order of the message's joint_names
  };

  std::string robotName() const { return ctx_.sim->robot(ctx_.robot).spec.name; }

  void onTrajectory(const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
    const std::string& frame = msg->header.frame_id;
    if (!frame.empty() && frame != "world" && frame != "map" && frame != "/map" &&
        !ctx_.sim->robot(ctx_.robot).model.linkInBody(frame, unused_body_, unused_pose_)) {
      ROS_ERROR(
          "%s: joint pose trajectory on %s: reference link '%s' (header.frame_id) is no link of the robot; "
          "trajectory ignored",
          robotName().c_str(), sub_.getTopic().c_str(), frame.c_str());
      return;
    }
    std::vector<int> joints;
    for (const std::string& name : msg->joint_names) {
      joints.push_back(ctx_.sim->robot(ctx_.robot).model.jointIndex(name));
      if (joints.back() < 0) {
        ROS_ERROR("%s: joint pose trajectory on %s: no movable joint named '%s'; trajectory ignored",
                  robotName().c_str(), sub_.getTopic().c_str(), name.c_str());
        return;
      }
    }
    const double start_s = std::max(msg->header.stamp.toSec(), ctx_.sim->timeS());
    std::vector<Point> points;
    for (size_t i = 0; i < msg->points.size(); ++i) {
      const auto& p = msg->points[i];
      if (p.positions.size() != joints.size()) {
        ROS_ERROR(
            "%s: joint pose trajectory on %s: point %zu has %zu positions for %zu joint names; trajectory "
            "ignored",
            robotName().c_str(), sub_.getTopic().c_str(), i, p.positions.size(), joints.size());
        return;
      }
      for (double q : p.positions) {
        if (!std::isfinite(q)) {
          ROS_ERROR("%s: joint pose trajectory on %s: point %zu has a non-finite position; trajectory ignored",
                    robotName().c_str(), sub_.getTopic().c_str(), i);
          return;
        }
      }
      points.push_back({start_s + p.time_from_start.toSec(), p.positions});
    }
    // Until the first point, the joints hold where they are.
    targets_.clear();
    for (int joint : joints)
      targets_.push_back(ctx_.sim->engine().jointPosition(ctx_.sim->robot(ctx_.robot).id, joint));
    servo_ = std::make_unique<JointPoseServo>(*ctx_.sim, ctx_.robot, std::move(joints));
    points_ = std::move(points);
    next_ = 0;
  }

  ros::Subscriber sub_;
  std::vector<Point> points_;
  size_t next_ = 0;
  // The joints of the last message's joint_names (what each moves found once per trajectory);
  // the motors hold them at targets_.
  std::unique_ptr<JointPoseServo> servo_;
  std::vector<double> targets_;  // [rad or m]
  int unused_body_ = -1;
  cp::Pose unused_pose_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeJointPoseTrajectoryPlugin() { return std::make_unique<JointPoseTrajectoryPlugin>(); }

}  // namespace conde_sim
