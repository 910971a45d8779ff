// The SDF camera block -> camera model, without ROS or a simulation: intrinsics as Gazebo
// computes them, formats, distortion from the sensor or the plugin, lenses, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "conde_sim/camera_sdf.h"

using conde_sim::cameraFromSdf;
using conde_sim::PluginError;
using conde_sim::PluginParams;

namespace {

// A <sensor> with `camera_xml` and a camera plugin with `plugin_xml`, parsed as the loader does.
struct Sensor {
  tinyxml2::XMLDocument doc;
  std::unique_ptr<PluginParams> params;
  Sensor(const std::string& camera_xml, const std::string& plugin_xml = "", const std::string& type = "camera") {
    const std::string xml = "<sensor type=\"" + type + "\" name=\"cam\">\n" + camera_xml +
                            "\n<plugin name=\"cam_controller\" filename=\"libgazebo_ros_camera.so\">" + plugin_xml +
                            "</plugin></sensor>";
    doc.Parse(xml.c_str());
    const tinyxml2::XMLElement* sensor = doc.FirstChildElement("sensor");
    params = std::make_unique<PluginParams>(sensor->FirstChildElement("plugin"), sensor, "robot.urdf", "base");
  }
};

}  // namespace

TEST(CameraFromSdf, PinholeIntrinsicsAsGazeboComputesThem) {
  Sensor s(
      "<camera><horizontal_fov>1.0865</horizontal_fov><image><width>160</width><height>120</height>"
      "<format>B8G8R8</format></image><clip><near>0.02</near><far>50</far></clip></camera>");
  const auto camera = cameraFromSdf(*s.params);
  EXPECT_EQ(camera.model.width_px, 160);
  EXPECT_EQ(camera.model.height_px, 120);
  EXPECT_NEAR(camera.model.fx_px, 160 / (2 * std::tan(1.0865 / 2)), 1e-9);  // 132.48 px, Conde's left camera
  EXPECT_EQ(camera.model.fy_px, camera.model.fx_px);
  EXPECT_DOUBLE_EQ(camera.model.cx_px, 79.5);  // the image's centre, (W - 1) / 2
  EXPECT_DOUBLE_EQ(camera.model.cy_px, 59.5);
  EXPECT_EQ(camera.encoding, "bgr8");
  EXPECT_EQ(camera.lens_type, "pinhole");
  EXPECT_DOUBLE_EQ(camera.model.near_clip_m, 0.02);
  EXPECT_DOUBLE_EQ(camera.model.far_clip_m, 50.0);
  EXPECT_TRUE(camera.model.distortion.isZero());
}

TEST(CameraFromSdf, GazeboDefaults) {
  Sensor s("<camera/>");
  const auto camera = cameraFromSdf(*s.params);
  EXPECT_EQ(camera.model.width_px, 320);
  EXPECT_EQ(camera.model.height_px, 240);
  EXPECT_DOUBLE_EQ(camera.horizontal_fov_rad, 1.047);
  EXPECT_EQ(camera.encoding, "rgb8");
}

TEST(CameraFromSdf, DistortionFromTheSensorOrThePluginOnce) {
  Sensor sensor(
      "<camera><distortion><k1>-0.25</k1><k2>0.12</k2><p1>0.001</p1><center>0.4 0.6</center>"
      "</distortion></camera>");
  const auto a = cameraFromSdf(*sensor.params);
  EXPECT_DOUBLE_EQ(a.model.distortion.k1, -0.25);
  EXPECT_DOUBLE_EQ(a.model.distortion.k2, 0.12);
  EXPECT_DOUBLE_EQ(a.model.distortion.p1, 0.001);
  EXPECT_NE(a.model.cx_px, 159.5);  // <center> moves the principal point
  Sensor plugin("<camera/>", "<distortionK1>-0.25</distortionK1><distortionT2>0.002</distortionT2>");
  const auto b = cameraFromSdf(*plugin.params);
  EXPECT_DOUBLE_EQ(b.model.distortion.k1, -0.25);
  EXPECT_DOUBLE_EQ(b.model.distortion.p2, 0.002);
  Sensor both("<camera><distortion><k1>-0.25</k1></distortion></camera>", "<distortionK1>-0.2</distortionK1>");
  EXPECT_THROW(cameraFromSdf(*both.params), PluginError);
}

TEST(CameraFromSdf, WideAngleLens) {
  Sensor s(
      "<camera><horizontal_fov>2.6</horizontal_fov><image><width>160</width><height>120</height></image>"
      "<lens><type>stereographic</type><scale_to_hfov>true</scale_to_hfov></lens></camera>",
      "", "wideanglecamera");
  const auto camera = cameraFromSdf(*s.params);
  EXPECT_EQ(camera.lens_type, "stereographic");
  // scale_to_hfov: the stereographic radius 2 f tan(theta / 2) reaches the image edge at hfov / 2.
  EXPECT_NEAR(2 * camera.model.fx_px * std::tan(2.6 / 4), 80.0, 0.5);
}

TEST(CameraFromSdf, BadInputNamesTheElement) {
  auto message = [](const std::string& camera_xml, const std::string& type = "camera") {
    Sensor s(camera_xml, "", type);
    try {
      cameraFromSdf(*s.params);
    } catch (const PluginError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto expect_error = [&](const std::string& camera_xml, const std::string& part) {
    const std::string m = message(camera_xml);
    EXPECT_NE(m.find(part), std::string::npos) << m;
  };
  expect_error("<camera><image><width>0</width></image></camera>",
               "<camera><image>: image size must be a positive whole number of pixels (got 0x240)");
  expect_error("<camera><horizontal_fov>3.1416</horizontal_fov></camera>",
               "<camera><horizontal_fov>: must be in (0, pi) rad (got 3.1416)");
  expect_error("<camera><image><format>R16G16B16</format></image></camera>", "unknown image format");
  expect_error("<camera><lens><type>stereographic</type></lens></camera>", "needs <sensor type=\"wideanglecamera\">");
  expect_error("<camera><noise><type>gaussian</type><mean>0.1</mean></noise></camera>",
               "only zero-mean noise is supported");
}
