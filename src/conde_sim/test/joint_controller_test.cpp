// ros_control-style joint controllers on the test car, in-process, stepped, once per engine: the
// Major Alvega setup (two effort position controllers on the steering hinges, four effort velocity
// controllers on the wheels) and the other controller types.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "conde_sim/joint_controller.h"
#include "conde_sim/simulation.h"
#include "stepped_robot_setup.h"

namespace cp = conde_physics;
using conde_sim::JointController;
using conde_sim::JointControllerType;
using conde_sim::PidController;

namespace {

// The test car with ros_control instead of its Ackermann drive plugin.
const std::string& carUrdf() {
  static const std::string urdf =
      conde_sim_test::xacroUrdf("tests/fixtures/ackermann_car.urdf.xacro", "drive:=ros_control");
  return urdf;
}

// Gains of tests/fixtures/ackermann_car_controllers.yaml.
PidController::Gains steeringGains() { return {100.0, 100.0, 0.2, 0.1, 0.0}; }
PidController::Gains wheelGains() { return {0.1, 2.0, 0.0, 1.0, 0.0}; }

class JointControllers : public conde_sim_test::SteppedRobotTest {
 protected:
  void SetUp() override {
    cp::WorldDescription w = conde_sim_test::flatGround("flat");
    ASSERT_NO_FATAL_FAILURE(buildWorld(w, "car", "ackermann_car.urdf.xacro", carUrdf()));
  }

  JointController& add(const std::string& joint, JointControllerType type, const PidController::Gains& gains = {}) {
    const int index = sim_->robot(0).model.jointIndex(joint);
    EXPECT_GE(index, 0) << joint;
    controllers_.push_back(std::make_unique<JointController>(*sim_, 0, index, type, gains));
    return *controllers_.back();
  }

  void run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / sim_->stepS()));
    for (int i = 0; i < steps; ++i) {
      for (auto& c : controllers_) {
        c->update(sim_->stepS());
        c->apply();
      }
      sim_->step();
    }
  }

  double position(const std::string& joint) const {
    return sim_->engine().jointPosition(sim_->robot(0).id, sim_->robot(0).model.jointIndex(joint));
  }
  double velocity(const std::string& joint) const {
    return sim_->engine().jointVelocity(sim_->robot(0).id, sim_->robot(0).model.jointIndex(joint));
  }
  double speed() const {
    const cp::Twist t = sim_->linkTwist(0, "base_footprint");
    return std::hypot(t.linear_mps.x, t.linear_mps.y);
  }

  std::vector<std::unique_ptr<JointController>> controllers_;
};

TEST_P(JointControllers, MajorAlvegaSetupSteersAndDrives) {
  JointController& left = add("left_steering_joint", JointControllerType::kEffortPosition, steeringGains());
  JointController& right = add("right_steering_joint", JointControllerType::kEffortPosition, steeringGains());
  std::vector<JointController*> wheels;
  for (const char* w :
       {"left_front_wheel_joint", "right_front_wheel_joint", "left_rear_wheel_joint", "right_rear_wheel_joint"}) {
    wheels.push_back(&add(w, JointControllerType::kEffortVelocity, wheelGains()));
  }
  run(0.3);  // the position controllers hold the hinges where they started
  EXPECT_NEAR(position("left_steering_joint"), 0.0, 0.005);
  ASSERT_TRUE(left.setCommand(0.3));
  ASSERT_TRUE(right.setCommand(0.25));
  for (JointController* w : wheels) ASSERT_TRUE(w->setCommand(10.0));
  run(0.3);
  EXPECT_NEAR(position("left_steering_joint"), 0.3, 0.01);
  EXPECT_NEAR(position("right_steering_joint"), 0.25, 0.01);
  run(1.7);
  EXPECT_NEAR(position("left_steering_joint"), 0.3, 0.005);
  EXPECT_NEAR(velocity("left_rear_wheel_joint"), 10.0, 0.5);
  EXPECT_NEAR(speed(), 0.5, 0.05);                                       // 10 rad/s on 0.05 m wheels
  EXPECT_GT(sim_->linkTwist(0, "base_footprint").angular_radps.z, 0.2);  // turning left
}

TEST_P(JointControllers, PositionTargetsStayWithinTheJointLimits) {
  JointController& left = add("left_steering_joint", JointControllerType::kEffortPosition, steeringGains());
  left.setCommand(2.0);
  EXPECT_DOUBLE_EQ(left.command(), 0.6);  // URDF upper limit
  run(0.5);
  EXPECT_NEAR(position("left_steering_joint"), 0.6, 0.01);
  EXPECT_FALSE(left.setCommand(std::nan("")));
  EXPECT_DOUBLE_EQ(left.command(), 0.6);
}

TEST_P(JointControllers, VelocityControllersDriveTheWheelsWithMotors) {
  for (const char* w : {"left_rear_wheel_joint", "right_rear_wheel_joint"}) {
    add(w, JointControllerType::kVelocity).setCommand(-8.0);
  }
  add("left_steering_joint", JointControllerType::kPosition).setCommand(0.0);
  add("right_steering_joint", JointControllerType::kPosition).setCommand(0.0);
  run(1.5);
  EXPECT_NEAR(velocity("left_rear_wheel_joint"), -8.0, 0.2);
  EXPECT_NEAR(sim_->linkTwist(0, "base_footprint").linear_mps.x, -0.4, 0.03);  // reversing
}

TEST_P(JointControllers, PositionControllerServoesTheHinge) {
  add("left_steering_joint", JointControllerType::kPosition).setCommand(-0.4);
  run(0.5);
  EXPECT_NEAR(position("left_steering_joint"), -0.4, 0.005);
}

TEST_P(JointControllers, EffortControllerAppliesItsCommand) {
  JointController& c = add("left_steering_joint", JointControllerType::kEffort);
  c.setCommand(0.5);  // [N m]: turns the hinge against the tyre until the stop
  run(1.0);
  EXPECT_GT(position("left_steering_joint"), 0.55);
  c.setCommand(-100.0);
  EXPECT_DOUBLE_EQ(c.command(), -5.0);  // URDF effort limit
}

TEST_P(JointControllers, EmergencyStopHoldsAndBrakes) {
  JointController& steer = add("left_steering_joint", JointControllerType::kEffortPosition, steeringGains());
  JointController& wheel = add("left_rear_wheel_joint", JointControllerType::kEffortVelocity, wheelGains());
  steer.setCommand(0.2);
  wheel.setCommand(10.0);
  run(1.0);
  for (auto& c : controllers_) c->setStopped(true);
  run(0.1);
  EXPECT_EQ(wheel.effort(), 0.0);
  EXPECT_EQ(steer.effort(), 0.0);
  for (auto& c : controllers_) c->setStopped(false);
  run(0.5);
  EXPECT_NEAR(position("left_steering_joint"), 0.2, 0.01);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, JointControllers, conde_sim_test::bothEngines(), conde_sim_test::engineName);

TEST(JointControllerType, NamesRoundTrip) {
  for (auto t : {JointControllerType::kEffortPosition, JointControllerType::kEffortVelocity,
                 JointControllerType::kEffort, JointControllerType::kVelocity, JointControllerType::kPosition}) {
    JointControllerType parsed;
    ASSERT_TRUE(conde_sim::parseJointControllerType(conde_sim::jointControllerTypeName(t), parsed));
    EXPECT_EQ(parsed, t);
  }
  JointControllerType unused;
  EXPECT_FALSE(conde_sim::parseJointControllerType("diff_drive_controller/DiffDriveController", unused));
}

}  // namespace
