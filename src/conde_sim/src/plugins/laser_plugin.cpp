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
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

class LaserPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    const std::string link = params.requireSensor({"ray", "gpu_ray"});
    int body = -1;
    cp::Pose unused;
    if (!ctx_.sim->robot(ctx_.robot).model.linkInBody(link, body, unused)) {
      throw PluginError(params.where() + ": <gazebo reference=\"" + link + "\"> must name a link to carry the sensor");
    }
    LaserScanConfig c;
    c.link = link;
    c.sensor_in_link = params.sensorPose();
    const double rate_hz = params.sensorDouble("update_rate", 0.0);
    if (rate_hz < 0) throw params.sensorError("update_rate", "must not be negative, got " + formatNumber(rate_hz));
    timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    params.sensorBool("always_on", true);

    const long samples = params.sensorInt("ray/scan/horizontal/samples", 640);
    if (samples < 1)
      throw params.sensorError("ray/scan/horizontal/samples", "must be at least 1, got " + std::to_string(samples));
    const double resolution = params.sensorDouble("ray/scan/horizontal/resolution", 1.0);
    if (!(resolution > 0)) {
      throw params.sensorError("ray/scan/horizontal/resolution", "must be positive, got " + formatNumber(resolution));
    }
    c.beam_count = static_cast<int>(std::max(1.0, std::round(samples * resolution)));
    c.min_angle_rad = params.sensorDouble("ray/scan/horizontal/min_angle", 0.0);
    c.max_angle_rad = params.sensorDouble("ray/scan/horizontal/max_angle", 0.0);
    if (c.beam_count > 1 && !(c.min_angle_rad < c.max_angle_rad)) {
      throw params.sensorError("ray/scan/horizontal/max_angle", "must be greater than <min_angle> (" +
                                                                    formatNumber(c.min_angle_rad) + "), got " +
                                                                    formatNumber(c.max_angle_rad));
    }
    const long vertical = params.sensorInt("ray/scan/vertical/samples", 1);
    if (vertical != 1) {
      throw params.sensorError("ray/scan/vertical/samples",
                               "only 2D scans are supported (1 sample), got " + std::to_string(vertical));
    }
    params.ignore({"ray/scan/vertical/resolution", "ray/scan/vertical/min_angle", "ray/scan/vertical/max_angle"});
    c.min_range_m = params.sensorDouble("ray/range/min", 0.0);
    c.max_range_m = params.sensorDouble("ray/range/max", 0.0);
    if (c.min_range_m < 0)
      throw params.sensorError("ray/range/min", "must not be negative, got " + formatNumber(c.min_range_m));
    if (!(c.max_range_m > c.min_range_m)) {
      throw params.sensorError("ray/range/max", "must be greater than <min> (" + formatNumber(c.min_range_m) +
                                                    "), got " + formatNumber(c.max_range_m));
    }
    if (params.sensorDouble("ray/range/resolution", 0.0) < 0) {
      throw params.sensorError("ray/range/resolution", "must not be negative");
    }
    readNoise(params, c);
    // Each sensor its own noise, the same in every run.
    c.noise_seed = static_cast<std::uint32_t>(
        std::hash<std::string>()(ctx_.sim->robot(ctx_.robot).spec.name + "/" + params.sensorName()));

    const std::string topic = params.getString("topicName", "scan");
    frame_ = ctx_.frame(params.getString("frameName", link));
    if (frame_.size() > 1 && frame_[0] == '/') frame_ = frame_.substr(1);  // tf2 frames have no leading slash
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
  static void readNoise(PluginParams& params, LaserScanConfig& c) {
    const PluginParams::SensorNoise noise = params.sensorNoise("ray/noise");
    if (noise.gaussian) {
      c.noise_mean_m = noise.mean;
      c.noise_stddev_m = noise.stddev;
    }
    const double extra = params.getDouble("gaussianNoise", 0.0);
    if (extra < 0) throw params.error("gaussianNoise", "must not be negative");
    c.noise_stddev_m = std::hypot(c.noise_stddev_m, extra);  // independent noises add in variance
  }

  std::unique_ptr<LaserScanner> scanner_;
  std::string frame_;
  UpdateTimer timer_;
  sensor_msgs::LaserScan msg_;
  ros::Publisher pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeLaserPlugin() { return std::make_unique<LaserPlugin>(); }

}  // namespace conde_sim
