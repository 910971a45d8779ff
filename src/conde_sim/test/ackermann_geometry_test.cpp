// Pure Ackermann geometry, rate limits and the PID controller (no simulation).
#include <gtest/gtest.h>

#include <cmath>

#include "conde_sim/ackermann_geometry.h"

using namespace conde_sim;

namespace {

// Major Alvega (the original robot's geometry): L = 0.32 m, d = 0.125 m, r = 0.05 m.
AckermannGeometry alvega() {
  AckermannGeometry g;
  g.wheelbase_m = 0.32;
  g.front_half_track_m = 0.125;
  g.rear_half_track_m = 0.125;
  g.wheel_radius_m = 0.05;
  return g;
}

TEST(AckermannGeometry, StraightAheadAllWheelsParallelAndEqual) {
  const FrontWheelAngles a = frontWheelAngles(alvega(), 0.0);
  EXPECT_EQ(a.left_rad, 0.0);
  EXPECT_EQ(a.right_rad, 0.0);
  const WheelSpeeds w = wheelSpeeds(alvega(), 1.0, 0.0);
  for (double s : {w.front_left_radps, w.front_right_radps, w.rear_left_radps, w.rear_right_radps}) {
    EXPECT_DOUBLE_EQ(s, 20.0);  // 1 m/s / 0.05 m
  }
}

TEST(AckermannGeometry, LeftTurnMatchesTheOriginalControllersFormulas) {
  const AckermannGeometry g = alvega();
  const double delta = 0.3;
  const double r = g.wheelbase_m / std::tan(delta);  // R = L / tan(delta)
  const double d = g.front_half_track_m, l = g.wheelbase_m;
  const FrontWheelAngles a = frontWheelAngles(g, delta);
  EXPECT_NEAR(a.left_rad, std::atan(l / (r - d)), 1e-12);
  EXPECT_NEAR(a.right_rad, std::atan(l / (r + d)), 1e-12);
  EXPECT_GT(a.left_rad, delta);   // inner wheel turns more
  EXPECT_LT(a.right_rad, delta);  // outer wheel less
  EXPECT_GT(a.right_rad, 0.0);
  const double v = 0.8;
  const WheelSpeeds w = wheelSpeeds(g, v, delta);
  const double radius = g.wheel_radius_m;
  EXPECT_NEAR(w.front_left_radps, v * std::sqrt((r - d) * (r - d) + l * l) / (std::abs(r) * radius), 1e-9);
  EXPECT_NEAR(w.front_right_radps, v * std::sqrt((r + d) * (r + d) + l * l) / (std::abs(r) * radius), 1e-9);
  EXPECT_NEAR(w.rear_left_radps, v * (r - d) / (r * radius), 1e-9);
  EXPECT_NEAR(w.rear_right_radps, v * (r + d) / (r * radius), 1e-9);
}

TEST(AckermannGeometry, RightTurnIsTheMirrorImage) {
  const AckermannGeometry g = alvega();
  const FrontWheelAngles left = frontWheelAngles(g, 0.25);
  const FrontWheelAngles right = frontWheelAngles(g, -0.25);
  EXPECT_NEAR(right.left_rad, -left.right_rad, 1e-12);
  EXPECT_NEAR(right.right_rad, -left.left_rad, 1e-12);
  EXPECT_LT(right.right_rad, right.left_rad);  // right wheel is the inner one: more negative
  const WheelSpeeds wl = wheelSpeeds(g, 0.5, 0.25), wr = wheelSpeeds(g, 0.5, -0.25);
  EXPECT_NEAR(wr.rear_left_radps, wl.rear_right_radps, 1e-12);
  EXPECT_NEAR(wr.front_left_radps, wl.front_right_radps, 1e-12);
}

TEST(AckermannGeometry, EveryWheelPointsAtTheInstantCentreOfRotation) {
  const AckermannGeometry g = alvega();
  for (double delta : {-0.6, -0.2, 0.05, 0.4, 0.7}) {
    const double r = g.wheelbase_m / std::tan(delta);
    const FrontWheelAngles a = frontWheelAngles(g, delta);
    // The wheel's normal through its hinge (x = L, y = +-d) meets the rear-axle line at y = R.
    EXPECT_NEAR(g.front_half_track_m + g.wheelbase_m / std::tan(a.left_rad), r, 1e-9) << delta;
    EXPECT_NEAR(-g.front_half_track_m + g.wheelbase_m / std::tan(a.right_rad), r, 1e-9) << delta;
  }
}

TEST(AckermannGeometry, WheelSpeedsAreYawRateTimesDistanceToTheCentre) {
  const AckermannGeometry g = alvega();
  const double v = -0.6, delta = 0.35;  // reversing while turning
  const double r = g.wheelbase_m / std::tan(delta);
  const double omega = yawRate(g, v, delta);
  EXPECT_NEAR(omega, v / r, 1e-12);
  const WheelSpeeds w = wheelSpeeds(g, v, delta);
  const double d = g.front_half_track_m, l = g.wheelbase_m, radius = g.wheel_radius_m;
  EXPECT_NEAR(w.rear_left_radps * radius, omega * (r - d), 1e-9);
  EXPECT_NEAR(w.rear_right_radps * radius, omega * (r + d), 1e-9);
  EXPECT_NEAR(w.front_left_radps * radius, omega * std::hypot(r - d, l), 1e-9);
  EXPECT_NEAR(w.front_right_radps * radius, omega * std::hypot(r + d, l), 1e-9);
  EXPECT_LT(w.rear_left_radps, 0.0);  // reversing: every wheel turns backwards
  EXPECT_LT(w.front_right_radps, 0.0);
}

TEST(AckermannGeometry, CentreAngleRecoveredFromTheWheelAngles) {
  const AckermannGeometry g = alvega();
  for (double delta : {-0.5, -0.1, 0.0, 0.2, 0.55}) {
    const FrontWheelAngles a = frontWheelAngles(g, delta);
    EXPECT_NEAR(centreSteeringAngle(g, a.left_rad, a.right_rad), delta, 1e-12);
  }
}

TEST(AckermannGeometry, MaxCentreAngleKeepsTheInnerWheelAtItsLimit) {
  const AckermannGeometry g = alvega();
  const double limit = 0.785398;  // Major Alvega's hinges: +-45 degrees
  const double delta_max = maxCentreSteeringAngle(g, limit);
  EXPECT_LT(delta_max, limit);
  EXPECT_NEAR(frontWheelAngles(g, delta_max).left_rad, limit, 1e-12);
  EXPECT_NEAR(frontWheelAngles(g, -delta_max).right_rad, -limit, 1e-12);
}

TEST(AckermannGeometry, TwistYawRateBecomesASteeringAngle) {
  const double l = 0.33;
  // 0.5 m/s at 0.6 rad/s: R = v / omega = 0.8333 m, tan(delta) = L / R.
  EXPECT_NEAR(steeringAngleForYawRate(l, 0.5, 0.6, 0.0), std::atan(0.6 * l / 0.5), 1e-12);
  AckermannGeometry g;
  g.wheelbase_m = l;
  EXPECT_NEAR(yawRate(g, 0.5, steeringAngleForYawRate(l, 0.5, 0.6, 0.0)), 0.6, 1e-12);
  // Reversing: same yaw rate needs the opposite steering angle.
  EXPECT_NEAR(steeringAngleForYawRate(l, -0.5, 0.6, 0.0), -std::atan(0.6 * l / 0.5), 1e-12);
  EXPECT_NEAR(yawRate(g, -0.5, steeringAngleForYawRate(l, -0.5, 0.6, 0.0)), 0.6, 1e-12);
  EXPECT_EQ(steeringAngleForYawRate(l, 0.5, 0.0, 0.3), 0.0);  // straight
  // Standing still: no turning on the spot; the current angle is held.
  EXPECT_EQ(steeringAngleForYawRate(l, 0.0, 1.0, 0.3), 0.3);
  EXPECT_EQ(steeringAngleForYawRate(l, 0.5 * kMinTurningSpeed_mps, -1.0, -0.2), -0.2);
}

TEST(RateLimited, StepsTowardsTheTargetAtTheRate) {
  EXPECT_DOUBLE_EQ(rateLimited(0.0, 1.0, 2.0, 0.1), 0.2);
  EXPECT_DOUBLE_EQ(rateLimited(0.0, -1.0, 2.0, 0.1), -0.2);
  EXPECT_DOUBLE_EQ(rateLimited(0.95, 1.0, 2.0, 0.1), 1.0);  // no overshoot
  EXPECT_DOUBLE_EQ(rateLimited(0.0, 1.0, 0.0, 0.1), 1.0);   // 0 = no limit
}

TEST(PidController, ProportionalIntegralDerivative) {
  PidController::Gains g;
  g.p = 2.0;
  g.i = 10.0;
  g.d = 0.5;
  PidController pid(g);
  // First call: no derivative (nothing to difference yet), integral 10 * 1 * 0.1.
  EXPECT_DOUBLE_EQ(pid.update(1.0, 0.1), 2.0 * 1.0 + 1.0);
  // Error 0.5: integral 1 + 10 * 0.5 * 0.1 = 1.5; rate (0.5 - 1) / 0.1 = -5.
  EXPECT_DOUBLE_EQ(pid.update(0.5, 0.1), 2.0 * 0.5 + 1.5 + 0.5 * -5.0);
  // Explicit error rate.
  EXPECT_DOUBLE_EQ(pid.update(0.0, 3.0, 0.1), 1.5 + 0.5 * 3.0);
  pid.reset();
  EXPECT_DOUBLE_EQ(pid.integralTerm(), 0.0);
  EXPECT_DOUBLE_EQ(pid.update(1.0, 0.1), 3.0);  // as after construction
}

TEST(PidController, IntegralClampAndOutputLimit) {
  PidController::Gains g;
  g.p = 1.0;
  g.i = 100.0;
  g.i_clamp = 0.5;
  g.output_limit = 1.2;
  PidController pid(g);
  for (int k = 0; k < 100; ++k) pid.update(1.0, 0.0, 0.01);
  EXPECT_DOUBLE_EQ(pid.integralTerm(), 0.5);          // clamped, not wound up
  EXPECT_DOUBLE_EQ(pid.update(0.5, 0.0, 0.01), 1.0);  // 0.5 + 0.5
  EXPECT_DOUBLE_EQ(pid.update(5.0, 0.0, 0.01), 1.2);  // output limit
  EXPECT_DOUBLE_EQ(pid.update(-50.0, 0.0, 0.01), -1.2);
  // The integral recovers at once from the clamp when the error changes sign.
  EXPECT_LT(pid.integralTerm(), 0.5);
}

}  // namespace
