// libgazebo_ros_block_laser.so: sensor_msgs/PointCloud of a 2-D grid of rays (<sensor type="ray">
// with <horizontal> and <vertical> samples), e.g. a tilting or multi-line laser.
//
//   <gazebo reference="block_link"><sensor type="ray" name="block">
//     <update_rate>10</update_rate>
//     <ray>
//       <scan><horizontal><samples>32</samples><min_angle>-0.5</min_angle><max_angle>0.5</max_angle></horizontal>
//             <vertical><samples>8</samples><min_angle>-0.2</min_angle><max_angle>0.2</max_angle></vertical></scan>
//       <range><min>0.05</min><max>5.0</max></range>
//     </ray>
//     <plugin name="block_laser" filename="libgazebo_ros_block_laser.so">
//       <topicName>points</topicName> <frameName>block_link</frameName>
//       <gaussianNoise>0.0</gaussianNoise> <hokuyoMinIntensity>101</hokuyoMinIntensity> <updateRate>10</updateRate>
//     </plugin></sensor></gazebo>
//
// As Gazebo's gazebo_ros_block_laser: one point per ray, row by row (vertical outer, from
// <vertical><min_angle> up; horizontal inner, from <horizontal><min_angle> counter-clockwise), at
// range r along the ray (r cos pitch cos yaw, r cos pitch sin yaw, r sin pitch) in the sensor
// frame; <gaussianNoise> [m] added to each coordinate of a return; one channel of intensities.
// Rays are cast at samples x resolution directly, so Gazebo's interpolation between rays is not
// needed. Rate: rayPluginRateHz(). <hokuyoMinIntensity> is accepted without effect (Gazebo only
// logs it). Differences: a ray with no return within range gives a point with NaN coordinates
// (Gazebo: +inf, or NaN where a direction component is 0), which rviz and PCL skip, and the
// cloud keeps its grid size; the channel is named "intensity" and holds 0 (no retro-reflective
// surfaces here; Gazebo leaves the name empty); topicName defaults to "block_laser" and frameName
// to the sensor's link (Gazebo: "/world" for both); nothing is cast while nobody subscribes.
#include <sensor_msgs/PointCloud.h>

#include <cmath>
#include <limits>

#include "conde_sim/gaussian_noise.h"
#include "conde_sim/laser_scanner.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ray_sdf.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class BlockLaserPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    LaserScanConfig rays = rayFromSdf(params, ctx_.sim->robot(ctx_.robot).model, /*vertical_allowed=*/true);
    rays.noise_seed = ctx_.noiseSeed(params.sensorName());
    point_noise_ = GaussianNoise(rayPluginNoiseStddev(params), rays.noise_seed + 1);
    timer_ = UpdateTimer(rayPluginRateHz(params), ctx_.sim->stepS());
    params.getDouble("hokuyoMinIntensity", 101);  // checked, then unused (Gazebo only logs it)
    params.ignore({"hokuyoMinIntensity"});
    const std::string topic = params.getString("topicName", "block_laser");
    msg_.header.frame_id = ctx_.frameParam(params, rays.link);
    params.ignore({"alwaysOn", "visualize"});
    scanner_ = std::make_unique<LaserScanner>(*ctx_.sim, ctx_.robot, rays);
    const size_t n = static_cast<size_t>(rays.beam_count) * rays.vertical_count;
    msg_.points.resize(n);
    msg_.channels.resize(1);
    msg_.channels[0].name = "intensity";
    msg_.channels[0].values.assign(n, 0.0f);
    pub_ = nh.advertise<sensor_msgs::PointCloud>(topic, 10);
    ROS_INFO("%s: block laser '%s' on link %s: %d x %d rays, %.3f..%.3f m, noise %.4f m, %s in frame %s",
             ctx_.sim->robot(ctx_.robot).spec.name.c_str(), params.sensorName().c_str(), rays.link.c_str(),
             rays.beam_count, rays.vertical_count, rays.min_range_m, rays.max_range_m, point_noise_.stddev(),
             pub_.getTopic().c_str(), msg_.header.frame_id.c_str());
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    const std::vector<float>& ranges = scanner_->scan();
    for (size_t k = 0; k < ranges.size(); ++k) {
      geometry_msgs::Point32& p = msg_.points[k];
      if (!std::isfinite(ranges[k])) {
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      const cp::Vec3 point = scanner_->directionInSensor(static_cast<int>(k)) * ranges[k];
      p.x = static_cast<float>(point.x + point_noise_());
      p.y = static_cast<float>(point.y + point_noise_());
      p.z = static_cast<float>(point.z + point_noise_());
    }
    msg_.header.stamp = ctx_.now();
    pub_.publish(msg_);
  }

 private:
  std::unique_ptr<LaserScanner> scanner_;
  GaussianNoise point_noise_;  // [m] on each coordinate of a return
  UpdateTimer timer_;
  sensor_msgs::PointCloud msg_;
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeBlockLaserPlugin() { return std::make_unique<BlockLaserPlugin>(); }

}  // namespace conde_sim
