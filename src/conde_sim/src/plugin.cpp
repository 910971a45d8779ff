#include "conde_sim/plugin.h"

namespace conde_sim {

ros::NodeHandle PluginContext::nodeHandle(PluginParams& params) const {
  if (params.has("robotNamespace")) {
    const std::string ns = params.getString("robotNamespace", "");
    return ros::NodeHandle(ns.empty() || ns[0] != '/' ? "/" + ns : ns);
  }
  return robot_nh;
}

std::string PluginContext::frame(const std::string& name) const {
  const std::string& prefix = sim->robot(robot).spec.frame_prefix;
  return prefix.empty() ? name : prefix + "/" + name;
}

std::string PluginContext::frameParam(PluginParams& params, const std::string& fallback) const {
  std::string name = params.getString("frameName", fallback);
  if (name.size() > 1 && name[0] == '/') name = name.substr(1);
  return frame(name);
}

std::uint32_t PluginContext::noiseSeed(const std::string& sensor_name) const {
  return static_cast<std::uint32_t>(std::hash<std::string>()(sim->robot(robot).spec.name + "/" + sensor_name));
}

const std::map<std::string, PluginFactory>& pluginRegistry() {
  static const std::map<std::string, PluginFactory> registry = {
      {"libgazebo_ros_diff_drive.so", makeDiffDrivePlugin},
      {"libgazebo_ros_joint_state_publisher.so", makeJointStatePublisherPlugin},
      {"libgazebo_ros_p3d.so", makeGroundTruthPlugin},
      {"libgazebo_ros_imu_sensor.so", makeImuSensorPlugin},
      {"libgazebo_ros_camera.so", makeCameraPlugin},
      {"libgazebo_ros_depth_camera.so", makeDepthCameraPlugin},
      {"libgazebo_ros_openni_kinect.so", makeOpenniKinectPlugin},
      {"libgazebo_ros_multicamera.so", makeMultiCameraPlugin},
      {"libgazebo_ros_video.so", makeVideoPlugin},
      {"libgazebo_ros_laser.so", makeLaserPlugin},
      {"libgazebo_ros_gpu_laser.so", makeLaserPlugin},
      {"libgazebo_ros_control.so", makeRosControlPlugin},
      {"libconde_ackermann_drive.so", makeAckermannDrivePlugin},
      {"libgazebo_ros_bumper.so", makeBumperPlugin},
      {"libgazebo_ros_imu.so", makeImuModelPlugin},
      {"libgazebo_ros_range.so", makeRangePlugin},
      {"libgazebo_ros_block_laser.so", makeBlockLaserPlugin},
      {"libgazebo_ros_skid_steer_drive.so", makeSkidSteerDrivePlugin},
      {"libgazebo_ros_planar_move.so", makePlanarMovePlugin},
      {"libgazebo_ros_force.so", makeForcePlugin},
      {"libgazebo_ros_f3d.so", makeF3dPlugin},
      {"libgazebo_ros_tricycle_drive.so", makeTricycleDrivePlugin},
      {"libgazebo_ros_joint_pose_trajectory.so", makeJointPoseTrajectoryPlugin},
      {"libgazebo_ros_ft_sensor.so", makeFtSensorPlugin},
  };
  return registry;
}

int requireJoint(const PluginContext& ctx, const PluginParams& params, const std::string& key,
                 const std::string& joint_name) {
  const int index = ctx.sim->robot(ctx.robot).model.jointIndex(joint_name);
  if (index < 0) {
    throw params.error(
        key, "robot '" + ctx.sim->robot(ctx.robot).spec.name + "' has no movable joint named '" + joint_name + "'");
  }
  return index;
}

std::string requireLink(const PluginContext& ctx, const PluginParams& params, const std::string& key,
                        const std::string& link_name) {
  int body = -1;
  conde_physics::Pose unused;
  if (!ctx.sim->robot(ctx.robot).model.linkInBody(link_name, body, unused)) {
    throw params.error(key, "robot has no link named '" + link_name + "'");
  }
  return link_name;
}

}  // namespace conde_sim
