#include "conde_sim/ackermann_drive.h"

#include <algorithm>
#include <cmath>

#include "conde_sim/drive_odometry.h"
#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

// ------------------------------------------------------------------ odometry

void AckermannOdometry::reset() {
  axle_x_odom_m_ = axle_x_m_;
  axle_y_odom_m_ = axle_y_m_;
  yaw_rad_ = 0.0;
  speed_mps_ = yaw_rate_radps_ = 0.0;
}

void AckermannOdometry::update(double distance_m, double steering_rad, double dt_s) {
  const double dyaw = distance_m * std::tan(steering_rad) / wheelbase_m_;
  // The rear-axle centre moves along the car's heading.
  integrateArc(distance_m, dyaw, axle_x_odom_m_, axle_y_odom_m_, yaw_rad_);
  if (dt_s > 0.0) {
    speed_mps_ = distance_m / dt_s;
    yaw_rate_radps_ = dyaw / dt_s;
  }
}

// Base = axle - R(yaw) * axle_in_base.
double AckermannOdometry::x_m() const {
  return axle_x_odom_m_ - (std::cos(yaw_rad_) * axle_x_m_ - std::sin(yaw_rad_) * axle_y_m_);
}

double AckermannOdometry::y_m() const {
  return axle_y_odom_m_ - (std::sin(yaw_rad_) * axle_x_m_ + std::cos(yaw_rad_) * axle_y_m_);
}

// ------------------------------------------------------------------ geometry from the URDF

namespace {

int jointOrThrow(const Robot& robot, const std::string& key, const std::string& name) {
  const int index = robot.model.jointIndex(name);
  if (index < 0) {
    throw AckermannConfigError(key, "robot '" + robot.spec.name + "' has no movable joint named '" + name + "'");
  }
  return index;
}

// The link frame `base_link` in the model frame (all joints at zero).
cp::Pose baseInModel(const Robot& robot, const std::string& base_link) {
  int body = -1;
  cp::Pose link_in_body;
  if (!robot.model.linkInBody(base_link, body, link_in_body)) {
    throw AckermannConfigError("robotBaseFrame",
                               "robot '" + robot.spec.name + "' has no link named '" + base_link + "'");
  }
  return robot.model.bodies[body].initial_pose_in_model * link_in_body;
}

// Joint frame in the base frame (all joints at zero).
cp::Pose jointInBase(const Robot& robot, const cp::Pose& base_in_model, int joint) {
  const cp::JointSpec& j = robot.model.joints[joint];
  return base_in_model.inverse() * robot.model.bodies[j.parent_body].initial_pose_in_model * j.pose_in_parent;
}

cp::Vec3 axisInBase(const Robot& robot, const cp::Pose& base_in_model, int joint) {
  return jointInBase(robot, base_in_model, joint).orientation.rotate(robot.model.joints[joint].axis.normalized());
}

}  // namespace

AckermannDrive::Config AckermannDrive::Config::placeNamedJoints() {
  Config c;
  c.left_steering_joint = "left_steering_joint";
  c.right_steering_joint = "right_steering_joint";
  c.left_front_wheel_joint = "left_front_wheel_joint";
  c.right_front_wheel_joint = "right_front_wheel_joint";
  c.left_rear_wheel_joint = "left_rear_wheel_joint";
  c.right_rear_wheel_joint = "right_rear_wheel_joint";
  return c;
}

MeasuredCarGeometry measureCarGeometry(const Robot& robot, const std::string& base_link,
                                       const std::string& left_steering_joint, const std::string& right_steering_joint,
                                       const std::string& left_rear_wheel_joint,
                                       const std::string& right_rear_wheel_joint) {
  const cp::Pose base = baseInModel(robot, base_link);
  const int sl = jointOrThrow(robot, "leftSteeringJoint", left_steering_joint);
  const int sr = jointOrThrow(robot, "rightSteeringJoint", right_steering_joint);
  const int rl = jointOrThrow(robot, "leftRearWheelJoint", left_rear_wheel_joint);
  const int rr = jointOrThrow(robot, "rightRearWheelJoint", right_rear_wheel_joint);
  const cp::Vec3 p_sl = jointInBase(robot, base, sl).position, p_sr = jointInBase(robot, base, sr).position;
  const cp::Vec3 p_rl = jointInBase(robot, base, rl).position, p_rr = jointInBase(robot, base, rr).position;
  MeasuredCarGeometry m;
  m.geometry.wheelbase_m = (p_sl.x + p_sr.x) / 2.0 - (p_rl.x + p_rr.x) / 2.0;
  m.geometry.front_half_track_m = (p_sl.y - p_sr.y) / 2.0;
  m.geometry.rear_half_track_m = (p_rl.y - p_rr.y) / 2.0;
  m.axle_x_in_base_m = (p_rl.x + p_rr.x) / 2.0;
  m.axle_y_in_base_m = (p_rl.y + p_rr.y) / 2.0;
  const cp::BodySpec& wheel = robot.model.bodies[robot.model.joints[rl].child_body];
  for (const cp::CollisionSpec& c : wheel.collisions) {
    if (c.shape.type == cp::ShapeType::kCylinder)
      m.geometry.wheel_radius_m = std::max(m.geometry.wheel_radius_m, c.shape.radius_m);
    if (c.shape.type == cp::ShapeType::kSphere)
      m.geometry.wheel_radius_m = std::max(m.geometry.wheel_radius_m, c.shape.radius_m);
  }
  const cp::JointSpec& left = robot.model.joints[sl];
  const cp::JointSpec& right = robot.model.joints[sr];
  m.steering_has_limits = left.has_position_limits && right.has_position_limits &&
                          left.type == cp::JointType::kRevolute && right.type == cp::JointType::kRevolute;
  if (m.steering_has_limits) {
    m.steering_lower_rad = std::max(left.lower, right.lower);
    m.steering_upper_rad = std::min(left.upper, right.upper);
  }
  return m;
}

// ------------------------------------------------------------------ the drive

AckermannDrive::AckermannDrive(Simulation& sim, int robot, const Config& config)
    : sim_(sim), robot_(robot), config_(config), odometry_(1.0, 0.0, 0.0) {
  const Robot& r = sim.robot(robot);
  const MeasuredCarGeometry measured =
      measureCarGeometry(r, config.base_link, config.left_steering_joint, config.right_steering_joint,
                         config.left_rear_wheel_joint, config.right_rear_wheel_joint);
  // Joint directions: steering about +z of the base (left positive), wheels about +y (forward).
  const cp::Pose base = baseInModel(r, config.base_link);
  const char* keys[kJointCount] = {"leftSteeringJoint",    "rightSteeringJoint", "leftFrontWheelJoint",
                                   "rightFrontWheelJoint", "leftRearWheelJoint", "rightRearWheelJoint"};
  const std::string* names[kJointCount] = {&config.left_steering_joint,    &config.right_steering_joint,
                                           &config.left_front_wheel_joint, &config.right_front_wheel_joint,
                                           &config.left_rear_wheel_joint,  &config.right_rear_wheel_joint};
  for (int i = 0; i < kJointCount; ++i) {
    if (names[i]->empty()) continue;
    joints_[i] = jointOrThrow(r, keys[i], *names[i]);
    const cp::Vec3 axis = axisInBase(r, base, joints_[i]);
    const bool steering = i <= kSteerRight;
    const double along = steering ? axis.z : axis.y;
    if (std::abs(along) < 0.99) {
      throw AckermannConfigError(keys[i], "joint '" + *names[i] + "' must turn about the " +
                                              (steering ? "vertical (z)" : "lateral (y)") + " axis of '" +
                                              config.base_link + "'");
    }
    signs_[i] = along > 0 ? 1.0 : -1.0;
  }
  AckermannGeometry& g = config_.geometry;
  if (g.wheelbase_m == 0.0) g.wheelbase_m = measured.geometry.wheelbase_m;
  if (g.front_half_track_m == 0.0) g.front_half_track_m = measured.geometry.front_half_track_m;
  if (g.rear_half_track_m == 0.0) g.rear_half_track_m = measured.geometry.rear_half_track_m;
  if (g.wheel_radius_m == 0.0) g.wheel_radius_m = measured.geometry.wheel_radius_m;
  if (!(g.wheelbase_m > 0.0)) {
    throw AckermannConfigError("wheelbase", "the steering joints must lie ahead of the rear wheel joints in '" +
                                                config.base_link +
                                                "' (wheelbase from the URDF: " + std::to_string(g.wheelbase_m) + " m)");
  }
  if (!(g.front_half_track_m > 0.0)) {
    throw AckermannConfigError("frontTrack", "the left steering joint must lie left of the right one (half track " +
                                                 std::to_string(g.front_half_track_m) + " m)");
  }
  if (!(g.rear_half_track_m > 0.0)) {
    throw AckermannConfigError("rearTrack", "the left rear wheel joint must lie left of the right one (half track " +
                                                std::to_string(g.rear_half_track_m) + " m)");
  }
  if (!(g.wheel_radius_m > 0.0)) {
    throw AckermannConfigError(
        "wheelRadius",
        "the rear wheel link '" +
            r.model.bodies[r.model.joints[r.model.jointIndex(config.left_rear_wheel_joint)].child_body].name +
            "' has no cylinder collision: give <wheelRadius>");
  }
  if (config_.max_steering_angle_rad <= 0.0) {
    if (!measured.steering_has_limits) {
      throw AckermannConfigError("maxSteeringAngle",
                                 "the steering joints have no position limits: give <maxSteeringAngle> [rad]");
    }
    const double inner_limit = std::min(std::abs(measured.steering_lower_rad), std::abs(measured.steering_upper_rad));
    config_.max_steering_angle_rad = maxCentreSteeringAngle(g, inner_limit);
  }
  if (config_.drive_front && (config.left_front_wheel_joint.empty() || config.right_front_wheel_joint.empty())) {
    throw AckermannConfigError("driveWheels",
                               "driving the front wheels needs leftFrontWheelJoint and rightFrontWheelJoint");
  }

  odometry_ = AckermannOdometry(g.wheelbase_m, measured.axle_x_in_base_m, measured.axle_y_in_base_m);
  // Efforts stay within the URDF's effort limits too (as ros_control's joint limits do).
  auto withinJointLimit = [&](PidController::Gains gains, int joint) {
    const double limit = joint >= 0 ? r.model.joints[joint].effort_limit : 0.0;
    if (limit > 0.0 && (gains.output_limit <= 0.0 || gains.output_limit > limit)) gains.output_limit = limit;
    return gains;
  };
  for (int s = 0; s < 2; ++s)
    steering_pid_[s] = PidController(withinJointLimit(config_.steering_pid, joints_[kSteerLeft + s]));
  for (int w = 0; w < 4; ++w)
    wheel_pid_[w] = PidController(withinJointLimit(config_.wheel_pid, joints_[kFrontLeft + w]));
  timer_ = UpdateTimer(config.update_rate_hz, sim.stepS());
  reset();
}

double AckermannDrive::jointPosition(int which) const {
  return signs_[which] * sim_.engine().jointPosition(sim_.robot(robot_).id, joints_[which]);
}

double AckermannDrive::jointVelocity(int which) const {
  return signs_[which] * sim_.engine().jointVelocity(sim_.robot(robot_).id, joints_[which]);
}

double AckermannDrive::rearWheelAngle() const { return (jointPosition(kRearLeft) + jointPosition(kRearRight)) / 2.0; }

FrontWheelAngles AckermannDrive::measuredSteering() const {
  return FrontWheelAngles{jointPosition(kSteerLeft), jointPosition(kSteerRight)};
}

bool AckermannDrive::commandDrive(double speed_mps, double steering_angle_rad, double steering_angle_velocity_radps,
                                  double acceleration_mps2) {
  if (!std::isfinite(speed_mps) || !std::isfinite(steering_angle_rad) ||
      !std::isfinite(steering_angle_velocity_radps) || !std::isfinite(acceleration_mps2)) {
    return false;
  }
  target_speed_mps_ = speed_mps;
  target_steering_rad_ =
      std::clamp(steering_angle_rad, -config_.max_steering_angle_rad, config_.max_steering_angle_rad);
  steering_rate_limit_ = std::abs(steering_angle_velocity_radps);
  acceleration_limit_ = std::abs(acceleration_mps2);
  command_time_s_ = sim_.timeS();
  has_command_ = true;
  return true;
}

bool AckermannDrive::commandTwist(double linear_mps, double yaw_rate_radps) {
  if (!std::isfinite(linear_mps) || !std::isfinite(yaw_rate_radps)) return false;
  const double steering =
      steeringAngleForYawRate(config_.geometry.wheelbase_m, linear_mps, yaw_rate_radps, target_steering_rad_);
  return commandDrive(linear_mps, steering);
}

bool AckermannDrive::timedOut() const {
  return has_command_ && config_.command_timeout_s > 0.0 && sim_.timeS() - command_time_s_ > config_.command_timeout_s;
}

void AckermannDrive::reset() {
  target_speed_mps_ = target_steering_rad_ = 0.0;
  steering_rate_limit_ = acceleration_limit_ = 0.0;
  speed_mps_ = steering_rad_ = 0.0;
  has_command_ = false;
  for (PidController& pid : steering_pid_) pid.reset();
  for (PidController& pid : wheel_pid_) pid.reset();
  odometry_.reset();
  last_rear_angle_rad_ = rearWheelAngle();
  last_steering_rad_ = centreSteeringAngle(config_.geometry, jointPosition(kSteerLeft), jointPosition(kSteerRight));
  start_pose_ = sim_.linkPose(robot_, config_.base_link);
  odom_pose_ = config_.encoder_odometry ? cp::Pose() : start_pose_;
  odom_twist_ = cp::Twist();
  last_update_step_ = sim_.stepCount();
}

void AckermannDrive::beforeStep() {
  const double dt_s = sim_.stepS();
  // After the timeout: brake at once (no acceleration limit) and hold the steering.
  const bool braking = !has_command_ || timedOut();
  speed_mps_ = rateLimited(speed_mps_, braking ? 0.0 : target_speed_mps_, braking ? 0.0 : acceleration_limit_, dt_s);
  steering_rad_ = rateLimited(steering_rad_, target_steering_rad_, steering_rate_limit_, dt_s);

  cp::PhysicsEngine& engine = sim_.engine();
  const cp::ModelId id = sim_.robot(robot_).id;
  const FrontWheelAngles angles = frontWheelAngles(config_.geometry, steering_rad_);
  const double steering_targets[2] = {angles.left_rad, angles.right_rad};
  for (int s = 0; s < 2; ++s) {
    const int which = kSteerLeft + s;
    // The error's rate is minus the hinge's speed (set point at rest): no derivative kick.
    const double effort =
        steering_pid_[s].update(steering_targets[s] - jointPosition(which), -jointVelocity(which), dt_s);
    engine.addJointEffort(id, joints_[which], signs_[which] * effort);
  }
  const WheelSpeeds speeds = wheelSpeeds(config_.geometry, speed_mps_, steering_rad_);
  const double wheel_targets[4] = {speeds.front_left_radps, speeds.front_right_radps, speeds.rear_left_radps,
                                   speeds.rear_right_radps};
  for (int w = 0; w < 4; ++w) {
    const int which = kFrontLeft + w;
    const bool driven = which <= kFrontRight ? config_.drive_front : config_.drive_rear;
    if (!driven || joints_[which] < 0) continue;
    const double effort = wheel_pid_[w].update(wheel_targets[w] - jointVelocity(which), dt_s);
    engine.addJointEffort(id, joints_[which], signs_[which] * effort);
  }
}

bool AckermannDrive::afterStep() {
  const std::uint64_t step = sim_.stepCount();
  if (!timer_.due(step)) return false;
  const double dt_s = static_cast<double>(step - last_update_step_) * sim_.stepS();
  last_update_step_ = step;
  if (config_.encoder_odometry) {
    const double rear_angle_rad = rearWheelAngle();
    const double steering_rad =
        centreSteeringAngle(config_.geometry, jointPosition(kSteerLeft), jointPosition(kSteerRight));
    const double distance_m = (rear_angle_rad - last_rear_angle_rad_) * config_.geometry.wheel_radius_m;
    odometry_.update(distance_m, (steering_rad + last_steering_rad_) / 2.0, dt_s);
    last_rear_angle_rad_ = rear_angle_rad;
    last_steering_rad_ = steering_rad;
    odom_pose_ =
        cp::Pose(cp::Vec3(odometry_.x_m(), odometry_.y_m(), 0.0), cp::Quat::fromRpy(0, 0, odometry_.yaw_rad()));
    odom_twist_.linear_mps = cp::Vec3(odometry_.linear_x_mps(), odometry_.linear_y_mps(), 0.0);
    odom_twist_.angular_radps = cp::Vec3(0.0, 0.0, odometry_.angular_radps());
  } else {
    groundTruthOdometry(sim_, robot_, config_.base_link, odom_pose_, odom_twist_);
  }
  return true;
}

}  // namespace conde_sim
