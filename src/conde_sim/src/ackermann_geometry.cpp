#include "conde_sim/ackermann_geometry.h"

#include <algorithm>
#include <cmath>

namespace conde_sim {

// With t = tan(delta) and R = L / t:  L / (R -+ d) = L t / (L -+ d t). atan2 keeps the angle
// continuous when the ICR passes the wheel (denominator through zero).
FrontWheelAngles frontWheelAngles(const AckermannGeometry& g, double delta_rad) {
  const double t = std::tan(delta_rad);
  const double l = g.wheelbase_m, d = g.front_half_track_m;
  FrontWheelAngles a;
  a.left_rad = std::atan2(l * t, l - d * t);
  a.right_rad = std::atan2(l * t, l + d * t);
  return a;
}

double maxCentreSteeringAngle(const AckermannGeometry& g, double max_wheel_angle_rad) {
  const double ti = std::tan(max_wheel_angle_rad);
  return std::atan(g.wheelbase_m * ti / (g.wheelbase_m + g.front_half_track_m * ti));
}

double centreSteeringAngle(const AckermannGeometry& g, double left_rad, double right_rad) {
  const double l = g.wheelbase_m, d = g.front_half_track_m;
  const double tl = std::tan(left_rad), tr = std::tan(right_rad);
  // Inverse of tan(left) = L t / (L - d t) and tan(right) = L t / (L + d t).
  const double t_from_left = l * tl / (l + d * tl);
  const double t_from_right = l * tr / (l - d * tr);
  return std::atan((t_from_left + t_from_right) / 2.0);
}

WheelSpeeds wheelSpeeds(const AckermannGeometry& g, double speed_mps, double delta_rad) {
  const double t = std::tan(delta_rad);
  const double k = t / g.wheelbase_m;  // curvature of the rear-axle centre's path [1/m]
  const double v_per_r = speed_mps / g.wheel_radius_m;
  WheelSpeeds w;
  // Distance to the ICR over |R|: rear (R -+ d_r) / R, front sqrt((R -+ d_f)^2 + L^2) / |R|.
  w.rear_left_radps = v_per_r * (1.0 - g.rear_half_track_m * k);
  w.rear_right_radps = v_per_r * (1.0 + g.rear_half_track_m * k);
  w.front_left_radps = v_per_r * std::hypot(1.0 - g.front_half_track_m * k, t);
  w.front_right_radps = v_per_r * std::hypot(1.0 + g.front_half_track_m * k, t);
  return w;
}

double yawRate(const AckermannGeometry& g, double speed_mps, double delta_rad) {
  return speed_mps * std::tan(delta_rad) / g.wheelbase_m;
}

double steeringAngleForYawRate(double wheelbase_m, double speed_mps, double yaw_rate_radps, double hold_rad) {
  if (std::abs(speed_mps) < kMinTurningSpeed_mps) return hold_rad;
  return std::atan(yaw_rate_radps * wheelbase_m / speed_mps);
}

double rateLimited(double current, double target, double max_rate, double dt_s) {
  if (max_rate <= 0.0) return target;
  const double max_change = max_rate * dt_s;
  return current + std::clamp(target - current, -max_change, max_change);
}

double PidController::update(double error, double dt_s) {
  const double rate = has_last_error_ && dt_s > 0.0 ? (error - last_error_) / dt_s : 0.0;
  return update(error, rate, dt_s);
}

double PidController::update(double error, double error_rate, double dt_s) {
  last_error_ = error;
  has_last_error_ = true;
  if (dt_s > 0.0) integral_term_ += gains_.i * error * dt_s;
  if (gains_.i_clamp > 0.0) integral_term_ = std::clamp(integral_term_, -gains_.i_clamp, gains_.i_clamp);
  double out = gains_.p * error + integral_term_ + gains_.d * error_rate;
  if (gains_.output_limit > 0.0) out = std::clamp(out, -gains_.output_limit, gains_.output_limit);
  return out;
}

void PidController::reset() {
  integral_term_ = 0.0;
  last_error_ = 0.0;
  has_last_error_ = false;
}

}  // namespace conde_sim
