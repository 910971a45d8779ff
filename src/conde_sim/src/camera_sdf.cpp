#include "conde_sim/camera_sdf.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace conde_sim {
namespace {

namespace cp = conde_physics;

// <camera><lens> of a wide-angle camera (SDF defaults: stereographic, scale_to_hfov true,
// cutoff_angle 1.5707). env_texture_size is accepted and unused: every pixel's ray is cast directly.
cp::CameraModel readWideAngle(PluginParams& params, int width, int height, double hfov_rad, std::string& lens_type) {
  lens_type = params.sensorString("camera/lens/type", "stereographic");
  cp::LensMapping lens;
  double focal_scale = 1.0;
  try {
    if (lens_type == "custom") {
      if (!params.sensorHas("camera/lens/custom_function"))
        throw params.sensorError("camera/lens/type", "lens type 'custom' needs a <custom_function>");
      lens = cp::LensMapping::custom(params.sensorDouble("camera/lens/custom_function/c1", 1.0),
                                     params.sensorDouble("camera/lens/custom_function/c2", 1.0),
                                     params.sensorDouble("camera/lens/custom_function/c3", 0.0),
                                     params.sensorString("camera/lens/custom_function/fun", "tan"));
      focal_scale = params.sensorDouble("camera/lens/custom_function/f", 1.0);
    } else {
      lens = cp::LensMapping::ofType(lens_type);
      if (params.sensorHas("camera/lens/custom_function")) params.ignore({"camera/lens/custom_function"});
    }
  } catch (const std::invalid_argument& e) {
    throw params.sensorError("camera/lens", e.what());
  }
  lens.cutoff_angle_rad = params.sensorDouble("camera/lens/cutoff_angle", 1.5707);
  const bool scale_to_hfov = params.sensorBool("camera/lens/scale_to_hfov", true);
  const double env_texture_size = params.sensorDouble("camera/lens/env_texture_size", 256);
  if (!(env_texture_size > 0)) throw params.sensorError("camera/lens/env_texture_size", "must be positive");
  try {
    return cp::CameraModel::fromWideAngle(width, height, hfov_rad, lens, scale_to_hfov, focal_scale);
  } catch (const std::invalid_argument& e) {
    throw params.sensorError("camera/lens", e.what());
  }
}

void readNoise(PluginParams& params, cp::CameraModel& model) {
  const PluginParams::SensorNoise noise = params.sensorNoise("camera/noise");
  if (noise.mean != 0.0) throw params.sensorError("camera/noise/mean", "only zero-mean noise is supported");
  if (noise.gaussian) model.noise_stddev = noise.stddev;
}

void readDistortion(PluginParams& params, cp::CameraModel& model) {
  cp::LensDistortion sensor, plugin;
  const bool in_sensor = params.sensorHas("camera/distortion");
  sensor.k1 = params.sensorDouble("camera/distortion/k1", 0.0);
  sensor.k2 = params.sensorDouble("camera/distortion/k2", 0.0);
  sensor.k3 = params.sensorDouble("camera/distortion/k3", 0.0);
  sensor.p1 = params.sensorDouble("camera/distortion/p1", 0.0);
  sensor.p2 = params.sensorDouble("camera/distortion/p2", 0.0);
  const std::string center = params.sensorString("camera/distortion/center", "0.5 0.5");
  std::istringstream center_in(center);
  double center_x = 0.5, center_y = 0.5;
  std::string rest;
  if (!(center_in >> center_x >> center_y) || (center_in >> rest) || !(center_x > 0 && center_x < 1) ||
      !(center_y > 0 && center_y < 1)) {
    throw params.sensorError(
        "camera/distortion/center",
        "expected two fractions of the image size in (0, 1), e.g. '0.5 0.5' (got '" + center + "')");
  }
  // The distortion's centre is the principal point here (the centre of the lens model too).
  if (in_sensor) model.setDistortionCenter(center_x, center_y);
  plugin.k1 = params.getDouble("distortionK1", 0.0);
  plugin.k2 = params.getDouble("distortionK2", 0.0);
  plugin.k3 = params.getDouble("distortionK3", 0.0);
  plugin.p1 = params.getDouble("distortionT1", 0.0);
  plugin.p2 = params.getDouble("distortionT2", 0.0);
  if (in_sensor && !plugin.isZero() &&
      (plugin.k1 != sensor.k1 || plugin.k2 != sensor.k2 || plugin.k3 != sensor.k3 || plugin.p1 != sensor.p1 ||
       plugin.p2 != sensor.p2)) {
    throw params.error("distortionK1", "differs from <camera><distortion>: give the coefficients once");
  }
  model.distortion = in_sensor ? sensor : plugin;
}

}  // namespace

CameraFromSdf cameraFromSdf(PluginParams& params) {
  const bool wide_angle = params.inSensor() && params.sensorType() == "wideanglecamera";
  const double width = params.sensorDouble("camera/image/width", 320);
  const double height = params.sensorDouble("camera/image/height", 240);
  if (width <= 0 || height <= 0 || width != std::floor(width) || height != std::floor(height)) {
    throw params.sensorError("camera/image", "image size must be a positive whole number of pixels (got " +
                                                 formatNumber(width) + "x" + formatNumber(height) + ")");
  }
  const double hfov_rad = params.sensorDouble("camera/horizontal_fov", 1.047);
  const double hfov_max_rad = wide_angle ? 2 * M_PI : M_PI;
  if (!(hfov_rad > 0 && (wide_angle ? hfov_rad <= hfov_max_rad : hfov_rad < hfov_max_rad))) {
    throw params.sensorError("camera/horizontal_fov", std::string("must be in (0, ") + (wide_angle ? "2 pi]" : "pi)") +
                                                          " rad (got " + formatNumber(hfov_rad) + ")");
  }
  CameraFromSdf camera;
  camera.horizontal_fov_rad = hfov_rad;
  const std::string format = params.sensorString("camera/image/format", "R8G8B8");
  if (format == "R8G8B8" || format == "RGB_INT8") {
    camera.encoding = "rgb8";
  } else if (format == "B8G8R8" || format == "BGR_INT8") {
    camera.encoding = "bgr8";
  } else if (format == "L8" || format == "L_INT8") {
    camera.encoding = "mono8";
  } else {
    throw params.sensorError("camera/image/format",
                             "unknown image format '" + format + "' (expected R8G8B8, B8G8R8 or L8)");
  }
  cp::CameraModel& model = camera.model;
  model = wide_angle ? readWideAngle(params, int(width), int(height), hfov_rad, camera.lens_type)
                     : cp::CameraModel::fromHorizontalFov(int(width), int(height), hfov_rad);
  if (!wide_angle && params.sensorHas("camera/lens")) {
    const std::string type = params.sensorString("camera/lens/type", "stereographic");
    if (type != "gnomonical") {
      throw params.sensorError("camera/lens/type", "lens '" + type +
                                                       "' needs <sensor type=\"wideanglecamera\"> (a "
                                                       "\"camera\" sensor is a pinhole, i.e. gnomonical)");
    }
    params.ignore({"camera/lens"});
  }
  model.near_clip_m = params.sensorDouble("camera/clip/near", 0.1);
  model.far_clip_m = params.sensorDouble("camera/clip/far", 100.0);
  if (!(model.near_clip_m > 0 && model.far_clip_m > model.near_clip_m)) {
    throw params.sensorError("camera/clip", "needs 0 < near < far (got near " + formatNumber(model.near_clip_m) +
                                                ", far " + formatNumber(model.far_clip_m) + ")");
  }
  readNoise(params, model);
  readDistortion(params, model);
  return camera;
}

}  // namespace conde_sim
