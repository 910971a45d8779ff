#include "conde_sim/image_conversion.h"

#include <opencv2/imgproc.hpp>

namespace conde_sim {

std::string imageMessageToRgb(const sensor_msgs::Image& msg, int max_width_px, conde_physics::RgbImage& out) {
  int channels = 0;
  int to_rgb = -1;  // cv::cvtColor code, -1 = already RGB
  if (msg.encoding == "rgb8") {
    channels = 3;
  } else if (msg.encoding == "bgr8") {
    channels = 3, to_rgb = cv::COLOR_BGR2RGB;
  } else if (msg.encoding == "rgba8") {
    channels = 4, to_rgb = cv::COLOR_RGBA2RGB;
  } else if (msg.encoding == "bgra8") {
    channels = 4, to_rgb = cv::COLOR_BGRA2RGB;
  } else if (msg.encoding == "mono8") {
    channels = 1, to_rgb = cv::COLOR_GRAY2RGB;
  } else {
    return "unsupported encoding '" + msg.encoding + "' (expected rgb8, bgr8, rgba8, bgra8 or mono8)";
  }
  if (msg.width == 0 || msg.height == 0) return "empty image (0 pixels)";
  if (msg.step < msg.width * channels || msg.data.size() < static_cast<size_t>(msg.step) * msg.height) {
    return "image data too short for " + std::to_string(msg.width) + "x" + std::to_string(msg.height) + " " +
           msg.encoding + " (step " + std::to_string(msg.step) + ", " + std::to_string(msg.data.size()) + " bytes)";
  }
  const cv::Mat in(static_cast<int>(msg.height), static_cast<int>(msg.width), CV_8UC(channels),
                   const_cast<std::uint8_t*>(msg.data.data()), msg.step);
  cv::Mat rgb;
  if (to_rgb >= 0) {
    cv::cvtColor(in, rgb, to_rgb);
  } else {
    rgb = in;
  }
  if (max_width_px > 0 && rgb.cols > max_width_px) {
    const int height = std::max(1, static_cast<int>(std::lround(rgb.rows * double(max_width_px) / rgb.cols)));
    cv::Mat small;
    cv::resize(rgb, small, cv::Size(max_width_px, height), 0, 0, cv::INTER_AREA);
    rgb = small;
  }
  out.resize(rgb.cols, rgb.rows);
  for (int v = 0; v < rgb.rows; ++v) {
    std::copy(rgb.ptr<std::uint8_t>(v), rgb.ptr<std::uint8_t>(v) + rgb.cols * 3, out.pixel(0, v));
  }
  return "";
}

}  // namespace conde_sim
