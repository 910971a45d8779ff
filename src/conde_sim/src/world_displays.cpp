#include "conde_sim/world_displays.h"

#include "conde_sim/image_conversion.h"

namespace conde_sim {

WorldDisplays::WorldDisplays(ros::NodeHandle& nh, Simulation& sim, int max_width_px)
    : sim_(sim), max_width_px_(max_width_px) {
  const auto& objects = sim.world().objects;
  for (size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].display_topic.empty()) continue;
    sim.renderScene();  // builds the scene, whose object i is world object i
    auto display = std::make_unique<Display>();
    display->scene_object = static_cast<int>(i);
    Display* raw = display.get();
    display->sub = nh.subscribe<sensor_msgs::Image>(
        objects[i].display_topic, 1, [this, raw](const sensor_msgs::ImageConstPtr& msg) { onImage(raw, msg); });
    ROS_INFO("conde_sim: display panel '%s' shows %s", objects[i].name.c_str(), display->sub.getTopic().c_str());
    displays_.push_back(std::move(display));
  }
}

void WorldDisplays::onImage(Display* display, const sensor_msgs::ImageConstPtr& msg) {
  const std::string problem = imageMessageToRgb(*msg, max_width_px_, display->image);
  if (!problem.empty()) {
    ROS_WARN_THROTTLE(5.0, "conde_sim: display panel %s: image ignored: %s", display->sub.getTopic().c_str(),
                      problem.c_str());
    return;
  }
  sim_.renderScene().setObjectImage(display->scene_object, display->image);
}

}  // namespace conde_sim
