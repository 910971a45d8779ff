// libgazebo_ros_laser.so (and libgazebo_ros_gpu_laser.so): sensor_msgs/LaserScan from a 2D
// <sensor type="ray"> (or "gpu_ray") on a link, cast on the CPU through the physics engine.
//
//   <gazebo reference="laser"><sensor type="ray" name="lidar">
//     <pose>0 0 0 0 0 0</pose> <update_rate>40</update_rate> <visualize>false</visualize>
//     <ray>
//       <scan><horizontal><samples>1081</samples> <resolution>1</resolution>
//         <min_angle>-2.356</min_angle> <max_angle>2.356</max_angle></horizontal></scan>
//       <range><min>0.06</min> <max>10.0</max> <resolution>0.01</resolution></range>
//       <noise><type>gaussian</type> <mean>0.0</mean> <stddev>0.01</stddev></noise>
//     </ray>
//     <plugin name="lidar" filename="libgazebo_ros_laser.so">
//       <topicName>scan</topicName> <frameName>laser</frameName>
//     </plugin></sensor></gazebo>
//
// As Gazebo: samples x resolution beams from min_angle to max_angle (angle_increment = span /
// (beams - 1)), rays start at <range><min>, update_rate 0 = every physics step, the scan is
// taken from <pose> in the link but stamped in <frameName>. <range><resolution> is accepted and
// not applied (Gazebo does not apply it either); <vertical> must have 1 sample (2D only).
// Differences: the defaults of topicName / frameName are `scan` / the sensor's link (Gazebo:
// `/world` for both); no return within range is +inf (REP 117); <gaussianNoise> in the plugin
// (from gazebo_ros_block_laser) adds zero-mean noise of that standard deviation to the
// sensor's own <noise>; the frame gets the robot's frame prefix; nothing is cast while nobody
// subscribes. The stamp is the simulated time of the scan.
#include <sensor_msgs/LaserScan.h>

#include <cmath>
#include <functional>

#include "conde_sim/laser_scanner.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ray_sdf.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class LaserPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    LaserScanConfig c = rayFromSdf(params, ctx_.sim->robot(ctx_.robot).model, /*vertical_allowed=*/false);
    const std::string& link = c.link;
    const double rate_hz = params.sensorDouble("update_rate", 0.0);
    if (rate_hz < 0) throw params.sensorError("update_rate", "must not be negative, got " + formatNumber(rate_hz));
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    const double extra_noise_m = rayPluginNoiseStddev(params);
    c.noise_stddev_m = std::hypot(c.noise_stddev_m, extra_noise_m);  // independent noises add in variance
    c.noise_seed = ctx_.noiseSeed(params.sensorName());

    const std::string topic = params.getString("topicName", "scan");
    frame_ = ctx_.frameParam(params, link);
    params.ignore({"hokuyoMinIntensity", "updateRate", "alwaysOn", "visualize", "topic"});
    scanner_ = std::make_unique<LaserScanner>(*ctx_.sim, ctx_.robot, c);

    msg_.header.frame_id = frame_;
    msg_.angle_min = static_cast<float>(c.min_angle_rad);
    msg_.angle_max = static_cast<float>(c.beam_count > 1 ? c.max_angle_rad : c.min_angle_rad);
    msg_.angle_increment = static_cast<float>(scanner_->angleIncrement());
    msg_.time_increment = 0.0f;  // all beams at once
    msg_.scan_time = static_cast<float>(timer_.stepsPerUpdate() * ctx_.sim->stepS());
    msg_.range_min = static_cast<float>(c.min_range_m);
    msg_.range_max = static_cast<float>(c.max_range_m);
    msg_.ranges.resize(c.beam_count);
    pub_ = nh.advertise<sensor_msgs::LaserScan>(topic, 1);
    ROS_INFO(
        "%s: LiDAR '%s' on link %s: %d beams over [%.4f, %.4f] rad, %.3f..%.3f m, noise %.4f m, %.1f Hz, "
        "%s in frame %s",
        ctx_.sim->robot(ctx_.robot).spec.name.c_str(), params.sensorName().c_str(), link.c_str(), c.beam_count,
        c.min_angle_rad, c.max_angle_rad, c.min_range_m, c.max_range_m, c.noise_stddev_m,
        1.0 / (timer_.stepsPerUpdate() * ctx_.sim->stepS()), pub_.getTopic().c_str(), frame_.c_str());
  }

  void afterStep() override {
    if (!timer_.due(ctx_.sim->stepCount()) || pub_.getNumSubscribers() == 0) return;
    const std::vector<float>& ranges = scanner_->scan();
    std::copy(ranges.begin(), ranges.end(), msg_.ranges.begin());
    msg_.header.stamp = ctx_.now();
    pub_.publish(msg_);
  }

 private:
  std::unique_ptr<LaserScanner> scanner_;
  std::string frame_;
  UpdateTimer timer_;
  sensor_msgs::LaserScan msg_;
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeLaserPlugin() { return std::make_unique<LaserPlugin>(); }

}  // namespace conde_sim
