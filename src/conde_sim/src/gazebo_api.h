// Gazebo's ROS 1 interface (gazebo_ros_api_plugin) on the simulator node: the /gazebo/ services
// and topics, field for field (gazebo_msgs), on the Simulation's models (robots and dynamic
// world objects, simulation.h).
//
// Services: get_model_state, set_model_state, get_link_state, set_link_state,
//   get_world_properties, get_model_properties, get_physics_properties, reset_simulation,
//   reset_world, pause_physics, unpause_physics, apply_body_wrench, clear_body_wrenches,
//   spawn_urdf_model, spawn_sdf_model (an SDF <model> converted as the SDF world loader does,
//   conde_physics/sdf_world.h; a URDF given to it is spawned as by spawn_urdf_model), delete_model.
// Topics: model_states, link_states (gazebo_msgs/*States, at ~gazebo_states_rate_hz of
//   simulated time, only while someone subscribes); set_model_state, set_link_state (input).
// Beside them, on the node's private namespace: ~model_poses (tf2_msgs/TFMessage), the same
//   models' poses (world -> model, child_frame_id = model name) stamped with the simulated time of
//   the step, at its own rate (~model_poses_rate_hz, by default the states') while someone
//   subscribes: model_states has no stamp, so a reader (the referee) cannot tell which step it shows.
//
// Semantics as in Gazebo: reference frames "" or "world" are the world, a model name or
// "model::link" a frame of the simulation; twists are in the reference frame's axes (world
// for ""); links are named "model::link"; a model's pose is its root link's. Differences:
// reset_simulation resets the world but not the simulated time; the pose and twist of a
// model set with set_model_state are those of a rigid body (every link moves with it).
//
// Threads: service callbacks run on the node's service thread and hand their work to the step
// loop (SimHost::runOnLoop), the only thread that touches the simulation; the input topics and
// the StepHooks run on the loop's thread.
#pragma once

#include <gazebo_msgs/ApplyBodyWrench.h>
#include <gazebo_msgs/BodyRequest.h>
#include <gazebo_msgs/DeleteModel.h>
#include <gazebo_msgs/GetLinkState.h>
#include <gazebo_msgs/GetModelProperties.h>
#include <gazebo_msgs/GetModelState.h>
#include <gazebo_msgs/GetPhysicsProperties.h>
#include <gazebo_msgs/GetWorldProperties.h>
#include <gazebo_msgs/LinkState.h>
#include <gazebo_msgs/ModelState.h>
#include <gazebo_msgs/SetLinkState.h>
#include <gazebo_msgs/SetModelState.h>
#include <gazebo_msgs/SpawnModel.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {

// What the interface needs from the node.
class SimHost {
 public:
  virtual ~SimHost() = default;
  // From the service thread: runs `task` on the step loop's thread between two steps and
  // returns when it is done (false when ROS shut down first).
  virtual bool runOnLoop(const std::function<void()>& task) = 0;
  // From the service thread.
  virtual void requestPause(bool paused) = 0;
  // On the loop's thread: the world back to its start, plugins reset.
  virtual void resetWorldNow() = 0;
  // On the loop's thread: adds a robot and loads its plugins; returns its index. Throws
  // std::exception (the robot is not added then).
  virtual int spawnRobot(const RobotSpec& spec) = 0;
  // On the loop's thread: unloads a robot's plugins and removes it.
  virtual void deleteRobot(int robot) = 0;
  virtual bool paused() const = 0;
  virtual double realTimeFactor() const = 0;
};

class GazeboApi : public StepHooks {
 public:
  // Advertises everything under `ns` (e.g. "/gazebo"); services on `service_nh`'s queue.
  // `states_rate_hz`: model_states and link_states per simulated second.
  // states_rate_hz: model_states and link_states per simulated second; poses_rate_hz: ~model_poses.
  GazeboApi(SimHost& host, Simulation& sim, const std::string& ns, ros::NodeHandle& service_nh, double states_rate_hz,
            double poses_rate_hz);

  void beforeStep() override;  // body wrenches
  void afterStep() override;   // model_states, link_states
  // Forgets the wrenches on a model that is gone.
  void forgetModel(const std::string& model_name);

 private:
  struct Frame {  // a reference frame's state in the world
    conde_physics::Pose pose;
    conde_physics::Twist twist;
  };
  struct Wrench {
    std::string model, link;
    conde_physics::Vec3 force_N, torque_Nm;  // world axes
    conde_physics::Vec3 point_in_link;       // where the force acts, in the link frame
    double start_s = 0.0, end_s = 0.0;       // simulated time; end < 0: until cleared
  };

  // "" / "world" / "map" = the world; a model name; "model::link". False when unknown.
  bool frameState(const std::string& frame, Frame& state) const;
  // "model::link" into its parts; false when not of that form or unknown.
  bool findLink(const std::string& scoped, ModelRef& model, std::string& link) const;
  // The state of `link` of `model` ("" = the model's root) seen from `frame`, as messages.
  void stateSeenFrom(const Frame& frame, const ModelRef& model, const std::string& link, geometry_msgs::Pose& pose,
                     geometry_msgs::Twist& twist) const;
  // A state to set, given in `reference_frame`, into the world; false with Gazebo's status
  // message ("<service>: ...") when not finite or when the frame (named `frame_field` in the
  // message) does not exist.
  bool stateInWorld(const std::string& service, const std::string& frame_field, const std::string& reference_frame,
                    const geometry_msgs::Pose& pose_msg, const geometry_msgs::Twist& twist_msg,
                    conde_physics::Pose& pose, conde_physics::Twist& twist, std::string& message) const;
  // True on success; `message` as Gazebo's status_message.
  bool setModelState(const gazebo_msgs::ModelState& state, std::string& message);
  // True on success; `message` as Gazebo's status_message.
  bool setLinkState(const gazebo_msgs::LinkState& state, std::string& message);

  bool onGetModelState(gazebo_msgs::GetModelState::Request& req, gazebo_msgs::GetModelState::Response& res);
  bool onSetModelState(gazebo_msgs::SetModelState::Request& req, gazebo_msgs::SetModelState::Response& res);
  bool onGetLinkState(gazebo_msgs::GetLinkState::Request& req, gazebo_msgs::GetLinkState::Response& res);
  bool onSetLinkState(gazebo_msgs::SetLinkState::Request& req, gazebo_msgs::SetLinkState::Response& res);
  bool onGetWorldProperties(gazebo_msgs::GetWorldProperties::Request& req,
                            gazebo_msgs::GetWorldProperties::Response& res);
  bool onGetModelProperties(gazebo_msgs::GetModelProperties::Request& req,
                            gazebo_msgs::GetModelProperties::Response& res);
  bool onGetPhysicsProperties(gazebo_msgs::GetPhysicsProperties::Request& req,
                              gazebo_msgs::GetPhysicsProperties::Response& res);
  bool onResetWorld(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onUnpause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onApplyBodyWrench(gazebo_msgs::ApplyBodyWrench::Request& req, gazebo_msgs::ApplyBodyWrench::Response& res);
  bool onClearBodyWrenches(gazebo_msgs::BodyRequest::Request& req, gazebo_msgs::BodyRequest::Response& res);
  bool onSpawnUrdf(gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res);
  bool onSpawnSdf(gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res);
  // Checks both spawn services make first (loop thread): false with Gazebo's status message;
  // `spawn_pose` is the initial pose in the world.
  bool spawnAllowed(const gazebo_msgs::SpawnModel::Request& req, conde_physics::Pose& spawn_pose,
                    std::string& message) const;
  void spawnUrdf(const gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res);
  bool onDeleteModel(gazebo_msgs::DeleteModel::Request& req, gazebo_msgs::DeleteModel::Response& res);
  // The set_model_state / set_link_state topics: as the service, a rejected state is a throttled warning.
  template <typename State, bool (GazeboApi::*set)(const State&, std::string&)>
  void onStateTopic(const boost::shared_ptr<const State>& msg) {
    std::string message;
    if (!(this->*set)(*msg, message)) ROS_WARN_THROTTLE(1.0, "%s", message.c_str());
  }

  SimHost& host_;
  Simulation& sim_;
  std::vector<ros::ServiceServer> services_;
  ros::Publisher model_states_pub_, link_states_pub_, model_poses_pub_;
  ros::Subscriber model_state_sub_, link_state_sub_;
  UpdateTimer states_timer_, poses_timer_;
  std::vector<Wrench> wrenches_;  // loop thread only
  // Static SDF models spawned: their shapes are world objects, not models (loop thread only).
  std::set<std::string> static_models_;
};

}  // namespace conde_sim
