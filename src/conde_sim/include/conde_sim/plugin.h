// Gazebo-style plugins of the simulator, and the registry that maps gazebo_ros plugin file
// names (libgazebo_ros_diff_drive.so, ...) to our implementations.
//
// Every plugin has one shape: configure() (called by load(), which keeps the context) reads all
// its parameters (each with its Gazebo default) and logs the resolved values once; beforeStep()
// runs before each physics step (commands, efforts); afterStep() after it (sensors, odometry),
// rate-limited in simulated time by an UpdateTimer (update_timer.h). The StepLoop (step_loop.h)
// calls them.
// ROS callbacks run between steps, on the node's thread, so no plugin needs a lock.
#pragma once

#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "conde_sim/plugin_params.h"
#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"

namespace conde_sim {

namespace cp = conde_physics;  // the plugins' short name for the physics layer

struct PluginContext {
  Simulation* sim = nullptr;
  int robot = -1;            // index of the robot that carries the plugin
  ros::NodeHandle robot_nh;  // the robot's namespace
  tf2_ros::TransformBroadcaster* tf = nullptr;
  tf2_ros::StaticTransformBroadcaster* static_tf = nullptr;

  // Node handle for a plugin: <robotNamespace> when given (as in gazebo_ros), else the robot's.
  ros::NodeHandle nodeHandle(PluginParams& params) const;
  // Frame name with the robot's frame prefix.
  std::string frame(const std::string& name) const;
  // <frameName> (else `fallback`) with the robot's frame prefix, without a leading '/' (tf2
  // frames have none; Gazebo users often write "/base_link").
  std::string frameParam(PluginParams& params, const std::string& fallback) const;
  // Seed of a sensor's noise: its own per robot and sensor, the same in every run.
  std::uint32_t noiseSeed(const std::string& sensor_name) const;
  ros::Time now() const { return ros::Time(sim->timeS()); }
};

// beforeStep() and afterStep() (StepHooks) run around each physics step, in the StepLoop.
class SimPlugin : public StepHooks {
 public:
  // Keeps the context (ctx_) and configures the plugin with the node handle of its topics (the
  // robot's namespace, then <robotNamespace>). Throws PluginError naming the key at fault.
  void load(const PluginContext& ctx, PluginParams& params) {
    ctx_ = ctx;
    ros::NodeHandle nh = ctx_.nodeHandle(params);
    configure(params, nh);
  }
  // After the world was reset: forget commands and integrated state.
  virtual void reset() {}

 protected:
  // Reads parameters and sets up topics on `nh`.
  virtual void configure(PluginParams& params, ros::NodeHandle& nh) = 0;

  PluginContext ctx_;
};

using PluginFactory = std::function<std::unique_ptr<SimPlugin>()>;

// Plugin file name -> factory, for every plugin the simulator implements.
const std::map<std::string, PluginFactory>& pluginRegistry();

// Joint index of `joint_name` in the context's robot, or a PluginError naming `key`.
int requireJoint(const PluginContext& ctx, const PluginParams& params, const std::string& key,
                 const std::string& joint_name);

// `link_name` (read from `key`) when the context's robot has that link (merged into a body or
// not), else a PluginError naming `key`.
std::string requireLink(const PluginContext& ctx, const PluginParams& params, const std::string& key,
                        const std::string& link_name);

// The individual plugins (defined in src/plugins/).
std::unique_ptr<SimPlugin> makeDiffDrivePlugin();
std::unique_ptr<SimPlugin> makeJointStatePublisherPlugin();
std::unique_ptr<SimPlugin> makeGroundTruthPlugin();
std::unique_ptr<SimPlugin> makeImuSensorPlugin();
std::unique_ptr<SimPlugin> makeImuModelPlugin();
std::unique_ptr<SimPlugin> makeCameraPlugin();
std::unique_ptr<SimPlugin> makeDepthCameraPlugin();
std::unique_ptr<SimPlugin> makeOpenniKinectPlugin();
std::unique_ptr<SimPlugin> makeMultiCameraPlugin();
std::unique_ptr<SimPlugin> makeVideoPlugin();
std::unique_ptr<SimPlugin> makeLaserPlugin();
std::unique_ptr<SimPlugin> makeRosControlPlugin();
std::unique_ptr<SimPlugin> makeAckermannDrivePlugin();
std::unique_ptr<SimPlugin> makeBumperPlugin();
std::unique_ptr<SimPlugin> makeRangePlugin();
std::unique_ptr<SimPlugin> makeBlockLaserPlugin();
std::unique_ptr<SimPlugin> makeSkidSteerDrivePlugin();
std::unique_ptr<SimPlugin> makePlanarMovePlugin();
std::unique_ptr<SimPlugin> makeForcePlugin();
std::unique_ptr<SimPlugin> makeF3dPlugin();
std::unique_ptr<SimPlugin> makeTricycleDrivePlugin();
std::unique_ptr<SimPlugin> makeJointPoseTrajectoryPlugin();
std::unique_ptr<SimPlugin> makeFtSensorPlugin();

}  // namespace conde_sim
