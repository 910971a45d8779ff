// The SDF <sensor type="camera"> / <sensor type="wideanglecamera"> block of a Gazebo camera (and
// the distortion keys of its gazebo_ros plugin) -> the camera model the renderer uses. No ROS.
//
//   CameraFromSdf camera = cameraFromSdf(params);   // params of the camera plugin in its <sensor>
//   CameraRenderer renderer(camera.model);          // encoding: "rgb8", "bgr8" or "mono8"
//
// Reads: <camera><image> width, height, format (R8G8B8, B8G8R8, L8; the *_INT8 names too),
// <horizontal_fov> (pinhole: (0, pi); wide angle: (0, 2 pi]), <clip> near and far, <noise>
// (gaussian, zero mean), <distortion> k1 k2 k3 p1 p2 and <center> (the principal point), <lens>
// of a wide-angle camera (type, custom_function, cutoff_angle, scale_to_hfov, env_texture_size),
// and the plugin's distortionK1..K3 / distortionT1..T2 (the same coefficients, given once).
// Throws PluginError naming the element at fault.
#pragma once

#include <string>

#include "conde_physics/camera_renderer.h"
#include "conde_sim/plugin_params.h"

namespace conde_sim {

struct CameraFromSdf {
  conde_physics::CameraModel model;
  std::string encoding = "rgb8";      // sensor_msgs image encoding of <image><format>
  std::string lens_type = "pinhole";  // for the log: pinhole or the wide-angle lens type
  double horizontal_fov_rad = 0.0;
};

CameraFromSdf cameraFromSdf(PluginParams& params);

}  // namespace conde_sim
