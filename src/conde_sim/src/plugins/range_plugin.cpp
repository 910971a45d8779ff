// libgazebo_ros_range.so: sensor_msgs/Range of a sonar or infrared sensor, the nearest return of
// the rays of a <sensor type="ray"> (a small grid of them spans the beam's cone).
//
//   <gazebo reference="sonar_link"><sensor type="ray" name="sonar">
//     <update_rate>10</update_rate>
//     <ray>
//       <scan><horizontal><samples>5</samples><min_angle>-0.1</min_angle><max_angle>0.1</max_angle></horizontal>
//             <vertical><samples>5</samples><min_angle>-0.1</min_angle><max_angle>0.1</max_angle></vertical></scan>
//       <range><min>0.02</min><max>4.0</max><resolution>0.01</resolution></range>
//     </ray>
//     <plugin name="sonar" filename="libgazebo_ros_range.so">
//       <topicName>sonar</topicName> <frameName>sonar_link</frameName> <radiation>ultrasound</radiation>
//       <fov>0.2</fov> <gaussianNoise>0.005</gaussianNoise> <updateRate>10</updateRate>
//     </plugin></sensor></gazebo>
//
// As Gazebo's gazebo_ros_range: range = the minimum over all rays, the plugin's <gaussianNoise>
// [m] is added to that minimum (and the sum kept within [min_range, max_range]); radiation
// "ultrasound" (default) or "infrared"; field_of_view = <fov> [rad] (default 0.05) as written,
// not the span of the rays; min_range / max_range from <ray><range>; rate: rayPluginRateHz().
// Differences: no return within max_range is +inf (REP 117; Gazebo publishes the float maximum);
// topicName defaults to "range" in the robot's namespace and frameName to the sensor's link
// (Gazebo: "/range" and "/world"); a radiation other than the two is an error (Gazebo takes it for
// infrared); nothing is cast while nobody subscribes.
#include <sensor_msgs/Range.h>

#include <algorithm>
#include <limits>

#include "conde_sim/gaussian_noise.h"
#include "conde_sim/laser_scanner.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ray_sdf.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class RangePlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    LaserScanConfig rays = rayFromSdf(params, ctx_.sim->robot(ctx_.robot).model, /*vertical_allowed=*/true);
    // The rays carry the sensor's own <noise>; the plugin's is added once, to their minimum.
    noise_ = GaussianNoise(rayPluginNoiseStddev(params), ctx_.noiseSeed(params.sensorName() + "/range"));
    timer_ = UpdateTimer(rayPluginRateHz(params), ctx_.sim->stepS());
    const std::string radiation = params.getString("radiation", "ultrasound");
    if (radiation == "ultrasound") {
      msg_.radiation_type = sensor_msgs::Range::ULTRASOUND;
    } else if (radiation == "infrared") {
      msg_.radiation_type = sensor_msgs::Range::INFRARED;
    } else {
      throw params.error("radiation", "expected ultrasound or infrared, got '" + radiation + "'");
    }
    const double fov_rad = params.getDouble("fov", 0.05);
    if (!(fov_rad >= 0)) throw params.error("fov", "must not be negative");
    const std::string topic = params.getString("topicName", "range");
    msg_.header.frame_id = ctx_.frameParam(params, rays.link);
    params.ignore({"alwaysOn", "visualize"});
    msg_.field_of_view = static_cast<float>(fov_rad);
    msg_.min_range = static_cast<float>(rays.min_range_m);
    msg_.max_range = static_cast<float>(rays.max_range_m);
    rays.noise_seed = ctx_.noiseSeed(params.sensorName());
    scanner_ = std::make_unique<LaserScanner>(*ctx_.sim, ctx_.robot, rays);
    pub_ = nh.advertise<sensor_msgs::Range>(topic, 10);
    ROS_INFO("%s: range sensor '%s' (%s) on link %s: %d x %d rays, %.3f..%.3f m, fov %.3f rad, %.1f Hz, %s in frame %s",
             ctx_.sim->robot(ctx_.robot).spec.name.c_str(), params.sensorName().c_str(), radiation.c_str(),
             rays.link.c_str(), rays.beam_count, rays.vertical_count, rays.min_range_m, rays.max_range_m, fov_rad,
             timer_.rateHz(ctx_.sim->stepS()), pub_.getTopic().c_str(), msg_.header.frame_id.c_str());
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    const std::vector<float>& ranges = scanner_->scan();
    float range_m = *std::min_element(ranges.begin(), ranges.end());  // +inf when nothing is in range
    if (std::isfinite(range_m) && noise_.stddev() > 0) {
      range_m = std::clamp(static_cast<float>(range_m + noise_()), msg_.min_range, msg_.max_range);
    }
    msg_.range = range_m;
    msg_.header.stamp = ctx_.now();
    pub_.publish(msg_);
  }

 private:
  sensor_msgs::Range msg_;
  ros::Publisher pub_;
  UpdateTimer timer_;
  std::unique_ptr<LaserScanner> scanner_;
  GaussianNoise noise_;  // [m], added to the nearest return
};

}  // namespace

std::unique_ptr<SimPlugin> makeRangePlugin() { return std::make_unique<RangePlugin>(); }

}  // namespace conde_sim
