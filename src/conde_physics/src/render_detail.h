// Helpers the camera model, the scene and the renderer share (private to conde_physics).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "conde_physics/camera_model.h"
#include "conde_physics/render_scene.h"

namespace conde_physics {
namespace render_detail {

constexpr double kPi = 3.14159265358979323846;

// A value as messages quote it (shortest form).
inline std::string text(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

inline std::uint8_t toByte(double unit_value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(unit_value, 0.0, 1.0) * 255.0));
}

inline void checkImage(const RgbImage& image, const std::string& what) {
  if (image.width < 0 || image.height < 0 || image.data.size() != static_cast<size_t>(image.width) * image.height * 3)
    throw std::invalid_argument(what + ": image data size " + std::to_string(image.data.size()) + " does not match " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) + " RGB");
}

inline void checkImageSize(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0)
    throw std::invalid_argument("camera image size must be positive (got " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + ")");
}

// plumb_bob: normalised undistorted (x, y) -> normalised distorted (xd, yd) (camera_model.cpp).
void distort(const LensDistortion& d, double x, double y, double& xd, double& yd);
// Inverts the distortion by damped Newton steps from (xd, yd). False when it does not converge
// or lands where the lens model folds over (Jacobian not positive), i.e. no unique ray exists.
bool undistort(const LensDistortion& d, double xd, double yd, double& x, double& y);

}  // namespace render_detail
}  // namespace conde_physics
