#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <tinyxml2.h>

#include "conde_physics/urdf_model.h"

namespace cp = conde_physics;

namespace {

const char* kTwoWheeler = R"(<?xml version="1.0"?>
<robot name="two_wheeler">
  <link name="base_footprint"/>
  <joint name="base_joint" type="fixed">
    <parent link="base_footprint"/><child link="base_link"/>
    <origin xyz="-0.1 0 0.1" rpy="0 0 0"/>
  </joint>
  <link name="base_link">
    <inertial><origin xyz="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
    <collision><geometry><box size="0.3 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="payload_joint" type="fixed">
    <parent link="base_link"/><child link="payload"/>
    <origin xyz="0.2 0 0" rpy="0 0 0"/>
  </joint>
  <link name="payload">
    <inertial><mass value="2.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="left_wheel_joint" type="continuous">
    <parent link="base_link"/><child link="left_wheel"/>
    <origin xyz="0.1 0.15 -0.07" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit effort="5" velocity="20"/><dynamics damping="0.01" friction="0.02"/>
  </joint>
  <link name="left_wheel">
    <inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="2e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><origin rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.03" length="0.02"/></geometry></collision>
  </link>
  <gazebo reference="left_wheel"><mu1>100</mu1><mu2>50</mu2><kp>1e6</kp><kd>100</kd><material>Gazebo/Black</material></gazebo>
  <gazebo><plugin name="x" filename="libgazebo_ros_diff_drive.so"/></gazebo>
</robot>)";

TEST(UrdfModel, MergesFixedLinksAndCombinesMass) {
  std::vector<std::string> warnings;
  const cp::ArticulatedModel m = cp::buildModelFromUrdf(kTwoWheeler, "two_wheeler.urdf", nullptr, &warnings);
  ASSERT_EQ(m.bodies.size(), 2u);
  ASSERT_EQ(m.joints.size(), 1u);
  EXPECT_EQ(m.bodies[0].name, "base_footprint");
  EXPECT_EQ(m.bodies[0].merged_links, (std::vector<std::string>{"base_footprint", "base_link", "payload"}));
  EXPECT_DOUBLE_EQ(m.bodies[0].mass_kg, 4.0);
  // Two 2 kg masses at x = -0.1 and +0.1 in base_footprint: centre of mass at x = 0, z = 0.1.
  EXPECT_NEAR(m.bodies[0].inertial_frame.position.x, 0.0, 1e-12);
  EXPECT_NEAR(m.bodies[0].inertial_frame.position.z, 0.1, 1e-12);
  // Parallel axis: izz = 0.04 + 0.01 + 2 * (2 * 0.1^2) = 0.09.
  const cp::Vec3 moments = m.bodies[0].principal_inertia_kgm2;
  EXPECT_NEAR(moments.x + moments.y + moments.z, 0.02 + 0.03 + 0.04 + 0.03 + 2 * 2 * (2 * 0.01), 1e-9);
  int body = -1;
  cp::Pose payload;
  ASSERT_TRUE(m.linkInBody("payload", body, payload));
  EXPECT_EQ(body, 0);
  EXPECT_NEAR(payload.position.x, 0.1, 1e-12);
  EXPECT_NEAR(payload.position.z, 0.1, 1e-12);
  EXPECT_TRUE(warnings.empty());
}

TEST(UrdfModel, JointsAndSurfaces) {
  const cp::ArticulatedModel m = cp::buildModelFromUrdf(kTwoWheeler, "two_wheeler.urdf", nullptr);
  const cp::JointSpec& j = m.joints[0];
  EXPECT_EQ(j.name, "left_wheel_joint");
  EXPECT_EQ(j.type, cp::JointType::kContinuous);
  EXPECT_FALSE(j.has_position_limits);
  EXPECT_EQ(j.parent_body, 0);
  EXPECT_EQ(j.child_body, 1);
  EXPECT_NEAR(j.pose_in_parent.position.x, 0.0, 1e-12);  // -0.1 + 0.1
  EXPECT_NEAR(j.pose_in_parent.position.y, 0.15, 1e-12);
  EXPECT_NEAR(j.pose_in_parent.position.z, 0.03, 1e-12);  // 0.1 - 0.07: on the ground for r = 0.03
  EXPECT_DOUBLE_EQ(j.effort_limit, 5.0);
  EXPECT_DOUBLE_EQ(j.damping, 0.01);
  EXPECT_DOUBLE_EQ(j.friction, 0.02);
  EXPECT_NEAR(m.bodies[1].initial_pose_in_model.position.z, 0.03, 1e-12);
  ASSERT_EQ(m.bodies[1].collisions.size(), 1u);
  const cp::SurfaceParams& s = m.bodies[1].collisions[0].surface;
  EXPECT_DOUBLE_EQ(s.mu, 100.0);
  EXPECT_DOUBLE_EQ(s.mu2, 50.0);
  EXPECT_DOUBLE_EQ(s.stiffness_npm, 1e6);
  EXPECT_DOUBLE_EQ(s.damping_nspm, 100.0);
  EXPECT_DOUBLE_EQ(m.bodies[0].collisions[0].surface.mu, 1.0);  // default
}

std::string errorOf(const std::string& xml) {
  try {
    cp::buildModelFromUrdf(xml, "bad.urdf", nullptr);
  } catch (const cp::ModelError& e) {
    return e.what();
  }
  return "no error";
}

TEST(UrdfModel, MalformedXmlNamesTheLine) {
  EXPECT_EQ(errorOf("<robot name=\"r\">\n<link name=\"a\">\n</robot>"),
            "bad.urdf: malformed URDF: XML error at line 2: XML_ERROR_MISMATCHED_ELEMENT");
}

TEST(UrdfModel, UrdfdomErrorsAreReported) {
  const std::string msg = errorOf(
      "<robot name=\"r\"><link name=\"a\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/></joint></robot>");
  EXPECT_EQ(msg.rfind("bad.urdf: malformed URDF: ", 0), 0u) << msg;
  EXPECT_NE(msg.find("child"), std::string::npos) << msg;
}

TEST(UrdfModel, UnknownGazeboReferenceElementIsAnError) {
  EXPECT_EQ(errorOf("<robot name=\"r\">\n<link name=\"a\"/>\n<gazebo reference=\"a\">\n<mu3>1</mu3></gazebo></robot>"),
            "bad.urdf:4: <gazebo reference=\"a\">: unknown element <mu3>");
  EXPECT_EQ(errorOf("<robot name=\"r\">\n<link name=\"a\"/>\n<gazebo reference=\"a\"><mu1>lots</mu1></gazebo></robot>"),
            "bad.urdf:3: <gazebo reference=\"a\"> <mu1>: expected a number, got 'lots'");
}

TEST(UrdfModel, FloatingJointsAreRejected) {
  EXPECT_EQ(errorOf("<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>"
                    "<joint name=\"free\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>"),
            "bad.urdf: joint 'free': type floating is not supported");
}

TEST(UrdfModel, WorldLinkWeldsTheModel) {
  const cp::ArticulatedModel m = cp::buildModelFromUrdf(
      "<robot name=\"arm\"><link name=\"world\"/><joint name=\"weld\" type=\"fixed\"><parent link=\"world\"/>"
      "<child link=\"base\"/></joint><link name=\"base\"/></robot>",
      "arm.urdf", nullptr);
  EXPECT_TRUE(m.fixed_to_world);
  EXPECT_EQ(m.bodies[0].name, "base");
}

TEST(UrdfModel, MissingMeshFileIsAnError) {
  const std::string msg = errorOf(
      "<robot name=\"r\"><link name=\"a\"><collision><geometry><mesh filename=\"package://nowhere/m.stl\"/>"
      "</geometry></collision></link></robot>");
  EXPECT_EQ(msg,
            "bad.urdf: link 'a' <collision>: mesh 'package://nowhere/m.stl': unknown package 'nowhere' in "
            "'package://nowhere/m.stl'");
}

// A folder of mesh files for the tests below: a good ASCII STL, a corrupt one and a Git LFS
// pointer left where a Collada file should be (as in public robots cloned without LFS).
std::string meshFixtureDir() {
  const std::string dir = ::testing::TempDir() + "urdf_model_test_meshes";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/good.stl") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                      "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  std::ofstream(dir + "/corrupt.stl") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n";
  std::ofstream(dir + "/lfs.dae") << "version https://git-lfs.github.com/spec/v1\n"
                                     "oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\n"
                                     "size 12345\n";
  return dir;
}

std::string meshLink(const std::string& name, const std::string& element, const std::string& uri) {
  return "<link name=\"" + name + "\"><" + element + "><geometry><mesh filename=\"" + uri + "\"/></geometry></" +
         element + "></link>";
}

std::string chainOf(const std::vector<std::string>& links) {
  std::string urdf = "<robot name=\"r\">" + links[0];
  for (size_t i = 1; i < links.size(); ++i) {
    urdf += links[i] + "<joint name=\"j" + std::to_string(i) +
            "\" type=\"fixed\"><parent link=\"l0\"/><child link=\"l" + std::to_string(i) + "\"/></joint>";
  }
  return urdf + "</robot>";
}

// A collision mesh that does not load stops the model: the message names the description, the
// link and the file.
TEST(UrdfModel, CollisionMeshThatDoesNotLoadIsAnError) {
  const std::string dir = meshFixtureDir();
  const cp::PackageResolver packages = [&](const std::string& p) { return p == "fixture" ? dir : std::string(); };
  auto error = [&](const std::string& uri) {
    try {
      cp::buildModelFromUrdf(chainOf({meshLink("l0", "collision", uri)}), "robot.urdf", packages);
    } catch (const cp::ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("package://fixture/absent.stl"),
            "robot.urdf: link 'l0' <collision>: mesh file '" + dir + "/absent.stl': cannot open it");
  EXPECT_EQ(error("package://fixture/lfs.dae")
                .rfind("robot.urdf: link 'l0' <collision>: mesh file '" + dir + "/lfs.dae': ", 0),
            0u);
  EXPECT_EQ(error("package://fixture/corrupt.stl")
                .rfind("robot.urdf: link 'l0' <collision>: mesh file '" + dir + "/corrupt.stl': ", 0),
            0u);
  EXPECT_EQ(error("package://fixture/good.stl"), "no error");
}

// A visual mesh that does not load is what Gazebo reports and goes on with: the model loads,
// each such visual is listed once per link with the description, the link and the file.
TEST(UrdfModel, VisualMeshThatDoesNotLoadIsListedAndTheModelLoads) {
  const std::string dir = meshFixtureDir();
  const cp::PackageResolver packages = [&](const std::string& p) { return p == "fixture" ? dir : std::string(); };
  const cp::ArticulatedModel m =
      cp::buildModelFromUrdf(chainOf({meshLink("l0", "visual", "package://fixture/absent.stl"),
                                      meshLink("l1", "visual", "package://elsewhere/base.stl"),
                                      meshLink("l2", "visual", "package://fixture/good.stl"),
                                      meshLink("l3", "visual", "package://fixture/absent.stl"),
                                      meshLink("l4", "visual", "package://fixture/lfs.dae")}),
                             "robot.urdf", packages);
  ASSERT_EQ(m.visual_errors.size(), 4u);
  EXPECT_EQ(m.visual_errors[0], "robot.urdf: link 'l0' <visual>: mesh file '" + dir + "/absent.stl': cannot open it");
  EXPECT_EQ(m.visual_errors[1],
            "robot.urdf: link 'l1' <visual>: mesh 'package://elsewhere/base.stl': unknown package 'elsewhere' in "
            "'package://elsewhere/base.stl'");
  EXPECT_EQ(m.visual_errors[2], "robot.urdf: link 'l3' <visual>: mesh file '" + dir + "/absent.stl': cannot open it");
  EXPECT_EQ(m.visual_errors[3].rfind("robot.urdf: link 'l4' <visual>: mesh file '" + dir + "/lfs.dae': ", 0), 0u)
      << m.visual_errors[3];
}

}  // namespace

// The <gazebo> blocks are read once, with the model: plugins in document order, each sensor with
// its link, surfaces per link; the model-level flags Gazebo accepts pass, anything else is named.
TEST(GazeboBlocks, PluginsInDocumentOrderWithTheirSensorsAndLinks) {
  const std::string urdf =
      "<robot name=\"r\">\n<link name=\"a\"/>\n"
      "<gazebo><static>false</static><plugin name=\"drive\" filename=\"libdrive.so\"/></gazebo>\n"
      "<gazebo reference=\"a\"><mu1>0.4</mu1><sensor name=\"cam\" type=\"camera\">"
      "<plugin name=\"c\" filename=\"libcam.so\"/></sensor><sensor name=\"bare\" type=\"ray\"/></gazebo>\n"
      "<gazebo><plugin name=\"truth\" filename=\"libtruth.so\"/></gazebo>\n</robot>";
  cp::GazeboBlocks blocks;
  cp::buildModelFromUrdf(urdf, "r.urdf", nullptr, nullptr, &blocks);
  ASSERT_EQ(blocks.plugins.size(), 4u);
  EXPECT_STREQ(blocks.plugins[0].plugin->Attribute("filename"), "libdrive.so");
  EXPECT_EQ(blocks.plugins[0].sensor, nullptr);
  EXPECT_EQ(blocks.plugins[0].link, "");
  EXPECT_STREQ(blocks.plugins[1].plugin->Attribute("filename"), "libcam.so");
  EXPECT_STREQ(blocks.plugins[1].sensor->Attribute("name"), "cam");
  EXPECT_EQ(blocks.plugins[1].link, "a");
  EXPECT_EQ(blocks.plugins[2].plugin, nullptr);  // a sensor without a plugin
  EXPECT_STREQ(blocks.plugins[2].sensor->Attribute("name"), "bare");
  EXPECT_STREQ(blocks.plugins[3].plugin->Attribute("filename"), "libtruth.so");
  EXPECT_EQ(blocks.plugins[3].plugin->GetLineNum(), 5);
  EXPECT_DOUBLE_EQ(blocks.surfaces.at("a").mu, 0.4);
}

// Every <gazebo reference> key of Gazebo's URDF extension is accepted; those physics does not use
// are listed once each, where first written, for the simulator's log.
TEST(GazeboBlocks, KeysWithoutEffectAreListedOnce) {
  const std::string urdf =
      "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
      "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
      "<gazebo reference=\"a\"><mu1>0.9</mu1><mu2>0.8</mu2><kp>1e6</kp><kd>10</kd><material>Gazebo/Red</material>"
      "<minDepth>0.001</minDepth><maxVel>0</maxVel><fdir1>1 0 0</fdir1><maxContacts>4</maxContacts>"
      "<selfCollide>false</selfCollide><gravity>true</gravity><dampingFactor>0.01</dampingFactor>"
      "<turnGravityOff>false</turnGravityOff></gazebo>\n"
      "<gazebo reference=\"b\"><material>Gazebo/Blue</material></gazebo>\n"
      "<gazebo reference=\"j\"><implicitSpringDamper>true</implicitSpringDamper>"
      "<provideFeedback>true</provideFeedback><stopCfm>0.1</stopCfm><stopErp>0.2</stopErp></gazebo>\n</robot>";
  cp::GazeboBlocks blocks;
  cp::buildModelFromUrdf(urdf, "r.urdf", nullptr, nullptr, &blocks);
  std::vector<std::string> keys;
  for (const auto& [key, where] : blocks.without_effect) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"dampingFactor", "fdir1", "gravity", "implicitSpringDamper", "material",
                                            "maxContacts", "maxVel", "minDepth", "provideFeedback", "selfCollide",
                                            "stopCfm", "stopErp", "turnGravityOff"}));
  EXPECT_EQ(blocks.without_effect.at("material"), "r.urdf:5: <gazebo reference=\"a\">");
  EXPECT_EQ(blocks.without_effect.at("stopErp"), "r.urdf:7: <gazebo reference=\"j\">");
  EXPECT_DOUBLE_EQ(blocks.surfaces.at("a").mu, 0.9);
  EXPECT_DOUBLE_EQ(blocks.surfaces.at("a").mu2, 0.8);
  EXPECT_DOUBLE_EQ(blocks.surfaces.at("a").stiffness_npm, 1e6);
  EXPECT_DOUBLE_EQ(blocks.surfaces.at("a").damping_nspm, 10);
}

// Gazebo ignores a block whose reference names no link or joint (a typo in a public robot): so do
// we, with a warning.
TEST(GazeboBlocks, ReferenceToNoLinkIsSkippedWithAWarning) {
  cp::GazeboBlocks blocks;
  cp::buildModelFromUrdf(
      "<robot name=\"r\">\n<link name=\"a\"/>\n<gazebo reference=\"b\"><mu1>1</mu1><oops/></gazebo></robot>", "r.urdf",
      nullptr, nullptr, &blocks);
  EXPECT_EQ(blocks.warnings,
            std::vector<std::string>{
                "r.urdf:3: <gazebo reference=\"b\">: no link or joint named 'b': block ignored, as Gazebo ignores it"});
  EXPECT_EQ(blocks.surfaces.count("b"), 0u);
}

TEST(GazeboBlocks, UnknownModelLevelElementIsNamed) {
  EXPECT_EQ(errorOf("<robot name=\"r\">\n<link name=\"a\"/>\n<gazebo>\n<plugins/></gazebo></robot>"),
            "bad.urdf:4: <gazebo>: unknown element <plugins>");
  EXPECT_EQ(errorOf("<robot name=\"r\">\n<link name=\"a\"/>\n<gazebo reference=\"a\">\n<mu1>-1</mu1></gazebo></robot>"),
            "bad.urdf:3: <gazebo reference=\"a\"> <mu1>: must not be negative, got -1.000000");
}
