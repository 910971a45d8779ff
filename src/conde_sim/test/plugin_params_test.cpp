#include <gtest/gtest.h>

#include "conde_sim/plugin_params.h"

using conde_sim::PluginError;
using conde_sim::PluginParams;

namespace {

// The message of the PluginError that `f` throws, or "no error".
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const PluginError& e) {
    return e.what();
  }
  return "no error";
}

struct Parsed {
  tinyxml2::XMLDocument doc;
  const tinyxml2::XMLElement* plugin = nullptr;
  const tinyxml2::XMLElement* sensor = nullptr;
  explicit Parsed(const char* xml) {
    doc.Parse(xml);
    const auto* root = doc.FirstChildElement();
    sensor = std::string(root->Name()) == "sensor" ? root : nullptr;
    plugin = sensor ? sensor->FirstChildElement("plugin") : root;
  }
};

TEST(PluginParams, ReadsValuesWithDefaults) {
  Parsed p(
      "<plugin name=\"dd\" filename=\"libx.so\">\n<wheelSeparation> 0.33 </wheelSeparation>\n"
      "<publishTf>1</publishTf><jointName>a, b c</jointName><xyz>1 2 3</xyz></plugin>");
  PluginParams params(p.plugin, nullptr, "robot.urdf", "");
  EXPECT_DOUBLE_EQ(params.getDouble("wheelSeparation", 0.34), 0.33);
  EXPECT_DOUBLE_EQ(params.getDouble("wheelDiameter", 0.15), 0.15);
  EXPECT_TRUE(params.getBool("publishTf", false));
  EXPECT_EQ(params.getList("jointName"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_DOUBLE_EQ(params.getVec3("xyz", {}).z, 3.0);
  EXPECT_NO_THROW(params.checkAllUsed());
}

TEST(PluginParams, UnknownKeyNamesFileLinePluginAndKey) {
  Parsed p(
      "<plugin name=\"dd\" filename=\"libgazebo_ros_diff_drive.so\">\n<wheelSeparation>0.3</wheelSeparation>\n"
      "<wheelSeperation>0.3</wheelSeperation></plugin>");
  PluginParams params(p.plugin, nullptr, "conde.urdf", "");
  params.getDouble("wheelSeparation", 0.34);
  EXPECT_EQ(errorOf([&] { params.checkAllUsed(); }),
            "conde.urdf:3: plugin 'dd' (libgazebo_ros_diff_drive.so): unknown parameter <wheelSeperation>");
}

TEST(PluginParams, BadValuesNameTheKey) {
  Parsed p("<plugin name=\"dd\" filename=\"libx.so\"><updateRate>fast</updateRate><publishTf>yes</publishTf></plugin>");
  PluginParams params(p.plugin, nullptr, "r.urdf", "");
  EXPECT_EQ(errorOf([&] { params.getDouble("updateRate", 10); }),
            "r.urdf:1: plugin 'dd' (libx.so): <updateRate>: expected a number, got 'fast'");
  EXPECT_THROW(params.getBool("publishTf", true), PluginError);
  EXPECT_EQ(errorOf([&] { params.requireString("leftJoint"); }),
            "r.urdf:1: plugin 'dd' (libx.so): <leftJoint>: required parameter is missing");
}

TEST(PluginParams, SensorKeysAreCheckedToo) {
  Parsed p(
      "<sensor name=\"imu\" type=\"imu\"><update_rate>100</update_rate>\n<updaterate>5</updaterate>"
      "<plugin name=\"i\" filename=\"libgazebo_ros_imu_sensor.so\"/></sensor>");
  PluginParams params(p.plugin, p.sensor, "r.urdf", "imu_link");
  EXPECT_DOUBLE_EQ(params.sensorDouble("update_rate", 0), 100.0);
  EXPECT_EQ(params.sensorType(), "imu");
  EXPECT_EQ(errorOf([&] { params.checkAllUsed(); }), "r.urdf:2: sensor 'imu' (imu): unknown element <updaterate>");
}

TEST(PluginParams, NestedSensorKeysAreReadAndChecked) {
  Parsed p(
      "<sensor name=\"laser\" type=\"ray\"><update_rate>40</update_rate>\n<ray><scan><horizontal>\n"
      "<samples>1081</samples>\n<min_angle>x</min_angle></horizontal></scan>\n<range><mni>0.1</mni></range></ray>"
      "<plugin name=\"l\" filename=\"libgazebo_ros_laser.so\"/></sensor>");
  PluginParams params(p.plugin, p.sensor, "r.urdf", "laser");
  EXPECT_DOUBLE_EQ(params.sensorDouble("update_rate", 0), 40.0);
  EXPECT_EQ(params.sensorInt("ray/scan/horizontal/samples", 1), 1081);
  EXPECT_TRUE(params.sensorHas("ray/scan/horizontal"));
  EXPECT_FALSE(params.sensorHas("ray/range/min"));
  EXPECT_DOUBLE_EQ(params.sensorDouble("ray/range/min", 0.5), 0.5);
  EXPECT_EQ(errorOf([&] { params.sensorDouble("ray/scan/horizontal/min_angle", 0.0); }),
            "r.urdf:4: sensor 'laser' (ray): <ray><scan><horizontal><min_angle>: expected a number, got 'x'");
  // <min_angle> was read (if badly); <mni> never was
  EXPECT_EQ(errorOf([&] { params.checkAllUsed(); }),
            "r.urdf:5: sensor 'laser' (ray): unknown element <ray><range><mni>");
  params.ignore({"ray/range"});
  EXPECT_NO_THROW(params.checkAllUsed());
}

}  // namespace

TEST(PluginParams, SensorPoseAndNoiseAreReadAlikeForEverySensor) {
  Parsed p(
      "<sensor type=\"ray\" name=\"lidar\">\n<pose>0.1 0 0.2 0 0 1.5707963</pose>\n"
      "<ray><noise><type>gaussian</type><mean>0</mean><stddev>0.01</stddev></noise></ray>\n"
      "<plugin name=\"l\" filename=\"libgazebo_ros_laser.so\"/></sensor>");
  PluginParams params(p.plugin, p.sensor, "r.urdf", "base");
  const conde_physics::Pose pose = params.sensorPose();
  EXPECT_DOUBLE_EQ(pose.position.z, 0.2);
  EXPECT_NEAR(pose.orientation.yaw(), 1.5707963, 1e-9);
  const PluginParams::SensorNoise noise = params.sensorNoise("ray/noise");
  EXPECT_TRUE(noise.gaussian);
  EXPECT_DOUBLE_EQ(noise.stddev, 0.01);
  EXPECT_FALSE(params.sensorNoise("camera/noise").gaussian);  // no block: no noise

  Parsed bad(
      "<sensor type=\"ray\" name=\"lidar\">\n<pose>0 0 0.2</pose>\n<ray><noise><type>uniform</type></noise></ray>\n"
      "<plugin name=\"l\" filename=\"libgazebo_ros_laser.so\"/></sensor>");
  PluginParams bad_params(bad.plugin, bad.sensor, "r.urdf", "base");
  EXPECT_EQ(errorOf([&] { bad_params.sensorPose(); }),
            "r.urdf:2: sensor 'lidar' (ray): <pose>: expected six numbers 'x y z roll pitch yaw', got '0 0 0.2'");
  EXPECT_EQ(errorOf([&] { bad_params.sensorNoise("ray/noise"); }),
            "r.urdf:3: sensor 'lidar' (ray): <ray><noise><type>: unsupported noise type 'uniform' (expected "
            "gaussian or none)");
}

// Sensor plugins check where they sit in one place: a <sensor> of their type in a link's block.
TEST(PluginParams, SensorPluginsNameTheSensorTheyNeed) {
  Parsed imu(
      "<sensor name=\"imu\" type=\"imu\"><plugin name=\"i\" filename=\"libgazebo_ros_imu_sensor.so\"/></sensor>");
  EXPECT_EQ(PluginParams(imu.plugin, imu.sensor, "r.urdf", "imu_link").requireSensor({"imu"}), "imu_link");
  auto error = [](const Parsed& p, const std::string& link, const std::vector<std::string>& types) {
    return errorOf([&] { PluginParams(p.plugin, p.sensor, "r.urdf", link).requireSensor(types); });
  };
  EXPECT_EQ(error(imu, "imu_link", {"ray", "gpu_ray"}),
            "r.urdf:1: plugin 'i' (libgazebo_ros_imu_sensor.so): must sit in a <sensor type=\"ray\"> or "
            "<sensor type=\"gpu_ray\"> inside <gazebo reference=\"link\"> (got type 'imu')");
  EXPECT_EQ(error(imu, "", {"imu"}),
            "r.urdf:1: plugin 'i' (libgazebo_ros_imu_sensor.so): must sit in a <sensor type=\"imu\"> inside "
            "<gazebo reference=\"link\">");
  Parsed model_level("<plugin name=\"l\" filename=\"libgazebo_ros_laser.so\"/>");
  EXPECT_EQ(error(model_level, "", {"ray"}),
            "r.urdf:1: plugin 'l' (libgazebo_ros_laser.so): must sit in a <sensor type=\"ray\"> inside "
            "<gazebo reference=\"link\">");
  EXPECT_EQ(errorOf([&] { PluginParams(model_level.plugin, nullptr, "r.urdf", "").requireReferenceLink(); }),
            "r.urdf:1: plugin 'l' (libgazebo_ros_laser.so): must sit in <gazebo reference=\"link\">");
}

TEST(PluginParams, SeveralChildrenOfOneNameAreReadOneAtATime) {
  Parsed p(
      "<sensor type=\"multicamera\" name=\"stereo\">\n<camera name=\"left\"><image><width>64</width></image></camera>\n"
      "<camera name=\"right\">\n<pose>0 -0.1 0 0 0 0</pose>\n<image><width>-2</width><fov>1</fov></image></camera>\n"
      "<plugin name=\"p\" filename=\"libgazebo_ros_multicamera.so\"/></sensor>");
  PluginParams params(p.plugin, p.sensor, "robot.urdf", "base");
  const auto cameras = params.sensorChildren("camera");
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_DOUBLE_EQ(params.sensorDouble("camera/image/width", 1), 64);  // the first, without a selection
  params.selectSensorChild(cameras[1]);
  EXPECT_DOUBLE_EQ(params.sensorDouble("camera/image/width", 1), -2);
  EXPECT_DOUBLE_EQ(params.sensorPose("camera/pose").position.y, -0.1);
  EXPECT_EQ(params.sensorError("camera/image/width", "bad").what(),
            std::string("robot.urdf:5: sensor 'stereo' (multicamera): <camera name=\"right\"><image><width>: bad"));
  params.selectSensorChild(nullptr);
  EXPECT_DOUBLE_EQ(params.sensorPose("camera/pose").position.y, 0.0);  // the left camera has none
  // What was read counts for both cameras: only the right one's <fov> is unknown.
  EXPECT_EQ(errorOf([&] { params.checkAllUsed(); }),
            "robot.urdf:5: sensor 'stereo' (multicamera): unknown element <camera><image><fov>");
}
