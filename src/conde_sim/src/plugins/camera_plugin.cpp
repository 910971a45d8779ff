// libgazebo_ros_camera.so: a pinhole camera (<sensor type="camera">) or a wide-angle one
// (<sensor type="wideanglecamera"> with Gazebo's <lens> types) rendered on the CPU
// (conde_physics::CameraRenderer).
//
//   <gazebo reference="camera_link">
//     <sensor type="camera" name="camera1">
//       <update_rate>30</update_rate>
//       <camera>
//         <horizontal_fov>1.0865</horizontal_fov>
//         <image><width>160</width><height>120</height><format>R8G8B8</format></image>
//         <clip><near>0.001</near><far>50</far></clip>
//         <distortion><k1>-0.25</k1><k2>0.05</k2><k3>0</k3><p1>0.005</p1><p2>0.001</p2></distortion>
//         <noise><type>gaussian</type><mean>0</mean><stddev>0.007</stddev></noise>
//       </camera>
//       <plugin name="camera_controller" filename="libgazebo_ros_camera.so">
//         <cameraName>camera1</cameraName> <imageTopicName>image_raw</imageTopicName>
//         <cameraInfoTopicName>camera_info</cameraInfoTopicName> <frameName>camera_link_optical</frameName>
//       </plugin>
//     </sensor>
//   </gazebo>
//
// As in Gazebo the camera looks along the +x axis of its link (+y = image left, +z = image up),
// offset by the sensor's <pose>. Differences from gazebo_ros_camera, on purpose:
// - Images are stamped in an optical frame (REP 103: z forward, x right, y down). <frameName>
//   defaults to "<link>_optical"; when that frame is not a link of the URDF the plugin publishes
//   it on /tf_static, and when it is, its pose must be the camera's optical frame (else an error).
// - Distortion is applied to the pixels, from <camera><distortion> or, for Gazebo-ready URDFs
//   that only set them, from the plugin's distortionK1..K3 / distortionT1..T2 (both given and
//   different is an error). CameraInfo reports exactly the numbers used.
// - The principal point defaults to the image centre, ((W-1)/2, (H-1)/2) in OpenCV's convention,
//   where the image really is centred; <Cx>/<Cy>/<focalLength> move the rendering with them.
// - Nothing is rendered while nobody subscribes to the image.
// - <distortion><center> is the principal point (Gazebo keeps the pinhole centre in the middle and
//   moves only the distortion's centre).
// - A wide-angle camera's CameraInfo gives the lens's focal length (the scale at the image centre)
//   and the plumb_bob numbers; CameraInfo has no model for stereographic and the other lenses,
//   and the distortion acts on the lens image in units of the image size (Gazebo's compositor), so
//   it is exact only near the centre. Pixels beyond <cutoff_angle> are black.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <sstream>

#include "conde_sim/camera_sdf.h"
#include "conde_sim/plugin.h"
#include "conde_sim/ros_conversions.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

// The camera link's frame (x forward, z up) -> its optical frame (z forward, x right, y down).
const cp::Quat kLinkToOptical = cp::Quat::fromRpy(-M_PI / 2, 0.0, -M_PI / 2);

// Poses within 1 mm and 0.5 degrees: URDFs write the optical frame's rpy with pi/2 rounded
// ("-1.57 0 -1.57" is 0.06 degrees off), and that is still the optical frame.
constexpr double kOpticalPositionTolerance_m = 1e-3;
constexpr double kOpticalAngleTolerance_rad = 0.5 * M_PI / 180.0;

bool samePose(const cp::Pose& a, const cp::Pose& b) {
  const cp::Quat d = a.orientation.conjugate() * b.orientation;
  const double angle_rad = 2.0 * std::acos(std::min(1.0, std::abs(d.normalized().w)));
  return (a.position - b.position).norm() < kOpticalPositionTolerance_m && angle_rad < kOpticalAngleTolerance_rad;
}

class CameraPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    link_ = params.requireSensor({"camera", "wideanglecamera"});
    const bool wide_angle = params.sensorType() == "wideanglecamera";
    const auto& robot = ctx_.sim->robot(ctx_.robot);
    if (robot.model.bodyIndex(link_) < 0) {
      throw PluginError(params.where() + ": robot '" + robot.spec.name + "' has no link '" + link_ + "'");
    }

    // <sensor> and <camera>: size, field of view, clip, format, noise, distortion, lens.
    CameraFromSdf camera = cameraFromSdf(params);
    cp::CameraModel& model = camera.model;
    encoding_ = camera.encoding;
    lens_type_ = camera.lens_type;
    const double hfov_rad = camera.horizontal_fov_rad;

    // Plugin: intrinsics overrides, topics, frame, rate.
    const double focal_px = params.getDouble("focalLength", 0.0);
    if (focal_px < 0) throw params.error("focalLength", "must not be negative (0 = from horizontal_fov)");
    if (focal_px > 0) model.fx_px = model.fy_px = focal_px;
    const double cx_px = params.getDouble("Cx", 0.0), cy_px = params.getDouble("Cy", 0.0);
    if (cx_px > 0) model.cx_px = cx_px;
    if (cy_px > 0) model.cy_px = cy_px;
    baseline_m_ = params.getDouble("hackBaseline", 0.0);
    params.getDouble("CxPrime", 0.0);
    const std::string camera_name = params.getString("cameraName", "camera");
    const std::string image_topic = params.getString("imageTopicName", "image_raw");
    const std::string info_topic = params.getString("cameraInfoTopicName", "camera_info");
    const double sensor_rate_hz = params.sensorDouble("update_rate", 0.0);
    double rate_hz = params.getDouble("updateRate", 0.0);
    if (rate_hz < 0) throw params.error("updateRate", "must not be negative");
    if (rate_hz == 0) rate_hz = sensor_rate_hz;  // as in Gazebo: 0 = the sensor's rate
    if (rate_hz <= 0) rate_hz = 30.0;            // Gazebo renders unbounded; here a camera needs a rate
    // Exactly rate_hz frames per simulated second, also when the period is not a whole number of
    // steps (30 Hz at 1 kHz: 33, 33, 34 steps apart).
    frame_timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    params.getBool("alwaysOn", true);
    params.sensorBool("always_on", true);
    params.ignore({"visualize", "borderCrop", "autoDistortion", "camera_info_topic", "topic"});
    params.sensorString("camera/save", "");  // accepted, unused

    // Where the camera sits and which frame its images carry.
    const cp::Pose sensor_pose = params.sensorPose();
    link_T_optical_ = sensor_pose * cp::Pose(cp::Vec3(), kLinkToOptical);
    const std::string frame_name = params.getString("frameName", link_ + "_optical");
    frame_ = ctx_.frame(frame_name);
    int frame_body = -1;
    cp::Pose frame_in_body, link_in_body;
    if (robot.model.linkInBody(frame_name, frame_body, frame_in_body)) {
      int link_body = -1;
      robot.model.linkInBody(link_, link_body, link_in_body);
      const cp::Pose expected = link_in_body * link_T_optical_;
      if (frame_body != link_body || !samePose(frame_in_body, expected)) {
        throw params.error("frameName", "link '" + frame_name + "' is not the optical frame of the camera on link '" +
                                            link_ +
                                            "' (REP 103: z forward, x right, y down; expected rpy -pi/2 0 "
                                            "-pi/2 from the camera link, within 0.5 degrees)");
      }
    } else if (ctx_.static_tf) {
      ctx_.static_tf->sendTransform(transformMessage(ctx_.now(), ctx_.frame(link_), frame_, link_T_optical_));
    }

    try {
      renderer_ = std::make_unique<cp::CameraRenderer>(model);
    } catch (const std::invalid_argument& e) {
      throw params.sensorError("camera", e.what());
    }
    rng_.seed(std::hash<std::string>()(robot.spec.name + "/" + link_));

    ros::NodeHandle camera_nh(nh, camera_name);
    image_pub_ = camera_nh.advertise<sensor_msgs::Image>(image_topic, 2);
    // Latched and published once at load (stamp 0): a node can read the intrinsics before the
    // simulation runs (conde_tracking subscribes to its images only then; a lock-step run starts
    // once it has, the same way every time).
    info_pub_ = camera_nh.advertise<sensor_msgs::CameraInfo>(info_topic, 2, true);
    fillCameraInfo(model);
    info_pub_.publish(info_);
    ROS_INFO(
        "%s: camera on link %s: %dx%d, %s lens, hfov %.4f rad (fx %.2f px), %s distortion, %.1f Hz, %s + %s in "
        "frame %s",
        robot.spec.name.c_str(), link_.c_str(), model.width_px, model.height_px, lens_type_.c_str(), hfov_rad,
        model.fx_px, model.distortion.isZero() ? "no" : "plumb_bob", rate_hz, image_pub_.getTopic().c_str(),
        info_pub_.getTopic().c_str(), frame_.c_str());
  }

  void afterStep() override {
    if (!frame_timer_.due(ctx_.sim->stepCount())) return;
    const bool want_image = image_pub_.getNumSubscribers() > 0;
    if (!want_image && info_pub_.getNumSubscribers() == 0) return;
    const ros::Time stamp = ctx_.now();
    if (want_image) {
      cp::RenderScene& scene = ctx_.sim->renderScene();
      const cp::Pose world_T_optical = ctx_.sim->linkPose(ctx_.robot, link_) * link_T_optical_;
      renderer_->render(scene, world_T_optical, ctx_.robot, &rng_, image_);
      sensor_msgs::Image msg;
      msg.header.stamp = stamp;
      msg.header.frame_id = frame_;
      msg.width = image_.width;
      msg.height = image_.height;
      msg.encoding = encoding_;
      toEncoding(msg);
      image_pub_.publish(msg);  // serialises the message before it returns
      // Take the pixel buffer back so that the next frame renders into it without allocating.
      if (image_.data.empty()) image_.data.swap(msg.data);
    }
    info_.header.stamp = stamp;
    info_pub_.publish(info_);
  }

 private:
  void fillCameraInfo(const cp::CameraModel& model) {
    info_.header.frame_id = frame_;
    info_.width = model.width_px;
    info_.height = model.height_px;
    info_.distortion_model = "plumb_bob";
    const cp::LensDistortion& d = model.distortion;
    info_.D = {d.k1, d.k2, d.p1, d.p2, d.k3};
    info_.K = {model.fx_px, 0, model.cx_px, 0, model.fy_px, model.cy_px, 0, 0, 1};
    info_.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    info_.P = {model.fx_px, 0, model.cx_px, -model.fx_px * baseline_m_, 0, model.fy_px, model.cy_px, 0, 0, 0, 1, 0};
  }

  // Moves the rendered RGB pixels into the message in its encoding.
  void toEncoding(sensor_msgs::Image& msg) {
    const size_t pixels = static_cast<size_t>(image_.width) * image_.height;
    if (encoding_ == sensor_msgs::image_encodings::RGB8) {
      msg.step = image_.width * 3;
      msg.data.swap(image_.data);
      return;
    }
    if (encoding_ == sensor_msgs::image_encodings::BGR8) {
      msg.step = image_.width * 3;
      msg.data.swap(image_.data);
      for (size_t i = 0; i < pixels; ++i) std::swap(msg.data[3 * i], msg.data[3 * i + 2]);
      return;
    }
    msg.step = image_.width;
    msg.data.resize(pixels);
    for (size_t i = 0; i < pixels; ++i) {
      const std::uint8_t* p = &image_.data[3 * i];
      msg.data[i] = static_cast<std::uint8_t>((299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000);
    }
  }

  std::string link_, frame_, encoding_;
  std::string lens_type_ = "pinhole";
  cp::Pose link_T_optical_;
  double baseline_m_ = 0.0;
  UpdateTimer frame_timer_;
  std::unique_ptr<cp::CameraRenderer> renderer_;
  std::mt19937 rng_;
  cp::RgbImage image_;
  sensor_msgs::CameraInfo info_;
  ros::Publisher image_pub_, info_pub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeCameraPlugin() { return std::make_unique<CameraPlugin>(); }

}  // namespace conde_sim
