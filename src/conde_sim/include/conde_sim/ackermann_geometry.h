// Ackermann steering geometry and the small controllers of the Ackermann drive, free of ROS.
//
// Model (as the original Conde/Major Alvega ackermann_controller computes it): a car with wheelbase L between the front
// (steering) axle and the rear axle, steering hinges at +-d_f from the car's centre line, rear wheels at +-d_r. The
// commanded steering angle delta belongs to a virtual wheel at the front-axle centre; the commanded speed v to the
// rear-axle centre. Without slip every wheel rolls on a circle about the instantaneous centre of
// rotation (ICR) on the rear-axle line, at R = L / tan(delta) to the left of the rear-axle centre
// (R < 0: to the right). Then
//   left front angle  = atan(L / (R - d_f)),   right front angle = atan(L / (R + d_f)),
//   yaw rate          = v tan(delta) / L,
//   each wheel's rolling speed = yaw rate * its distance to the ICR.
// The formulas below are written in tan(delta), not R, so they are exact and continuous through
// delta = 0 (straight ahead, R infinite) and for both turning directions and for reversing.
// Assumptions: the steering axis passes through the front wheel's centre (no scrub radius),
// the wheels do not slip, and the car moves in a plane.
#pragma once

namespace conde_sim {

struct AckermannGeometry {
  double wheelbase_m = 0.0;         // L: front axle to rear axle
  double front_half_track_m = 0.0;  // d_f: car centre line to each steering hinge
  double rear_half_track_m = 0.0;   // d_r: car centre line to each rear wheel
  double wheel_radius_m = 0.0;      // rolling radius of every wheel
};

struct FrontWheelAngles {
  double left_rad = 0.0;  // + = towards the left, like delta
  double right_rad = 0.0;
};

struct WheelSpeeds {  // joint speeds [rad/s]; + rolls the car forwards
  double front_left_radps = 0.0, front_right_radps = 0.0;
  double rear_left_radps = 0.0, rear_right_radps = 0.0;
};

// Angles of the two front wheels for a centre steering angle `delta_rad` (|delta| < pi/2).
// The inner wheel turns more. Past |tan delta| = L / d_f the inner wheel would turn beyond 90
// degrees (ICR between the front wheels); the result stays exact (|angle| > pi/2) but no real
// steering reaches it: limit delta with maxCentreSteeringAngle() first.
FrontWheelAngles frontWheelAngles(const AckermannGeometry& g, double delta_rad);

// Centre steering angle [rad] whose inner wheel angle is `max_wheel_angle_rad` (> 0): the
// largest delta a steering whose hinges stop at that angle can follow exactly.
double maxCentreSteeringAngle(const AckermannGeometry& g, double max_wheel_angle_rad);

// Centre steering angle that the measured front wheel angles correspond to (the mean of what
// each wheel says; exact when they follow frontWheelAngles()). For encoder odometry.
double centreSteeringAngle(const AckermannGeometry& g, double left_rad, double right_rad);

// Joint speeds of the four wheels for speed `speed_mps` of the rear-axle centre and steering
// angle `delta_rad` (the rear wheels act as an ideal differential, each front wheel turns on its
// own radius).
WheelSpeeds wheelSpeeds(const AckermannGeometry& g, double speed_mps, double delta_rad);

// Yaw rate [rad/s] of the car at rear-axle speed `speed_mps` and steering angle `delta_rad`.
double yawRate(const AckermannGeometry& g, double speed_mps, double delta_rad);

// Steering angle that gives yaw rate `yaw_rate_radps` at speed `speed_mps`: atan(omega L / v).
// geometry_msgs/Twist commands carry a yaw rate in angular.z (not an angle, which is what
// ros_controllers' ackermann_steering_controller wrongly assumes). Reversing (v < 0) flips the
// sign, so the car still turns the commanded way. A car cannot turn on the spot: for
// |v| < kMinTurningSpeed_mps the yaw rate cannot be realised and `hold_rad` (the current
// steering angle) is returned, so a stop command does not jerk the wheels straight.
constexpr double kMinTurningSpeed_mps = 1e-3;
double steeringAngleForYawRate(double wheelbase_m, double speed_mps, double yaw_rate_radps, double hold_rad);

// Moves `current` towards `target` by at most `max_rate * dt_s`; a max_rate <= 0 means no
// limit (AckermannDrive's convention for steering_angle_velocity and acceleration).
double rateLimited(double current, double target, double max_rate, double dt_s);

// PID controller with the conventions of ros_control's control_toolbox::Pid:
// output = p e + i integral(e dt) + d de/dt, where the integral term i * integral(e dt) is held
// within +-i_clamp (anti-windup; i_clamp 0 = unlimited), and the output within +-output_limit
// (0 = unlimited).
class PidController {
 public:
  struct Gains {
    double p = 0.0, i = 0.0, d = 0.0;
    double i_clamp = 0.0;
    double output_limit = 0.0;
  };

  PidController() = default;
  explicit PidController(const Gains& gains) : gains_(gains) {}

  const Gains& gains() const { return gains_; }
  void setGains(const Gains& gains) { gains_ = gains; }
  // The error's rate is the change of `error` since the previous call (0 on the first call).
  double update(double error, double dt_s);
  // The caller gives the error's rate, e.g. -joint velocity for a position target at rest; this
  // avoids the derivative kick of a step in the target.
  double update(double error, double error_rate, double dt_s);
  void reset();

  double integralTerm() const { return integral_term_; }

 private:
  Gains gains_;
  double integral_term_ = 0.0;  // i * integral(e dt), clamped
  double last_error_ = 0.0;
  bool has_last_error_ = false;
};

}  // namespace conde_sim
