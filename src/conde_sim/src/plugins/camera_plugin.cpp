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
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
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

// One camera of a <sensor type="multicamera"> (MultiCameraPlugin below): which <camera> element
// it is, its topics' suffix, and the camera whose optical frame is <frameName>.
struct StereoMember {
  const tinyxml2::XMLElement* camera = nullptr;        // its <camera> element
  std::string name_suffix;                             // "/left" or "/right", after <cameraName>
  bool right = false;                                  // P[3] from <hackBaseline> (the left's is 0)
  const tinyxml2::XMLElement* frame_camera = nullptr;  // the <camera> whose optical frame is <frameName>
};

class CameraPlugin : public SimPlugin {
 public:
  // `sensor_types`: the <sensor> types this plugin sits in; the defaults of the colour image's
  // topics differ between gazebo_ros_camera ("image_raw") and gazebo_ros_openni_kinect ("ir/...").
  explicit CameraPlugin(std::vector<std::string> sensor_types = {"camera", "wideanglecamera"},
                        std::string image_topic_default = "image_raw", std::string info_topic_default = "camera_info")
      : sensor_types_(std::move(sensor_types)),
        image_topic_default_(std::move(image_topic_default)),
        info_topic_default_(std::move(info_topic_default)) {}
  // A camera of a multicamera sensor.
  explicit CameraPlugin(StereoMember member) : CameraPlugin({"multicamera"}) { member_ = std::move(member); }

  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    link_ = params.requireSensor(sensor_types_);
    const bool wide_angle = params.sensorType() == "wideanglecamera";
    const auto& robot = ctx_.sim->robot(ctx_.robot);
    if (robot.model.bodyIndex(link_) < 0) {
      throw PluginError(params.where() + ": robot '" + robot.spec.name + "' has no link '" + link_ + "'");
    }

    // <sensor> and <camera>: size, field of view, clip, format, noise, distortion, lens.
    if (member_) params.selectSensorChild(member_->camera);
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
    if (member_ && !member_->right) baseline_m_ = 0.0;  // as gazebo_ros_multicamera: only the right one's
    params.getDouble("CxPrime", 0.0);
    const std::string camera_name = params.getString("cameraName", "camera") + (member_ ? member_->name_suffix : "");
    const std::string image_topic = params.getString("imageTopicName", image_topic_default_);
    const std::string info_topic = params.getString("cameraInfoTopicName", info_topic_default_);
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
    params.ignore({"visualize", "borderCrop", "autoDistortion", "triggerTopicName", "camera_info_topic", "topic"});
    params.sensorString("camera/save", "");  // accepted, unused

    // Where the camera sits and which frame its images carry. A camera of a multicamera sits at
    // its <camera><pose> in the sensor, and its images carry the optical frame of the left camera
    // (Gazebo's one <frameName>; the right camera's CameraInfo says where it is from there).
    const cp::Pose sensor_pose = params.sensorPose();
    const cp::Pose camera_pose = member_ ? params.sensorPose("camera/pose") : cp::Pose();
    link_T_optical_ = sensor_pose * camera_pose * cp::Pose(cp::Vec3(), kLinkToOptical);
    cp::Pose link_T_frame = link_T_optical_;
    const bool frame_of_other_camera = member_ && member_->frame_camera != member_->camera;
    if (frame_of_other_camera) {
      params.selectSensorChild(member_->frame_camera);
      link_T_frame = sensor_pose * params.sensorPose("camera/pose") * cp::Pose(cp::Vec3(), kLinkToOptical);
      params.selectSensorChild(member_->camera);
    }
    const std::string frame_name = params.getString("frameName", link_ + "_optical");
    frame_ = ctx_.frame(frame_name);
    int frame_body = -1;
    cp::Pose frame_in_body, link_in_body;
    if (robot.model.linkInBody(frame_name, frame_body, frame_in_body)) {
      int link_body = -1;
      robot.model.linkInBody(link_, link_body, link_in_body);
      const cp::Pose expected = link_in_body * link_T_frame;
      if (frame_body != link_body || !samePose(frame_in_body, expected)) {
        throw params.error("frameName", "link '" + frame_name + "' is not the optical frame of the camera on link '" +
                                            link_ +
                                            "' (REP 103: z forward, x right, y down; expected rpy -pi/2 0 "
                                            "-pi/2 from the camera link, within 0.5 degrees)");
      }
    } else if (ctx_.static_tf && !frame_of_other_camera) {  // that camera publishes it
      ctx_.static_tf->sendTransform(transformMessage(ctx_.now(), ctx_.frame(link_), frame_, link_T_frame));
    }

    try {
      renderer_ = std::make_unique<cp::CameraRenderer>(model);
    } catch (const std::invalid_argument& e) {
      throw params.sensorError("camera", e.what());
    }
    rng_.seed(std::hash<std::string>()(robot.spec.name + "/" + link_ + (member_ ? member_->name_suffix : "")));

    ros::NodeHandle camera_nh(nh, camera_name);
    image_pub_ = camera_nh.advertise<sensor_msgs::Image>(image_topic, 2);
    // Latched and published once at load (stamp 0): a node can read the intrinsics before the
    // simulation runs (conde_tracking subscribes to its images only then; a lock-step run starts
    // once it has, the same way every time).
    info_pub_ = camera_nh.advertise<sensor_msgs::CameraInfo>(info_topic, 2, true);
    fillCameraInfo(model);
    info_pub_.publish(info_);
    configureOutputs(params, camera_nh);
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
    const bool want_depth = wantsDepth();
    const ros::Time stamp = ctx_.now();
    publishExtraInfo(stamp);
    if (!want_image && !want_depth && info_pub_.getNumSubscribers() == 0) return;
    if (want_image || want_depth) {
      cp::RenderScene& scene = ctx_.sim->renderScene();
      const cp::Pose world_T_optical = ctx_.sim->linkPose(ctx_.robot, link_) * link_T_optical_;
      renderer_->render(scene, world_T_optical, ctx_.robot, &rng_, image_, want_depth ? &depth_ : nullptr);
      if (want_depth) publishDepth(stamp);  // reads image_ (the cloud's colours) before it moves
    }
    if (want_image) {
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

 protected:
  // Hooks of the depth camera: more topics at load, the depth outputs of a rendered frame.
  virtual void configureOutputs(PluginParams& /*params*/, ros::NodeHandle& /*camera_nh*/) {}
  virtual bool wantsDepth() const { return false; }
  virtual void publishDepth(const ros::Time& /*stamp*/) {}
  virtual void publishExtraInfo(const ros::Time& /*stamp*/) {}

  const cp::CameraModel& model() const { return renderer_->model(); }
  const std::string& frame() const { return frame_; }
  const cp::RgbImage& colourImage() const { return image_; }
  const cp::DepthImage& depthImage() const { return depth_; }
  const sensor_msgs::CameraInfo& cameraInfo() const { return info_; }

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

  std::vector<std::string> sensor_types_;
  std::optional<StereoMember> member_;
  std::string image_topic_default_, info_topic_default_;
  std::string link_, frame_, encoding_;
  std::string lens_type_ = "pinhole";
  cp::Pose link_T_optical_;
  double baseline_m_ = 0.0;
  UpdateTimer frame_timer_;
  std::unique_ptr<cp::CameraRenderer> renderer_;
  std::mt19937 rng_;
  cp::RgbImage image_;
  cp::DepthImage depth_;
  sensor_msgs::CameraInfo info_;
  ros::Publisher image_pub_, info_pub_;
};

// libgazebo_ros_depth_camera.so and libgazebo_ros_openni_kinect.so on <sensor type="depth">: the
// colour image and its CameraInfo as the camera above, plus from the same rendering pass
//   <cameraName>/<depthImageTopicName>            depth image, 32FC1 in metres (the z of each pixel
//                                                 in the optical frame; 16UC1 in millimetres with
//                                                 <useDepth16UC1Format>, 0 = no value)
//   <cameraName>/<depthImageCameraInfoTopicName>  its CameraInfo (the colour camera's numbers)
//   <cameraName>/<pointCloudTopicName>            organised PointCloud2 (height x width; x y z rgb
//                                                 float32, 32 bytes a point) in the optical frame
// As in Gazebo, a pixel nearer than <pointCloudCutoff> [m] (default 0.4) or, on the Kinect (and on
// the depth camera when given), not nearer than <pointCloudCutoffMax> [m] (default 5 on the
// Kinect) is NaN in both the depth image and the cloud (is_dense false). The colour image topics
// default to image_raw / camera_info on the depth camera and ir/image_raw / ir/camera_info on the
// Kinect, as in gazebo_ros_pkgs. Differences, on purpose:
// - A pixel that sees nothing (between the clips) is +inf in the 32FC1 image (REP 117) and NaN in
//   the cloud.
// - The rgb field is packed as PCL reads it (bytes B, G, R, 0; Gazebo writes R first, so red and
//   blue come out swapped in its clouds).
// - Points are back-projected through K (x = (u - cx) / fx * z); with lens distortion on the image
//   they are the distorted pixels' depths on undistorted rays, exact only without distortion.
// - <reflectanceTopicName>, <normalsTopicName>, <reduceNormals> (outputs of newer Gazebo's depth
//   camera) and <baseline> (written in many Kinect URDFs, read by no gazebo_ros version; the
//   stereo baseline is <hackBaseline>) are accepted without effect; <sensor><camera><depth_camera> too.
class DepthCameraPlugin : public CameraPlugin {
 public:
  DepthCameraPlugin(bool kinect)
      : CameraPlugin({"depth"}, kinect ? "ir/image_raw" : "image_raw", kinect ? "ir/camera_info" : "camera_info"),
        kinect_(kinect) {}

 protected:
  void configureOutputs(PluginParams& params, ros::NodeHandle& camera_nh) override {
    cutoff_min_m_ = params.getDouble("pointCloudCutoff", 0.4);
    cutoff_max_m_ = params.getDouble("pointCloudCutoffMax", kinect_ ? 5.0 : std::numeric_limits<double>::infinity());
    if (cutoff_min_m_ < 0) throw params.error("pointCloudCutoff", "must not be negative [m]");
    if (!(cutoff_max_m_ > cutoff_min_m_)) {
      throw params.error("pointCloudCutoffMax",
                         "must be greater than pointCloudCutoff (" + formatNumber(cutoff_min_m_) + " m)");
    }
    depth_16uc1_ = params.getBool("useDepth16UC1Format", false);
    const std::string depth_topic = params.getString("depthImageTopicName", "depth/image_raw");
    const std::string depth_info_topic = params.getString("depthImageCameraInfoTopicName", "depth/camera_info");
    const std::string points_topic = params.getString("pointCloudTopicName", "points");
    params.ignore({"reflectanceTopicName", "normalsTopicName", "reduceNormals", "baseline", "camera/depth_camera"});
    depth_pub_ = camera_nh.advertise<sensor_msgs::Image>(depth_topic, 2);
    depth_info_pub_ = camera_nh.advertise<sensor_msgs::CameraInfo>(depth_info_topic, 2, true);
    points_pub_ = camera_nh.advertise<sensor_msgs::PointCloud2>(points_topic, 2);
    depth_info_pub_.publish(cameraInfo());
    ROS_INFO("depth camera %s: %s (%s) + %s, %s; points from %.3f m to %.3f m", frame().c_str(),
             depth_pub_.getTopic().c_str(), depth_16uc1_ ? "16UC1 mm" : "32FC1 m", depth_info_pub_.getTopic().c_str(),
             points_pub_.getTopic().c_str(), cutoff_min_m_, cutoff_max_m_);
  }

  bool wantsDepth() const override { return depth_pub_.getNumSubscribers() > 0 || points_pub_.getNumSubscribers() > 0; }

  void publishExtraInfo(const ros::Time& stamp) override {
    if (depth_info_pub_.getNumSubscribers() == 0) return;
    sensor_msgs::CameraInfo info = cameraInfo();
    info.header.stamp = stamp;
    depth_info_pub_.publish(info);
  }

  void publishDepth(const ros::Time& stamp) override {
    if (depth_pub_.getNumSubscribers() > 0) publishDepthImage(stamp);
    if (points_pub_.getNumSubscribers() > 0) publishPoints(stamp);
  }

 private:
  // Gazebo's range test: only depths strictly between the two cut-offs are values.
  bool inRange(float depth_m) const { return depth_m > cutoff_min_m_ && depth_m < cutoff_max_m_; }

  void publishDepthImage(const ros::Time& stamp) {
    const cp::DepthImage& depth = depthImage();
    sensor_msgs::Image msg;
    msg.header.stamp = stamp;
    msg.header.frame_id = frame();
    msg.width = depth.width;
    msg.height = depth.height;
    msg.is_bigendian = 0;
    const size_t pixels = depth.depth_m.size();
    if (depth_16uc1_) {
      msg.encoding = sensor_msgs::image_encodings::TYPE_16UC1;
      msg.step = depth.width * sizeof(std::uint16_t);
      std::vector<std::uint16_t> mm(pixels, 0);
      for (size_t i = 0; i < pixels; ++i) {
        const float d = depth.depth_m[i];
        if (inRange(d) && std::isfinite(d)) mm[i] = static_cast<std::uint16_t>(std::min(65535.0f, d * 1000.0f + 0.5f));
      }
      msg.data.resize(pixels * sizeof(std::uint16_t));
      std::memcpy(msg.data.data(), mm.data(), msg.data.size());
    } else {
      msg.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
      msg.step = depth.width * sizeof(float);
      std::vector<float> values(pixels);
      for (size_t i = 0; i < pixels; ++i) {
        const float d = depth.depth_m[i];
        // Gazebo's depth camera (no upper cut-off) passes "nothing" on as +inf; beyond a cut-off is NaN.
        const bool value = inRange(d) || (std::isinf(d) && std::isinf(cutoff_max_m_));
        values[i] = value ? d : std::numeric_limits<float>::quiet_NaN();
      }
      msg.data.resize(pixels * sizeof(float));
      std::memcpy(msg.data.data(), values.data(), msg.data.size());
    }
    depth_pub_.publish(msg);
  }

  void publishPoints(const ros::Time& stamp) {
    const cp::DepthImage& depth = depthImage();
    const cp::RgbImage& colour = colourImage();
    const cp::CameraModel& m = model();
    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = stamp;
    cloud.header.frame_id = frame();
    sensor_msgs::PointCloud2Modifier modifier(cloud);
    modifier.setPointCloud2FieldsByString(2, "xyz", "rgb");
    modifier.resize(static_cast<size_t>(depth.width) * depth.height);
    cloud.width = depth.width;  // organised: one point per pixel, row by row
    cloud.height = depth.height;
    cloud.row_step = cloud.point_step * cloud.width;
    cloud.is_dense = true;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    sensor_msgs::PointCloud2Iterator<std::uint8_t> rgb(cloud, "rgb");
    for (int v = 0; v < depth.height; ++v) {
      for (int u = 0; u < depth.width; ++u, ++x, ++y, ++z, ++rgb) {
        const float d = depth.at(u, v);
        if (inRange(d) && std::isfinite(d)) {
          *x = static_cast<float>((u - m.cx_px) / m.fx_px * d);
          *y = static_cast<float>((v - m.cy_px) / m.fy_px * d);
          *z = d;
        } else {
          *x = *y = *z = nan;
          cloud.is_dense = false;
        }
        const std::uint8_t* p = &colour.data[3 * (static_cast<size_t>(v) * colour.width + u)];
        rgb[0] = p[2];  // little-endian 0x00RRGGBB, as PCL packs it
        rgb[1] = p[1];
        rgb[2] = p[0];
        rgb[3] = 0;
      }
    }
    points_pub_.publish(cloud);
  }

  bool kinect_;
  bool depth_16uc1_ = false;
  double cutoff_min_m_ = 0.4, cutoff_max_m_ = 5.0;
  ros::Publisher depth_pub_, depth_info_pub_, points_pub_;
};

// libgazebo_ros_multicamera.so on <sensor type="multicamera">: one camera per <camera name="...">
// (each with its own <pose> in the sensor, field of view, image, clip, noise and distortion),
// rendered in the same step, all with the plugin's keys of libgazebo_ros_camera.so. As in
// gazebo_ros_multicamera:
//   <cameraName>/left/<imageTopicName>, <cameraName>/left/<cameraInfoTopicName>    camera whose name contains "left"
//   <cameraName>/right/<imageTopicName>, <cameraName>/right/<cameraInfoTopicName>  camera whose name contains "right"
// both stamped in <frameName>, the optical frame of the left camera, and the right camera's
// CameraInfo has P[3] = -fx * <hackBaseline> (the left one's 0): the projection of a point given in
// the left optical frame, as stereo_image_proc expects. Differences, on purpose:
// - A camera whose name has neither "left" nor "right", or a second left or right one, is an error
//   (Gazebo loads it and publishes nothing for it, or two cameras on one topic).
// - The cameras may come in any order (Gazebo publishes the first <camera>'s frames as the left).
// - A <hackBaseline> that differs from where the <camera><pose>s put the right camera (its x in the
//   left optical frame) is reported once as a warning: disparities would give wrong depths.
class MultiCameraPlugin : public SimPlugin {
 protected:
  void configure(PluginParams& params, ros::NodeHandle& /*nh*/) override {
    params.requireSensor({"multicamera"});
    std::vector<StereoMember> members;
    const tinyxml2::XMLElement* left = nullptr;
    for (const tinyxml2::XMLElement* camera : params.sensorChildren("camera")) {
      const std::string name = camera->Attribute("name") ? camera->Attribute("name") : "";
      params.selectSensorChild(camera);
      StereoMember member;
      member.camera = camera;
      if (name.find("left") != std::string::npos) {
        member.name_suffix = "/left";
      } else if (name.find("right") != std::string::npos) {
        member.name_suffix = "/right";
        member.right = true;
      } else {
        throw params.sensorError("camera",
                                 "a camera of libgazebo_ros_multicamera.so needs a name that contains "
                                 "'left' or 'right' (got '" +
                                     name + "')");
      }
      for (const StereoMember& other : members) {
        if (other.name_suffix == member.name_suffix)
          throw params.sensorError("camera", "a second " + member.name_suffix.substr(1) + " camera");
      }
      if (!member.right) left = camera;
      members.push_back(member);
    }
    params.selectSensorChild(nullptr);
    if (members.empty())
      throw params.sensorError("camera",
                               "a multicamera sensor needs <camera name=\"left\"> and/or "
                               "<camera name=\"right\">");
    for (StereoMember& member : members) {
      member.frame_camera = left ? left : members.front().camera;
      cameras_.push_back(std::make_unique<CameraPlugin>(member));
      cameras_.back()->load(ctx_, params);
      params.selectSensorChild(nullptr);
    }
    if (left && members.size() == 2) checkBaseline(params, left, members[0].right ? members[0] : members[1]);
  }

  void afterStep() override {
    for (auto& camera : cameras_) camera->afterStep();
  }

 private:
  // Warns when <hackBaseline> is not the right camera's x in the left optical frame.
  static void checkBaseline(PluginParams& params, const tinyxml2::XMLElement* left, const StereoMember& right) {
    params.selectSensorChild(left);
    const cp::Pose left_optical = params.sensorPose("camera/pose") * cp::Pose(cp::Vec3(), kLinkToOptical);
    params.selectSensorChild(right.camera);
    const cp::Pose right_optical = params.sensorPose("camera/pose") * cp::Pose(cp::Vec3(), kLinkToOptical);
    params.selectSensorChild(nullptr);
    const double baseline_m = (left_optical.inverse() * right_optical).position.x;
    const double hack_baseline_m = params.getDouble("hackBaseline", 0.0);
    if (std::abs(baseline_m - hack_baseline_m) > 1e-3) {
      ROS_WARN(
          "%s: <hackBaseline> %s m, but the right camera is %s m right of the left one (<camera><pose>): "
          "depths from disparity will be wrong",
          params.where().c_str(), formatNumber(hack_baseline_m).c_str(), formatNumber(baseline_m).c_str());
    }
  }

  std::vector<std::unique_ptr<CameraPlugin>> cameras_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeCameraPlugin() { return std::make_unique<CameraPlugin>(); }
std::unique_ptr<SimPlugin> makeDepthCameraPlugin() { return std::make_unique<DepthCameraPlugin>(false); }
std::unique_ptr<SimPlugin> makeOpenniKinectPlugin() { return std::make_unique<DepthCameraPlugin>(true); }
std::unique_ptr<SimPlugin> makeMultiCameraPlugin() { return std::make_unique<MultiCameraPlugin>(); }

}  // namespace conde_sim
