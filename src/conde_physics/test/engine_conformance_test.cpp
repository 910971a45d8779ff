// One conformance suite for every physics backend: each TEST_P runs once on ODE and once on
// Bullet. The scenarios are built in-process and stepped; nothing sleeps.
#include <gtest/gtest.h>

#include <cmath>

#include "conde_physics/physics_engine.h"
#include "test_models.h"

namespace cp = conde_physics;

namespace {

cp::BodySpec makeBody(const std::string& name, double mass_kg, const cp::Inertia& inertia,
                      const cp::Pose& pose_in_model) {
  cp::BodySpec body;
  body.name = name;
  body.merged_links = {name};
  body.merged_link_poses = {cp::Pose()};
  body.mass_kg = mass_kg;
  cp::Quat axes;
  cp::principalAxes(inertia, body.principal_inertia_kgm2, axes);
  body.inertial_frame = cp::Pose(cp::Vec3(), axes);
  body.initial_pose_in_model = pose_in_model;
  return body;
}

cp::CollisionSpec boxCollision(const cp::Vec3& size_m, const cp::Pose& pose = cp::Pose()) {
  cp::CollisionSpec c;
  c.shape.type = cp::ShapeType::kBox;
  c.shape.box_size_m = size_m;
  c.pose_in_link = pose;
  return c;
}

// A 0.2 m cube of 1 kg.
cp::ArticulatedModel makeCube() {
  cp::ArticulatedModel m;
  m.name = "cube";
  m.bodies.push_back(makeBody("cube", 1.0, cp::boxInertia(1.0, {0.2, 0.2, 0.2}), cp::Pose()));
  m.bodies[0].collisions.push_back(boxCollision({0.2, 0.2, 0.2}));
  return m;
}

constexpr double kWheelRadius = 0.032;  // Conde's drive wheels [m]
constexpr double kWheelSeparation = 0.33;

// Conde-like cart: a chassis box, two driven wheels on continuous joints about +y and a
// frictionless skid sphere at the back. Root link frame on the ground under the axle centre.
cp::ArticulatedModel makeCart() {
  cp::ArticulatedModel m;
  m.name = "cart";
  cp::BodySpec chassis = makeBody("chassis", 5.0, cp::boxInertia(5.0, {0.4, 0.3, 0.1}), cp::Pose());
  chassis.inertial_frame.position = cp::Vec3(-0.15, 0, 0.1);
  chassis.collisions.push_back(boxCollision({0.4, 0.3, 0.1}, cp::Pose(cp::Vec3(-0.15, 0, 0.1), cp::Quat())));
  cp::CollisionSpec skid;
  skid.shape.type = cp::ShapeType::kSphere;
  skid.shape.radius_m = kWheelRadius;
  skid.pose_in_link = cp::Pose(cp::Vec3(-0.3, 0, kWheelRadius), cp::Quat());
  skid.surface.mu = skid.surface.mu2 = 0.0;
  chassis.collisions.push_back(skid);
  m.bodies.push_back(chassis);

  for (int side = 0; side < 2; ++side) {
    const double y = side == 0 ? kWheelSeparation / 2 : -kWheelSeparation / 2;
    const cp::Pose wheel_pose(cp::Vec3(0, y, kWheelRadius), cp::Quat());
    // Cylinder inertia about its own z axis, rotated so the spin axis is the link's y axis.
    const cp::Quat cyl_to_link = cp::Quat::fromRpy(M_PI / 2, 0, 0);
    cp::BodySpec wheel =
        makeBody(side == 0 ? "left_wheel" : "right_wheel", 0.1,
                 cp::rotateInertia(cp::cylinderInertia(0.1, kWheelRadius, 0.03), cyl_to_link), wheel_pose);
    cp::CollisionSpec tyre;
    tyre.shape.type = cp::ShapeType::kCylinder;
    tyre.shape.radius_m = kWheelRadius;
    tyre.shape.length_m = 0.03;
    tyre.pose_in_link = cp::Pose(cp::Vec3(), cyl_to_link);
    tyre.surface.mu = tyre.surface.mu2 = 100.0;
    wheel.collisions.push_back(tyre);
    m.bodies.push_back(wheel);

    conde_physics_test::addJoint(m, side == 0 ? "left_wheel_joint" : "right_wheel_joint", cp::JointType::kContinuous, 0,
                                 static_cast<int>(m.bodies.size()) - 1, wheel_pose);
  }
  return m;
}

// A 0.5 m arm hanging from a revolute joint about +y, welded to the world, limits ±0.5 rad.
cp::ArticulatedModel makePendulum() {
  cp::ArticulatedModel m;
  m.name = "pendulum";
  m.fixed_to_world = true;
  m.bodies.push_back(makeBody("base", 1.0, cp::boxInertia(1.0, {0.1, 0.1, 0.1}), cp::Pose()));
  const cp::Pose joint_pose(cp::Vec3(0, 0, 1.0), cp::Quat());
  cp::BodySpec arm = makeBody("arm", 1.0, cp::boxInertia(1.0, {0.05, 0.05, 0.5}), joint_pose);
  arm.inertial_frame.position = cp::Vec3(0.25, 0, 0);  // centre of mass off the axis: it swings
  arm.collisions.push_back(boxCollision({0.5, 0.05, 0.05}, cp::Pose(cp::Vec3(0.25, 0, 0), cp::Quat())));
  m.bodies.push_back(arm);
  cp::JointSpec& joint = conde_physics_test::addJoint(m, "hinge", cp::JointType::kRevolute, 0, 1, joint_pose);
  joint.has_position_limits = true;
  joint.lower = -0.5;
  joint.upper = 0.5;
  return m;
}

class EngineConformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<cp::PhysicsEngine> makeEngine(const cp::PhysicsSettings& s = cp::PhysicsSettings()) {
    auto engine = cp::createPhysicsEngine(GetParam(), s);
    cp::SurfaceParams ground;
    ground.mu = ground.mu2 = 100.0;
    engine->addGroundPlane(ground);
    return engine;
  }
  static void stepFor(cp::PhysicsEngine& engine, double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / engine.settings().step_s));
    for (int i = 0; i < steps; ++i) engine.step();
  }
};

TEST_P(EngineConformance, ReportsItsName) { EXPECT_EQ(makeEngine()->name(), GetParam()); }

TEST_P(EngineConformance, DroppedBoxRestsOnTheGround) {
  auto engine = makeEngine();
  const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0.3, -0.2, 0.5, 0, 0, 0.4));
  stepFor(*engine, 2.0);
  const cp::Pose pose = engine->bodyPose(cube, 0);
  EXPECT_NEAR(pose.position.z, 0.1, 0.002);
  EXPECT_NEAR(pose.position.x, 0.3, 0.002);
  EXPECT_NEAR(pose.position.y, -0.2, 0.002);
  EXPECT_NEAR(pose.orientation.yaw(), 0.4, 0.01);
  EXPECT_LT(engine->bodyTwist(cube, 0).linear_mps.norm(), 0.005);
}

TEST_P(EngineConformance, BoxRestsOnAStaticBox) {
  auto engine = makeEngine();
  cp::Shape table;
  table.type = cp::ShapeType::kBox;
  table.box_size_m = cp::Vec3(1.0, 1.0, 0.4);
  engine->addStaticShape(table, cp::Pose::fromXyzRpy(0, 0, 0.2, 0, 0, 0), cp::SurfaceParams());
  const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.8, 0, 0, 0));
  stepFor(*engine, 2.0);
  EXPECT_NEAR(engine->bodyPose(cube, 0).position.z, 0.5, 0.002);
}

TEST_P(EngineConformance, DrivenWheelsRollAtOmegaTimesRadius) {
  auto engine = makeEngine();
  const cp::ArticulatedModel cart = makeCart();
  const cp::ModelId id = engine->addModel(cart, cp::Pose());
  const double omega_radps = 10.0;
  engine->setJointVelocityMotor(id, 0, omega_radps, 5.0);
  engine->setJointVelocityMotor(id, 1, omega_radps, 5.0);
  stepFor(*engine, 1.0);  // accelerate
  const double x0 = engine->bodyPose(id, 0).position.x;
  stepFor(*engine, 2.0);
  const double speed_mps = (engine->bodyPose(id, 0).position.x - x0) / 2.0;
  EXPECT_NEAR(speed_mps, omega_radps * kWheelRadius, 0.02 * omega_radps * kWheelRadius);
  EXPECT_NEAR(engine->jointVelocity(id, 0), omega_radps, 0.02 * omega_radps);
  EXPECT_NEAR(engine->bodyTwist(id, 0).linear_mps.x, omega_radps * kWheelRadius, 0.02 * omega_radps * kWheelRadius);
  EXPECT_NEAR(engine->bodyPose(id, 0).position.y, 0.0, 0.01);  // straight
}

TEST_P(EngineConformance, OppositeWheelSpeedsTurnInPlace) {
  auto engine = makeEngine();
  const cp::ModelId id = engine->addModel(makeCart(), cp::Pose());
  const double omega_radps = 5.0;
  engine->setJointVelocityMotor(id, 0, -omega_radps, 5.0);  // left backwards
  engine->setJointVelocityMotor(id, 1, omega_radps, 5.0);   // right forwards: turn left (+yaw)
  stepFor(*engine, 1.0);
  const double yaw0 = engine->bodyPose(id, 0).orientation.yaw();
  stepFor(*engine, 0.5);
  const double yaw_rate = cp::wrapAngle(engine->bodyPose(id, 0).orientation.yaw() - yaw0) / 0.5;
  const double expected = 2 * omega_radps * kWheelRadius / kWheelSeparation;
  EXPECT_NEAR(yaw_rate, expected, 0.03 * expected);
}

TEST_P(EngineConformance, JointPositionIntegratesVelocity) {
  auto engine = makeEngine();
  const cp::ModelId id = engine->addModel(makeCart(), cp::Pose());
  EXPECT_NEAR(engine->jointPosition(id, 0), 0.0, 1e-9);
  engine->setJointVelocityMotor(id, 0, 2.0, 5.0);
  engine->setJointVelocityMotor(id, 1, 2.0, 5.0);
  stepFor(*engine, 3.0);
  // Continuous joints are not wrapped: about 6 rad minus the spin-up.
  EXPECT_GT(engine->jointPosition(id, 0), 5.0);
  EXPECT_LT(engine->jointPosition(id, 0), 6.1);
}

TEST_P(EngineConformance, MotorOffLetsTheCartCoastAndStop) {
  auto engine = makeEngine();
  const cp::ModelId id = engine->addModel(makeCart(), cp::Pose());
  engine->setJointVelocityMotor(id, 0, 10.0, 5.0);
  engine->setJointVelocityMotor(id, 1, 10.0, 5.0);
  stepFor(*engine, 1.0);
  // Braking is a zero-velocity motor with torque; the cart stops within a few cm.
  engine->setJointVelocityMotor(id, 0, 0.0, 5.0);
  engine->setJointVelocityMotor(id, 1, 0.0, 5.0);
  stepFor(*engine, 1.0);
  EXPECT_LT(std::abs(engine->bodyTwist(id, 0).linear_mps.x), 0.005);
}

TEST_P(EngineConformance, RevoluteJointRespectsItsLimits) {
  auto engine = makeEngine();
  const cp::ModelId id = engine->addModel(makePendulum(), cp::Pose());
  // Gravity pulls the arm (centre of mass at +x) down: rotation about +y is positive.
  double max_angle = -1e9, min_angle = 1e9;
  for (int i = 0; i < 2000; ++i) {
    engine->step();
    max_angle = std::max(max_angle, engine->jointPosition(id, 0));
    min_angle = std::min(min_angle, engine->jointPosition(id, 0));
  }
  EXPECT_LT(max_angle, 0.5 + 0.02);
  EXPECT_GT(min_angle, -0.02);
  EXPECT_NEAR(engine->jointPosition(id, 0), 0.5, 0.02);  // resting on the upper stop
  // Drive it the other way with a motor: it stops at the lower limit.
  engine->setJointVelocityMotor(id, 0, -2.0, 50.0);
  for (int i = 0; i < 2000; ++i) {
    engine->step();
    min_angle = std::min(min_angle, engine->jointPosition(id, 0));
  }
  EXPECT_GT(min_angle, -0.5 - 0.02);
  EXPECT_NEAR(engine->jointPosition(id, 0), -0.5, 0.02);
  // The base is welded to the world.
  EXPECT_NEAR(engine->bodyPose(id, 0).position.norm(), 0.0, 1e-6);
}

TEST_P(EngineConformance, EffortAccumulatesOverOneStepOnly) {
  auto engine = makeEngine();
  cp::ArticulatedModel pendulum = makePendulum();
  pendulum.joints[0].has_position_limits = false;
  pendulum.bodies[1].inertial_frame.position = cp::Vec3();  // balanced: gravity has no torque
  const cp::ModelId id = engine->addModel(pendulum, cp::Pose());
  for (int i = 0; i < 100; ++i) {
    engine->addJointEffort(id, 0, 0.5);
    engine->step();
  }
  const double v = engine->jointVelocity(id, 0);
  EXPECT_GT(v, 0.1);
  for (int i = 0; i < 100; ++i) engine->step();  // no effort: velocity stays (no damping)
  EXPECT_NEAR(engine->jointVelocity(id, 0), v, 0.05 * v);
}

TEST_P(EngineConformance, SameInputsGiveIdenticalTrajectories) {
  auto run = [&]() {
    auto engine = makeEngine();
    const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(1, 1, 0.3, 0.2, 0.1, 0));
    const cp::ModelId cart = engine->addModel(makeCart(), cp::Pose());
    std::vector<double> trace;
    for (int i = 0; i < 1500; ++i) {
      engine->setJointVelocityMotor(cart, 0, 5.0 + 3.0 * std::sin(i * 0.01), 5.0);
      engine->setJointVelocityMotor(cart, 1, 5.0, 5.0);
      engine->step();
      const cp::Pose p = engine->bodyPose(cart, 0);
      trace.insert(trace.end(), {p.position.x, p.position.y, p.orientation.z, engine->bodyPose(cube, 0).position.z});
    }
    return trace;
  };
  const std::vector<double> first = run();
  const std::vector<double> second = run();
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) ASSERT_EQ(first[i], second[i]) << "differs at sample " << i;
}

TEST_P(EngineConformance, RaysMeasureDistanceToShapes) {
  auto engine = makeEngine();
  cp::Shape wall;
  wall.type = cp::ShapeType::kBox;
  wall.box_size_m = cp::Vec3(0.1, 6.0, 1.0);  // wide enough for the slanted ray (y = 2.67 at the wall)
  engine->addStaticShape(wall, cp::Pose::fromXyzRpy(2.05, 0, 0.5, 0, 0, 0), cp::SurfaceParams());
  const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  std::vector<cp::RayHit> hits;
  const std::vector<cp::Vec3> origins(4, cp::Vec3(0, 0, 0.1));
  const std::vector<cp::Vec3> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 0, -1}, {0.6, 0.8, 0}};
  engine->castRays(origins, dirs, 10.0, cube, hits);  // ignore the cube the rays start in
  ASSERT_EQ(hits.size(), 4u);
  EXPECT_TRUE(hits[0].hit);
  EXPECT_NEAR(hits[0].distance_m, 2.0, 1e-3);
  EXPECT_FALSE(hits[1].hit);
  EXPECT_DOUBLE_EQ(hits[1].distance_m, 10.0);
  EXPECT_TRUE(hits[2].hit);  // the ground plane
  EXPECT_NEAR(hits[2].distance_m, 0.1, 1e-3);
  EXPECT_TRUE(hits[3].hit);
  EXPECT_NEAR(hits[3].distance_m, 2.0 / 0.6, 1e-3);
  // Without ignoring it, the cube itself is hit first (from inside, at its face or at 0).
  engine->castRays({cp::Vec3(-1, 0, 0.1)}, {cp::Vec3(1, 0, 0)}, 10.0, -1, hits);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0].distance_m, 0.9, 1e-3);
}

TEST_P(EngineConformance, MeshShapesCollide) {
  // A tetrahedron-free check: a closed cube mesh (12 triangles) falls onto the ground.
  auto engine = makeEngine();
  cp::ArticulatedModel m = makeCube();
  m.bodies[0].collisions[0].shape = conde_physics_test::cubeMesh(0.1);
  const cp::ModelId id = engine->addModel(m, cp::Pose::fromXyzRpy(0, 0, 0.5, 0, 0, 0));
  stepFor(*engine, 2.0);
  EXPECT_NEAR(engine->bodyPose(id, 0).position.z, 0.1, 0.01);
}

TEST_P(EngineConformance, RemovedModelLeavesTheWorld) {
  auto engine = makeEngine();
  const cp::ModelId lower = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  const cp::ModelId upper = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.3, 0, 0, 0));
  const cp::ModelId cart = engine->addModel(makeCart(), cp::Pose::fromXyzRpy(2, 0, 0, 0, 0, 0));
  stepFor(*engine, 0.5);
  EXPECT_NEAR(engine->bodyPose(upper, 0).position.z, 0.3, 0.003);  // resting on the lower cube
  engine->removeModel(lower);
  engine->removeModel(cart);  // a model with joints
  EXPECT_THROW(engine->bodyPose(lower, 0), std::out_of_range);
  EXPECT_THROW(engine->jointPosition(cart, 0), std::out_of_range);
  EXPECT_THROW(engine->removeModel(lower), std::out_of_range);
  stepFor(*engine, 1.0);
  EXPECT_NEAR(engine->bodyPose(upper, 0).position.z, 0.1, 0.003);  // fell onto the ground
  std::vector<cp::RayHit> hits;
  engine->castRays({cp::Vec3(2, 0, 1)}, {cp::Vec3(0, 0, -1)}, 10.0, -1, hits);  // where the cart was
  EXPECT_NEAR(hits[0].distance_m, 1.0, 1e-3);                                   // the ground, not the cart
  const cp::ModelId again = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(1, 0, 0.1, 0, 0, 0));
  EXPECT_NE(again, lower);  // ids are not reused
  stepFor(*engine, 0.1);
  EXPECT_NEAR(engine->bodyPose(again, 0).position.x, 1.0, 1e-3);
}

TEST_P(EngineConformance, SetBodyStateTeleportsAndSetsVelocity) {
  auto engine = makeEngine();
  const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  stepFor(*engine, 0.1);
  cp::Twist twist;
  twist.linear_mps = cp::Vec3(0.5, 0, 0);
  twist.angular_radps = cp::Vec3(0, 0, 1.0);
  const cp::Pose target = cp::Pose::fromXyzRpy(3, -1, 1.0, 0, 0, 0.7);
  engine->setBodyState(cube, 0, target, twist);
  EXPECT_NEAR(engine->bodyPose(cube, 0).position.x, 3.0, 1e-9);
  EXPECT_NEAR(engine->bodyPose(cube, 0).orientation.yaw(), 0.7, 1e-9);
  EXPECT_NEAR(engine->bodyTwist(cube, 0).linear_mps.x, 0.5, 1e-9);
  EXPECT_NEAR(engine->bodyTwist(cube, 0).angular_radps.z, 1.0, 1e-9);
  engine->step();
  const cp::Pose after = engine->bodyPose(cube, 0);
  EXPECT_NEAR(after.position.x, 3.0 + 0.5 * engine->settings().step_s, 1e-6);
  EXPECT_LT(after.position.z, 1.0);  // falling
}

TEST_P(EngineConformance, BodyWrenchActsForOneStep) {
  cp::PhysicsSettings zero_g;
  zero_g.gravity_mps2 = cp::Vec3();
  auto engine = makeEngine(zero_g);
  const cp::ModelId cube = engine->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 1.0, 0, 0, 0));
  const double dt = engine->settings().step_s;
  for (int i = 0; i < 100; ++i) {  // 2 N on 1 kg for 0.1 s at the centre: 0.2 m/s, no spin
    engine->addBodyWrench(cube, 0, cp::Vec3(2, 0, 0), cp::Vec3(), engine->bodyPose(cube, 0).position);
    engine->step();
  }
  EXPECT_NEAR(engine->bodyTwist(cube, 0).linear_mps.x, 2.0 * 100 * dt, 1e-6);
  EXPECT_NEAR(engine->bodyTwist(cube, 0).angular_radps.norm(), 0.0, 1e-9);
  engine->step();  // no wrench: velocity kept
  EXPECT_NEAR(engine->bodyTwist(cube, 0).linear_mps.x, 2.0 * 100 * dt, 1e-6);
  const double izz = cp::boxInertia(1.0, {0.2, 0.2, 0.2}).ixx;
  engine->addBodyWrench(cube, 0, cp::Vec3(), cp::Vec3(0, 0, 0.5), engine->bodyPose(cube, 0).position);
  engine->step();
  EXPECT_NEAR(engine->bodyTwist(cube, 0).angular_radps.z, 0.5 / izz * dt, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, EngineConformance, ::testing::Values("ode", "bullet"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(EngineFactory, UnknownNameIsAnError) {
  try {
    cp::createPhysicsEngine("havok", cp::PhysicsSettings());
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown physics engine 'havok' (expected one of: ode, bullet)");
  }
}

}  // namespace
