// Display panels of the world file: every box with `display_topic` shows, on its +z face, the
// last sensor_msgs/Image received on that topic (as libgazebo_ros_video does for a link).
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <memory>
#include <vector>

#include "conde_physics/camera_renderer.h"
#include "conde_sim/simulation.h"

namespace conde_sim {

class WorldDisplays {
 public:
  // Subscribes to every display topic of the simulation's world. Images wider than
  // max_width_px are shrunk (area averaging) before they are drawn.
  WorldDisplays(ros::NodeHandle& nh, Simulation& sim, int max_width_px = 320);
  int count() const { return static_cast<int>(displays_.size()); }

 private:
  struct Display {
    int scene_object = -1;
    ros::Subscriber sub;
    conde_physics::RgbImage image;
  };
  void onImage(Display* display, const sensor_msgs::ImageConstPtr& msg);

  Simulation& sim_;
  int max_width_px_;
  std::vector<std::unique_ptr<Display>> displays_;
};

}  // namespace conde_sim
