// sensor_msgs/Image <-> the renderer's RgbImage.
#pragma once

#include <sensor_msgs/Image.h>

#include <string>

#include "conde_physics/camera_renderer.h"

namespace conde_sim {

// Converts an image of encoding rgb8, bgr8, rgba8, bgra8 or mono8 to RGB and, when it is wider
// than max_width_px, shrinks it (area averaging) to that width keeping its aspect ratio.
// Returns "" on success, else why the image was refused, e.g.
// "unsupported encoding '16UC1' (expected rgb8, bgr8, rgba8, bgra8 or mono8)".
std::string imageMessageToRgb(const sensor_msgs::Image& msg, int max_width_px, conde_physics::RgbImage& out);

}  // namespace conde_sim
