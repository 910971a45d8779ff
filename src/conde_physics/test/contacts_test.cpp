// PhysicsEngine::lastContacts() on both backends: which pairs touch, where, and how hard.
// Everything is built in-process and stepped; nothing sleeps.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "conde_physics/physics_engine.h"

namespace cp = conde_physics;

namespace {

cp::Shape box(const cp::Vec3& size_m) {
  cp::Shape s;
  s.type = cp::ShapeType::kBox;
  s.box_size_m = size_m;
  return s;
}

// A free cube of 1 kg and 0.2 m, its link frame at its centre.
cp::ArticulatedModel makeCube(const std::string& name = "cube") {
  cp::ArticulatedModel m;
  m.name = name;
  cp::BodySpec body;
  body.name = name;
  body.merged_links = {name};
  body.merged_link_poses = {cp::Pose()};
  body.mass_kg = 1.0;
  cp::Quat axes;
  cp::principalAxes(cp::boxInertia(1.0, {0.2, 0.2, 0.2}), body.principal_inertia_kgm2, axes);
  body.inertial_frame = cp::Pose(cp::Vec3(), axes);
  cp::CollisionSpec c;
  c.shape = box({0.2, 0.2, 0.2});
  body.collisions.push_back(c);
  m.bodies.push_back(body);
  return m;
}

bool involves(const cp::Contact& c, const cp::ContactSide& s) {
  auto same = [](const cp::ContactSide& x, const cp::ContactSide& y) {
    return x.model == y.model && x.body == y.body && x.static_shape == y.static_shape;
  };
  return same(c.a, s) || same(c.b, s);
}

class Contacts : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    engine_ = cp::createPhysicsEngine(GetParam(), cp::PhysicsSettings());
    engine_->addGroundPlane(cp::SurfaceParams());
  }
  void stepFor(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / engine_->settings().step_s));
    for (int i = 0; i < steps; ++i) engine_->step();
  }
  // Contacts between `model` and static shape `shape`, with their total force on the model.
  int contactsWith(cp::ModelId model, int shape, cp::Vec3* force_on_model_N = nullptr) const {
    int n = 0;
    cp::Vec3 total;
    for (const cp::Contact& c : engine_->lastContacts()) {
      const cp::ContactSide obj{-1, -1, shape};
      if (!involves(c, obj)) continue;
      const bool model_is_a = c.a.model == model;
      if (!model_is_a && c.b.model != model) continue;
      ++n;
      const cp::Vec3 f = model_is_a ? c.force_on_a_N : c.force_on_a_N * -1.0;
      total = total + f;
    }
    if (force_on_model_N != nullptr) *force_on_model_N = total;
    return n;
  }
  std::unique_ptr<cp::PhysicsEngine> engine_;
};

TEST_P(Contacts, NoneBeforeTheFirstStep) { EXPECT_TRUE(engine_->lastContacts().empty()); }

TEST_P(Contacts, CubeDroppedOnAStaticBoxTouchesThatBoxOnly) {
  engine_->addStaticShape(box({1, 1, 1}), cp::Pose::fromXyzRpy(5, 5, 0.5, 0, 0, 0), cp::SurfaceParams());    // 0
  engine_->addStaticShape(box({1, 1, 0.2}), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0), cp::SurfaceParams());  // 1
  const cp::ModelId cube = engine_->addModel(makeCube(), cp::Pose::fromXyzRpy(0.1, 0, 0.5, 0, 0, 0));
  engine_->step();
  EXPECT_EQ(contactsWith(cube, 1), 0) << "still falling";
  stepFor(1.5);
  cp::Vec3 force;
  ASSERT_GT(contactsWith(cube, 1, &force), 0);
  EXPECT_EQ(contactsWith(cube, 0), 0) << "the far box";
  for (const cp::Contact& c : engine_->lastContacts()) {
    EXPECT_FALSE(c.a.isGround() || c.b.isGround()) << "the cube rests on the box, not the ground";
    EXPECT_NEAR(c.position_m.z, 0.2, 0.01);
    const double up = c.a.model == cube ? c.normal.z : -c.normal.z;  // pushes the cube up
    EXPECT_GT(up, 0.99);
    EXPECT_GE(c.depth_m, 0.0);
    EXPECT_LT(c.depth_m, 0.01);
    EXPECT_TRUE(c.has_force);
  }
  // At rest the box holds the cube's weight.
  EXPECT_NEAR(force.z, 9.81, 0.5);
  EXPECT_NEAR(force.x, 0.0, 0.2);
}

TEST_P(Contacts, CubeOnCubeNamesBothModels) {
  const cp::ModelId lower = engine_->addModel(makeCube("lower"), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  const cp::ModelId upper = engine_->addModel(makeCube("upper"), cp::Pose::fromXyzRpy(0, 0, 0.4, 0, 0, 0));
  stepFor(1.5);
  int between = 0, lower_on_ground = 0, upper_on_ground = 0;
  for (const cp::Contact& c : engine_->lastContacts()) {
    if ((c.a.model == lower && c.b.model == upper) || (c.a.model == upper && c.b.model == lower)) {
      ++between;
      EXPECT_NEAR(c.position_m.z, 0.2, 0.01);
      EXPECT_EQ(c.a.body, 0);
      EXPECT_EQ(c.b.body, 0);
    }
    if (involves(c, cp::ContactSide{}) && (c.a.model == lower || c.b.model == lower)) ++lower_on_ground;
    if (involves(c, cp::ContactSide{}) && (c.a.model == upper || c.b.model == upper)) ++upper_on_ground;
  }
  EXPECT_GT(between, 0);
  EXPECT_GT(lower_on_ground, 0);
  EXPECT_EQ(upper_on_ground, 0);
}

TEST_P(Contacts, CubePushedIntoAWallTouchesItAndApartItDoesNot) {
  engine_->addStaticShape(box({0.2, 2, 1}), cp::Pose::fromXyzRpy(1.0, 0, 0.5, 0, 0, 0), cp::SurfaceParams());
  const cp::ModelId cube = engine_->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  const int steps_per_s = static_cast<int>(std::lround(1.0 / engine_->settings().step_s));
  for (int i = 0; i < steps_per_s; ++i) {  // 1 s: settles on the ground, well apart
    engine_->step();
    EXPECT_EQ(contactsWith(cube, 0), 0);
  }
  cp::Vec3 force;
  for (int i = 0; i < 3 * steps_per_s; ++i) {  // 3 s pushing +x with 20 N: reaches the wall at x = 0.9
    engine_->addBodyWrench(cube, 0, cp::Vec3(20, 0, 0), cp::Vec3(), engine_->bodyPose(cube, 0).position);
    engine_->step();
  }
  ASSERT_GT(contactsWith(cube, 0, &force), 0);
  EXPECT_LT(force.x, -1.0) << "the wall pushes back";
  for (const cp::Contact& c : engine_->lastContacts()) {
    if (c.a.isGround() || c.b.isGround()) continue;
    EXPECT_NEAR(c.position_m.x, 0.9, 0.01);
  }
}

TEST_P(Contacts, RemovedModelHasNoContacts) {
  const cp::ModelId cube = engine_->addModel(makeCube(), cp::Pose::fromXyzRpy(0, 0, 0.1, 0, 0, 0));
  stepFor(0.5);
  ASSERT_FALSE(engine_->lastContacts().empty());
  engine_->removeModel(cube);
  EXPECT_TRUE(engine_->lastContacts().empty());
  engine_->step();
  EXPECT_TRUE(engine_->lastContacts().empty());
}

INSTANTIATE_TEST_SUITE_P(BothEngines, Contacts, ::testing::Values("ode", "bullet"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
