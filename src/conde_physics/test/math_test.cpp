#include <gtest/gtest.h>

#include "conde_physics/math.h"

namespace cp = conde_physics;

TEST(Math, RpyRoundTrip) {
  const cp::Quat q = cp::Quat::fromRpy(0.3, -0.4, 2.5);
  double r, p, y;
  q.toRpy(r, p, y);
  EXPECT_NEAR(r, 0.3, 1e-12);
  EXPECT_NEAR(p, -0.4, 1e-12);
  EXPECT_NEAR(y, 2.5, 1e-12);
}

TEST(Math, RpyIsFixedAxisRollPitchYaw) {
  // Yaw 90 deg maps x to y; roll 90 deg then maps y to z before the yaw.
  const cp::Vec3 v = cp::Quat::fromRpy(M_PI / 2, 0, M_PI / 2).rotate(cp::Vec3(0, 1, 0));
  EXPECT_NEAR(v.x, 0, 1e-12);
  EXPECT_NEAR(v.y, 0, 1e-12);
  EXPECT_NEAR(v.z, 1, 1e-12);
}

TEST(Math, PoseComposeAndInverse) {
  const cp::Pose a = cp::Pose::fromXyzRpy(1, 2, 3, 0.1, 0.2, 0.3);
  const cp::Pose b = cp::Pose::fromXyzRpy(-0.5, 0.4, 0.0, -0.3, 0.0, 1.0);
  const cp::Pose identity = (a * b) * (a * b).inverse();
  EXPECT_NEAR(identity.position.norm(), 0, 1e-12);
  EXPECT_NEAR(std::abs(identity.orientation.w), 1, 1e-12);
  const cp::Vec3 p = (a * b) * cp::Vec3(1, 0, 0);
  const cp::Vec3 q = a * (b * cp::Vec3(1, 0, 0));
  EXPECT_NEAR((p - q).norm(), 0, 1e-12);
}

TEST(Math, PrincipalAxesDiagonaliseATiltedBox) {
  const cp::Inertia body{1.0, 0, 0, 2.0, 0, 3.0};
  const cp::Quat tilt = cp::Quat::fromRpy(0.3, 0.5, -0.7);
  const cp::Inertia tilted = cp::rotateInertia(body, tilt);
  cp::Vec3 moments;
  cp::Quat axes;
  cp::principalAxes(tilted, moments, axes);
  // Rotating the tilted tensor back into the principal frame gives a diagonal tensor.
  const cp::Inertia back = cp::rotateInertia(tilted, axes.conjugate());
  EXPECT_NEAR(back.ixy, 0, 1e-10);
  EXPECT_NEAR(back.ixz, 0, 1e-10);
  EXPECT_NEAR(back.iyz, 0, 1e-10);
  EXPECT_NEAR(moments.x + moments.y + moments.z, 6.0, 1e-10);
  EXPECT_NEAR(back.ixx, moments.x, 1e-10);
  double m[3][3];
  axes.toMatrix(m);
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  EXPECT_NEAR(det, 1.0, 1e-10);
}

TEST(Math, WrapAngle) {
  EXPECT_NEAR(cp::wrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-12);
  EXPECT_NEAR(cp::wrapAngle(-3 * M_PI / 2), M_PI / 2, 1e-12);
  EXPECT_NEAR(cp::wrapAngle(M_PI), M_PI, 1e-12);
}

TEST(Math, RotationVectorIsAUnitRotationByItsLength) {
  const cp::Quat identity = cp::Quat::fromRotationVector({0, 0, 0});
  EXPECT_EQ(identity.w, 1.0);
  const cp::Quat q = cp::Quat::fromRotationVector({0.03, -0.04, 0.0});  // 0.05 rad about (0.6, -0.8, 0)
  EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0, 1e-15);
  EXPECT_NEAR(2.0 * std::acos(q.w), 0.05, 1e-12);
  const cp::Vec3 axis = q.rotate(cp::Vec3(0.6, -0.8, 0.0));  // the axis stays put
  EXPECT_NEAR(axis.x, 0.6, 1e-12);
  EXPECT_NEAR(axis.y, -0.8, 1e-12);
}
