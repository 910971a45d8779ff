// The simulation's Gazebo-style model access without ROS, once per engine: models by name
// (robots and dynamic world objects), rigid teleports with a velocity, link wrenches, and robots
// removed and added again while the world runs.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "conde_physics/urdf_model.h"
#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;
using conde_sim::ModelRef;
using conde_sim_test::addRobot;
using conde_sim_test::condeUrdf;

namespace {

// Flat ground, a static wall and a dynamic 1 kg crate.
cp::WorldDescription crateWorld() {
  cp::WorldDescription w = conde_sim_test::flatGround("crate");
  cp::WorldObject wall;
  wall.name = "wall";
  wall.size_m = cp::Vec3(0.1, 2, 0.5);
  wall.pose = cp::Pose::fromXyzRpy(-3, 0, 0.25, 0, 0, 0);
  w.objects.push_back(wall);
  cp::WorldObject crate;
  crate.name = "crate";
  crate.size_m = cp::Vec3(0.2, 0.2, 0.2);
  crate.pose = cp::Pose::fromXyzRpy(2, 0, 0.1, 0, 0, 0);
  crate.is_static = false;
  crate.mass_kg = 1.0;
  w.objects.push_back(crate);
  return w;
}

class SimulationModels : public conde_sim_test::SteppedRobotTest {
 protected:
  void SetUp() override { ASSERT_NO_FATAL_FAILURE(buildWorld(crateWorld(), "conde", "conde.urdf.xacro", condeUrdf())); }
  void run(int steps) {
    conde_sim::StepLoop loop(*sim_);
    loop.run(steps);
  }
};

TEST_P(SimulationModels, FindsRobotsAndDynamicObjectsByName) {
  const ModelRef conde = sim_->findModel("conde");
  EXPECT_EQ(conde.robot, 0);
  const ModelRef crate = sim_->findModel("crate");
  EXPECT_EQ(crate.object, 1);
  EXPECT_FALSE(sim_->findModel("wall").valid());  // static objects are part of the world
  EXPECT_FALSE(sim_->findModel("nobody").valid());
  ASSERT_EQ(sim_->models().size(), 2u);
  EXPECT_EQ(sim_->modelName(sim_->models()[1]), "crate");
  EXPECT_EQ(sim_->bodyLinkNames(conde).front(), "base_footprint");
  EXPECT_TRUE(sim_->hasLink(conde, "imu_link"));  // merged into base_footprint's body
  EXPECT_FALSE(sim_->hasLink(conde, "crate"));
  EXPECT_THROW(sim_->linkPose(conde, "nolink"), std::out_of_range);
}

TEST_P(SimulationModels, SetModelStateMovesTheWholeRobotRigidly) {
  run(200);
  const ModelRef conde = sim_->findModel("conde");
  const cp::Pose wheel_in_root = sim_->linkPose(conde, "").inverse() * sim_->linkPose(conde, "left_wheel");
  cp::Twist twist;
  twist.linear_mps = cp::Vec3(0.3 * std::cos(1.2), 0.3 * std::sin(1.2), 0);  // straight ahead
  const cp::Pose target = cp::Pose::fromXyzRpy(1.0, -0.5, 0.0, 0, 0, 1.2);
  sim_->setModelState(conde, target, twist);
  const cp::Pose root = sim_->linkPose(conde, "");
  EXPECT_NEAR(root.position.x, 1.0, 1e-9);
  EXPECT_NEAR(root.position.y, -0.5, 1e-9);
  EXPECT_NEAR(root.orientation.yaw(), 1.2, 1e-9);
  const cp::Pose wheel = sim_->linkPose(conde, "left_wheel");
  const cp::Pose expected = target * wheel_in_root;
  EXPECT_NEAR(wheel.position.x, expected.position.x, 1e-9);
  EXPECT_NEAR(wheel.position.y, expected.position.y, 1e-9);
  EXPECT_NEAR(sim_->linkTwist(conde, "left_wheel").linear_mps.y, 0.3 * std::sin(1.2), 1e-9);
  run(100);  // it stays together and rolls on
  EXPECT_GT(sim_->linkPose(conde, "").position.y, -0.5 + 0.005);
  EXPECT_NEAR(sim_->linkPose(conde, "").orientation.yaw(), 1.2, 0.05);
}

TEST_P(SimulationModels, LinkWrenchPushesADynamicObject) {
  const ModelRef crate = sim_->findModel("crate");
  for (int i = 0; i < 200; ++i) {  // 20 N for 0.2 s against friction
    sim_->addLinkWrench(crate, "crate", cp::Vec3(20, 0, 0), cp::Vec3(), sim_->linkPose(crate, "crate").position);
    run(1);
  }
  EXPECT_GT(sim_->linkPose(crate, "").position.x, 2.05);
}

TEST_P(SimulationModels, RemovedRobotIsGoneAndItsNameFree) {
  run(100);
  sim_->renderScene();  // cameras' scene exists: the robot must leave it too
  sim_->removeRobot(0);
  EXPECT_FALSE(sim_->findModel("conde").valid());
  EXPECT_EQ(sim_->findRobot(""), -1);
  EXPECT_EQ(sim_->models().size(), 1u);
  run(100);
  sim_->resetWorld();  // does not bring it back
  EXPECT_FALSE(sim_->findModel("conde").valid());
  run(100);
  const int again = addRobot(*sim_, "conde", "conde.urdf.xacro", condeUrdf(), cp::Pose::fromXyzRpy(0.5, 0, 0, 0, 0, 0));
  EXPECT_EQ(again, 1);
  EXPECT_EQ(sim_->findModel("conde").robot, 1);
  EXPECT_EQ(sim_->findRobot(""), 1);
  run(100);
  EXPECT_NEAR(sim_->linkPose(sim_->findModel("conde"), "").position.x, 0.5, 0.01);
  EXPECT_THROW(addRobot(*sim_, "conde", "second.urdf", condeUrdf()), cp::ModelError);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, SimulationModels, conde_sim_test::bothEngines(), conde_sim_test::engineName);

}  // namespace
