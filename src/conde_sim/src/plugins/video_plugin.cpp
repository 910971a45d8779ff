// libgazebo_ros_video.so: a display panel. The box of the link in <gazebo reference="link">
// shows, on its local +z face, the last sensor_msgs/Image received on <topicName> (upright and
// not mirrored for a viewer in front of that face, as in Gazebo), until the next one arrives.
//
//   <gazebo reference="screen_link">
//     <plugin name="display" filename="libgazebo_ros_video.so">
//       <robotNamespace>monitor1</robotNamespace> <topicName>image1</topicName>
//       <height>120</height> <width>160</width>
//     </plugin>
//   </gazebo>
//
// Gazebo stretches every image to height x width; here the image keeps its own resolution (at
// most `width` pixels wide, shrunk by area averaging) and is stretched over the face when drawn.
// World-file boxes with `display_topic` get the same behaviour without a URDF (world_displays).
#include "conde_sim/image_conversion.h"
#include "conde_sim/plugin.h"

namespace conde_sim {
namespace {

class VideoPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const std::string link = params.requireReferenceLink();
    const auto& robot = ctx_.sim->robot(ctx_.robot);
    if (robot.model.bodyIndex(link) < 0) {
      throw PluginError(params.where() + ": robot '" + robot.spec.name + "' has no link '" + link + "'");
    }
    for (int index : ctx_.sim->renderObjectsOfLink(ctx_.robot, link)) {
      if (ctx_.sim->renderScene().object(index).shape == cp::RenderShape::kBox) {
        scene_object_ = index;
        break;
      }
    }
    if (scene_object_ < 0) {
      throw PluginError(params.where() + ": link '" + link + "' has no box collision to show the video on");
    }
    const std::string topic = params.getString("topicName", "image_raw");
    max_width_px_ = static_cast<int>(params.getDouble("width", 320));
    params.getDouble("height", 240);
    if (max_width_px_ <= 0) throw params.error("width", "must be positive");
    sub_ = nh.subscribe(topic, 1, &VideoPlugin::onImage, this);
    ROS_INFO("%s: display panel on link %s shows %s", robot.spec.name.c_str(), link.c_str(), sub_.getTopic().c_str());
  }

 private:
  void onImage(const sensor_msgs::ImageConstPtr& msg) {
    const std::string problem = imageMessageToRgb(*msg, max_width_px_, image_);
    if (!problem.empty()) {
      ROS_WARN_THROTTLE(5.0, "display panel %s: image ignored: %s", sub_.getTopic().c_str(), problem.c_str());
      return;
    }
    ctx_.sim->renderScene().setObjectImage(scene_object_, image_);
  }

  int scene_object_ = -1;
  int max_width_px_ = 320;
  cp::RgbImage image_;
  ros::Subscriber sub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeVideoPlugin() { return std::make_unique<VideoPlugin>(); }

}  // namespace conde_sim
