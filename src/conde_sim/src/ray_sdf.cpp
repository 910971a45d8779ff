#include "conde_sim/ray_sdf.h"

#include <algorithm>
#include <cmath>

namespace conde_sim {
namespace {

// Rays of one scan direction ("ray/scan/horizontal" or ".../vertical"): samples x resolution of
// them, from min_angle to max_angle [rad].
int readScanAxis(PluginParams& params, const std::string& axis, long default_samples, double& min_rad,
                 double& max_rad) {
  const long samples = params.sensorInt(axis + "/samples", default_samples);
  if (samples < 1) throw params.sensorError(axis + "/samples", "must be at least 1, got " + std::to_string(samples));
  const double resolution = params.sensorDouble(axis + "/resolution", 1.0);
  if (!(resolution > 0)) {
    throw params.sensorError(axis + "/resolution", "must be positive, got " + formatNumber(resolution));
  }
  const int count = static_cast<int>(std::max(1.0, std::round(samples * resolution)));
  min_rad = params.sensorDouble(axis + "/min_angle", 0.0);
  max_rad = params.sensorDouble(axis + "/max_angle", 0.0);
  if (count > 1 && !(min_rad < max_rad)) {
    throw params.sensorError(axis + "/max_angle", "must be greater than <min_angle> (" + formatNumber(min_rad) +
                                                      "), got " + formatNumber(max_rad));
  }
  return count;
}

}  // namespace

LaserScanConfig rayFromSdf(PluginParams& params, const conde_physics::ArticulatedModel& model, bool vertical_allowed) {
  const std::string link = params.requireSensor({"ray", "gpu_ray"});
  int body = -1;
  conde_physics::Pose unused;
  if (!model.linkInBody(link, body, unused)) {
    throw PluginError(params.where() + ": <gazebo reference=\"" + link + "\"> must name a link to carry the sensor");
  }
  LaserScanConfig c;
  c.link = link;
  c.sensor_in_link = params.sensorPose();
  params.sensorBool("always_on", true);
  c.beam_count = readScanAxis(params, "ray/scan/horizontal", 640, c.min_angle_rad, c.max_angle_rad);
  if (vertical_allowed) {
    c.vertical_count = readScanAxis(params, "ray/scan/vertical", 1, c.min_vertical_angle_rad, c.max_vertical_angle_rad);
  } else {
    const long vertical = params.sensorInt("ray/scan/vertical/samples", 1);
    if (vertical != 1) {
      throw params.sensorError("ray/scan/vertical/samples",
                               "only 2D scans are supported (1 sample), got " + std::to_string(vertical));
    }
    params.ignore({"ray/scan/vertical/resolution", "ray/scan/vertical/min_angle", "ray/scan/vertical/max_angle"});
  }
  c.min_range_m = params.sensorDouble("ray/range/min", 0.0);
  c.max_range_m = params.sensorDouble("ray/range/max", 0.0);
  if (c.min_range_m < 0)
    throw params.sensorError("ray/range/min", "must not be negative, got " + formatNumber(c.min_range_m));
  if (!(c.max_range_m > c.min_range_m)) {
    throw params.sensorError("ray/range/max", "must be greater than <min> (" + formatNumber(c.min_range_m) + "), got " +
                                                  formatNumber(c.max_range_m));
  }
  if (params.sensorDouble("ray/range/resolution", 0.0) < 0) {
    throw params.sensorError("ray/range/resolution", "must not be negative");
  }
  const PluginParams::SensorNoise noise = params.sensorNoise("ray/noise");
  if (noise.gaussian) {
    c.noise_mean_m = noise.mean;
    c.noise_stddev_m = noise.stddev;
  }
  return c;
}

double rayPluginRateHz(PluginParams& params) {
  const double sensor_hz = params.sensorDouble("update_rate", 0.0);
  if (sensor_hz < 0) throw params.sensorError("update_rate", "must not be negative, got " + formatNumber(sensor_hz));
  const double plugin_hz = params.getDouble("updateRate", 0.0);
  if (plugin_hz < 0) throw params.error("updateRate", "must not be negative, got " + formatNumber(plugin_hz));
  if (sensor_hz == 0) return plugin_hz;
  if (plugin_hz == 0) return sensor_hz;
  return std::min(sensor_hz, plugin_hz);
}

double rayPluginNoiseStddev(PluginParams& params) {
  const double stddev = params.getDouble("gaussianNoise", 0.0);
  if (stddev < 0) throw params.error("gaussianNoise", "must not be negative");
  return stddev;
}

}  // namespace conde_sim
