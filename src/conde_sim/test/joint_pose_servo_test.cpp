// The joint pose servo (joint_pose_servo.h) on both engines: an arm on a post welded to the
// world, its joints turning about z; what each joint moves; the URDF velocity limit honoured.
#include "conde_sim/joint_pose_servo.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;

namespace {

// Shoulder limited to 0.5 rad/s, elbow to 4 rad/s; efforts 50 N m.
const char* kArm = R"(<robot name="arm">
  <link name="world"/>
  <joint name="weld" type="fixed"><parent link="world"/><child link="post"/></joint>
  <link name="post"><inertial><origin xyz="0 0 0.25"/><mass value="2"/>
    <inertia ixx="0.05" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.01"/></inertial></link>
  <joint name="shoulder_joint" type="revolute"><parent link="post"/><child link="upper_arm"/>
    <origin xyz="0 0 0.55"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="50" velocity="0.5"/></joint>
  <link name="upper_arm"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.014" iyz="0" izz="0.014"/></inertial></link>
  <joint name="elbow_joint" type="revolute"><parent link="upper_arm"/><child link="forearm"/>
    <origin xyz="0.4 0 0.06"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="50" velocity="4"/></joint>
  <link name="forearm"><inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
    <inertia ixx="0.0005" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/></inertial></link>
</robot>)";

class JointPoseServoTest : public conde_sim_test::SteppedRobotTest {
 protected:
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(buildWorld(conde_sim_test::flatGround("arm"), "arm", "arm.urdf", kArm));
  }
  int joint(const std::string& name) const { return sim_->robot(0).model.jointIndex(name); }
};

TEST_P(JointPoseServoTest, FindsWhatEachJointMovesOnce) {
  const cp::ArticulatedModel& model = sim_->robot(0).model;
  EXPECT_EQ(conde_sim::bodiesMovedBy(model, joint("shoulder_joint")).size(), 2u);
  EXPECT_EQ(conde_sim::bodiesMovedBy(model, joint("elbow_joint")), std::vector<int>{model.bodyIndex("forearm")});
}

// One joint at a time: while both move, the elbow's motor torque turns the upper arm too.
TEST_P(JointPoseServoTest, HonoursTheUrdfVelocityLimit) {
  const int shoulder = joint("shoulder_joint"), elbow = joint("elbow_joint");
  const conde_sim::JointPoseServo servo(*sim_, 0, {shoulder, elbow});
  const cp::ModelId id = sim_->robot(0).id;
  double shoulder_peak = 0.0, elbow_peak = 0.0, shoulder_at_1s = 0.0;
  conde_sim::StepLoop loop(*sim_);
  for (int i = 1; i <= 3000; ++i) {  // the shoulder to 1 rad, the elbow held
    servo.drive(*sim_, {1.0, 0.0});
    loop.run(1);
    shoulder_peak = std::max(shoulder_peak, std::abs(sim_->engine().jointVelocity(id, shoulder)));
    if (i == 1000) shoulder_at_1s = sim_->engine().jointPosition(id, shoulder);
  }
  for (int i = 1; i <= 1000; ++i) {  // then the elbow to 1 rad
    servo.drive(*sim_, {1.0, 1.0});
    loop.run(1);
    elbow_peak = std::max(elbow_peak, std::abs(sim_->engine().jointVelocity(id, elbow)));
  }
  EXPECT_LT(shoulder_peak, 0.5 * 1.02);
  EXPECT_NEAR(shoulder_at_1s, 0.5, 0.02);  // 1 s at 0.5 rad/s
  EXPECT_LT(elbow_peak, 4.0 * 1.02);
  EXPECT_GT(elbow_peak, 3.5);  // its own limit, not the shoulder's
  EXPECT_NEAR(sim_->engine().jointPosition(id, shoulder), 1.0, 0.005);
  EXPECT_NEAR(sim_->engine().jointPosition(id, elbow), 1.0, 0.005);
  std::printf(
      "%s: shoulder (limit 0.5 rad/s) peak %.4f rad/s, at 1 s %.4f rad; elbow (limit 4 rad/s) peak %.4f rad/s\n",
      GetParam().c_str(), shoulder_peak, shoulder_at_1s, elbow_peak);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, JointPoseServoTest, conde_sim_test::bothEngines(), conde_sim_test::engineName);

}  // namespace
