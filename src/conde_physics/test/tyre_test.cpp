// The tyre model both engines give wheels: which cylinders are wheels, and the one contact of a
// rounded tread with a plane.
#include <gtest/gtest.h>

#include <cmath>

#include "conde_physics/tyre.h"
#include "test_models.h"

namespace cp = conde_physics;

namespace {

const cp::Vec3 kUp(0, 0, 1);
constexpr double kRadius = 0.05, kWidth = 0.045;  // the F1/10 test car's wheels [m]

// A chassis with one wheel on a continuous joint about +y at (0.1, 0.12, 0): the cylinder's
// own axis (z) is turned onto the joint axis.
cp::ArticulatedModel oneWheel() {
  cp::ArticulatedModel m;
  cp::BodySpec chassis;
  chassis.name = "chassis";
  cp::BodySpec wheel;
  wheel.name = "wheel";
  const cp::Pose joint_pose(cp::Vec3(0.1, 0.12, 0), cp::Quat());
  wheel.initial_pose_in_model = joint_pose;
  cp::CollisionSpec tyre;
  tyre.shape.type = cp::ShapeType::kCylinder;
  tyre.shape.radius_m = kRadius;
  tyre.shape.length_m = kWidth;
  tyre.pose_in_link = cp::Pose(cp::Vec3(), cp::Quat::fromRpy(-M_PI / 2, 0, 0));
  wheel.collisions.push_back(tyre);
  m.bodies = {chassis, wheel};
  conde_physics_test::addJoint(m, "wheel_joint", cp::JointType::kContinuous, 0, 1, joint_pose);
  return m;
}

TEST(Tyre, ACylinderSpinningOnItsJointIsAWheel) {
  const cp::ArticulatedModel m = oneWheel();
  EXPECT_TRUE(cp::isWheelCollision(m, 1, m.bodies[1].collisions[0]));
}

TEST(Tyre, NotAWheel) {
  cp::ArticulatedModel m = oneWheel();
  const cp::CollisionSpec tyre = m.bodies[1].collisions[0];

  cp::CollisionSpec box = tyre;  // not a cylinder
  box.shape.type = cp::ShapeType::kBox;
  EXPECT_FALSE(cp::isWheelCollision(m, 1, box));

  cp::CollisionSpec upright = tyre;  // cylinder axis across the joint axis (a roller standing up)
  upright.pose_in_link = cp::Pose();
  EXPECT_FALSE(cp::isWheelCollision(m, 1, upright));

  cp::CollisionSpec off_axis = tyre;  // on the joint axis' direction but 2 cm beside it: a cam
  off_axis.pose_in_link.position = cp::Vec3(0.02, 0, 0);
  EXPECT_FALSE(cp::isWheelCollision(m, 1, off_axis));

  EXPECT_FALSE(cp::isWheelCollision(m, 0, tyre));  // the chassis is no joint's child

  m.joints[0].type = cp::JointType::kPrismatic;  // slides instead of spinning
  EXPECT_FALSE(cp::isWheelCollision(m, 1, tyre));
}

TEST(Tyre, OnlyCylindersNarrowerThanTheirDiameterAreRounded) {
  EXPECT_TRUE(cp::canBeTyre(kRadius, kWidth));
  EXPECT_FALSE(cp::canBeTyre(0.05, 0.1));  // a roller as long as it is wide
  EXPECT_FALSE(cp::canBeTyre(0.05, 0.0));
}

TEST(Tyre, UprightWheelTouchesInItsMidPlaneAtTheFullRadius) {
  cp::TyreContact c;
  const cp::Vec3 centre(1.0, 2.0, kRadius - 0.001);  // 1 mm into the ground z = 0
  ASSERT_EQ(cp::tyreOnPlane(centre, cp::Vec3(0, 1, 0), kRadius, kWidth, kUp, 0.0, c), cp::TyreOnPlane::kTouching);
  EXPECT_NEAR(c.depth_m, 0.001, 1e-12);
  EXPECT_NEAR(c.point_m.x, 1.0, 1e-12);
  EXPECT_NEAR(c.point_m.y, 2.0, 1e-12);  // in the mid-plane, not at a rim
  EXPECT_NEAR(c.point_m.z, -0.001, 1e-12);
}

TEST(Tyre, CamberedWheelRollsOntoTheRoundedShoulder) {
  // Leaning by 0.2 rad about x: the lowest point moves towards the lower side, on the rounding
  // of radius width/2 around the rim of the core disk (radius - width/2).
  const double lean = 0.2;
  const cp::Vec3 axis(0, std::cos(lean), std::sin(lean));
  const double core = kRadius - kWidth / 2, rounding = kWidth / 2;
  // Lowest point of the core disk's rim: centre - core * (direction of the normal across the axis).
  const double height_m = core * std::cos(lean) + rounding;  // centre height at which it just touches
  cp::TyreContact c;
  ASSERT_EQ(cp::tyreOnPlane(cp::Vec3(0, 0, height_m - 0.002), axis, kRadius, kWidth, kUp, 0.0, c),
            cp::TyreOnPlane::kTouching);
  EXPECT_NEAR(c.depth_m, 0.002, 1e-12);
  EXPECT_NEAR(c.point_m.x, 0.0, 1e-12);
  EXPECT_NEAR(c.point_m.y, core * std::sin(lean), 1e-12);  // shifted sideways from the centre
  EXPECT_NEAR(c.point_m.z, -0.002, 1e-12);
  // A tilted plane is the same problem: a wheel 3 cm above the plane z = 0.1 x + 0.2 (along its
  // normal) is apart, 1 mm into it touching.
  const cp::Vec3 n = cp::Vec3(-0.1, 0, 1).normalized();
  const double offset_m = 0.2 * n.z;
  const cp::Vec3 on_plane(0.5, 0.0, 0.25);
  const cp::Vec3 axis_on_slope = cp::Vec3(0, 1, 0);
  EXPECT_EQ(cp::tyreOnPlane(on_plane + n * (kRadius + 0.03), axis_on_slope, kRadius, kWidth, n, offset_m, c),
            cp::TyreOnPlane::kApart);
  ASSERT_EQ(cp::tyreOnPlane(on_plane + n * (kRadius - 0.001), axis_on_slope, kRadius, kWidth, n, offset_m, c),
            cp::TyreOnPlane::kTouching);
  EXPECT_NEAR(c.depth_m, 0.001, 1e-12);
  EXPECT_NEAR((c.point_m - (on_plane - n * 0.001)).norm(), 0.0, 1e-12);
}

TEST(Tyre, WheelLyingOnItsSideIsLeftToTheCylinderCollider) {
  cp::TyreContact c;
  EXPECT_EQ(cp::tyreOnPlane(cp::Vec3(0, 0, 0.02), kUp, kRadius, kWidth, kUp, 0.0, c), cp::TyreOnPlane::kOnFace);
  const cp::Vec3 nearly_flat = cp::Vec3(0, std::sin(0.2), std::cos(0.2));  // 11 degrees off the normal
  EXPECT_EQ(cp::tyreOnPlane(cp::Vec3(0, 0, 0.02), nearly_flat, kRadius, kWidth, kUp, 0.0, c), cp::TyreOnPlane::kOnFace);
}

}  // namespace
