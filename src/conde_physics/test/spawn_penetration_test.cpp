// A robot spawned with its wheels in the ground (Gazebo users' `spawn_model -z 0` for a robot
// whose root link is its chassis centre) must climb out and rest, not be thrown: both engines.
// Gazebo (ODE) caps the velocity that corrects a penetration at the surface's <max_vel>, 0.01 m/s
// by default, so such a robot rises slowly; an uncapped correction of 5 cm in one 1 ms step is
// tens of m/s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "conde_physics/physics_engine.h"
#include "conde_physics/urdf_model.h"

namespace cp = conde_physics;

namespace {

// A small skid-steer robot written for this test: a 4 kg chassis 0.30 x 0.20 x 0.08 m, four
// wheels of radius 0.05 m whose axles are 0.03 m below the chassis centre, so that the chassis
// centre is 0.08 m above the ground when the robot stands on its wheels.
constexpr double kStandingHeightM = 0.08;

std::string wheel(const std::string& name, double x_m, double y_m) {
  return "<joint name=\"" + name + "_joint\" type=\"continuous\"><parent link=\"chassis\"/><child link=\"" + name +
         "\"/><origin xyz=\"" + std::to_string(x_m) + " " + std::to_string(y_m) +
         " -0.03\"/><axis xyz=\"0 1 0\"/></joint>"
         "<link name=\"" +
         name +
         "\"><inertial><mass value=\"0.2\"/><inertia ixx=\"1.5e-4\" ixy=\"0\" ixz=\"0\" iyy=\"2.5e-4\" iyz=\"0\" "
         "izz=\"1.5e-4\"/></inertial><collision><origin rpy=\"1.5707963 0 0\"/><geometry><cylinder radius=\"0.05\" "
         "length=\"0.04\"/></geometry></collision></link>";
}

std::string skidSteerUrdf() {
  return "<robot name=\"skid\"><link name=\"chassis\"><inertial><mass value=\"4\"/>"
         "<inertia ixx=\"0.016\" ixy=\"0\" ixz=\"0\" iyy=\"0.032\" iyz=\"0\" izz=\"0.043\"/></inertial>"
         "<collision><geometry><box size=\"0.30 0.20 0.08\"/></geometry></collision></link>" +
         wheel("front_left", 0.1, 0.13) + wheel("front_right", 0.1, -0.13) + wheel("rear_left", -0.1, 0.13) +
         wheel("rear_right", -0.1, -0.13) + "</robot>";
}

struct Outcome {
  double peak_speed_mps = 0.0;  // largest speed of the chassis while it climbs out
  double final_z_m = 0.0;
  double final_speed_mps = 0.0;
};

Outcome spawnPenetrating(const std::string& engine_name, double depth_m, double seconds) {
  auto engine = cp::createPhysicsEngine(engine_name, cp::PhysicsSettings());
  cp::SurfaceParams ground;
  engine->addGroundPlane(ground);
  const cp::ArticulatedModel model = cp::buildModelFromUrdf(skidSteerUrdf(), "skid.urdf", nullptr);
  const cp::ModelId id = engine->addModel(model, cp::Pose::fromXyzRpy(0, 0, kStandingHeightM - depth_m, 0, 0, 0));
  Outcome out;
  const int steps = static_cast<int>(seconds / engine->settings().step_s);
  for (int i = 0; i < steps; ++i) {
    engine->step();
    out.peak_speed_mps = std::max(out.peak_speed_mps, engine->bodyTwist(id, 0).linear_mps.norm());
  }
  out.final_z_m = engine->bodyPose(id, 0).position.z;
  out.final_speed_mps = engine->bodyTwist(id, 0).linear_mps.norm();
  std::printf("%s, spawned %.2f m deep: peak speed %.4f m/s, after %.0f s z %.4f m (standing %.2f m), speed %.5f m/s\n",
              engine_name.c_str(), depth_m, out.peak_speed_mps, seconds, out.final_z_m, kStandingHeightM,
              out.final_speed_mps);
  return out;
}

class SpawnPenetration : public ::testing::TestWithParam<std::string> {};

TEST_P(SpawnPenetration, WheelsTwoCentimetresInTheGroundClimbOutAndRest) {
  const Outcome o = spawnPenetrating(GetParam(), 0.02, 3.0);
  EXPECT_LT(o.peak_speed_mps, 0.1);
  EXPECT_NEAR(o.final_z_m, kStandingHeightM, 0.003);
  EXPECT_LT(o.final_speed_mps, 0.005);
}

TEST_P(SpawnPenetration, WheelsFiveCentimetresInTheGroundClimbOutAndRest) {
  const Outcome o = spawnPenetrating(GetParam(), 0.05, 6.0);
  EXPECT_LT(o.peak_speed_mps, 0.1);
  EXPECT_NEAR(o.final_z_m, kStandingHeightM, 0.003);
  EXPECT_LT(o.final_speed_mps, 0.005);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, SpawnPenetration, ::testing::Values("ode", "bullet"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
